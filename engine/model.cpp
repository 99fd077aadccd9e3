#include "engine/model.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "collision/shapes/shape.hpp"
#include "engine/number_text.hpp"
#include "tumble/error.hpp"

namespace tumble {

Real default_friction_mixing(const Material& a, const Material& b) {
  return std::sqrt(a.friction * b.friction);
}

Real default_restitution_mixing(const Material& a, const Material& b) {
  return a.restitution > b.restitution ? a.restitution : b.restitution;
}

const Scene& scene_of(const Model& model) {
  return model.scene();
}

std::shared_ptr<const Model> compile(std::shared_ptr<const Scene> scene) {
  if (!scene)
    throw Error("tumble::compile: the scene is null");
  check_scene(*scene);
  return Model::build(std::move(scene));
}

std::shared_ptr<const Model> Model::build(std::shared_ptr<const Scene> scene) {
  auto model = std::make_shared<Model>();
  model->assign(std::move(scene));
  return model;
}

void Model::release_scenes() {
  scene_.reset();
  described_.reset();
  drawn_from_.reset();
}

void Model::assign(std::shared_ptr<const Scene> scene, std::shared_ptr<const Scene> drawn_from) {
  removed_.clear();
  drawn_from_ = std::move(drawn_from);
  described_ = scene;
  // Training geometry: each body with a training shape collides with it (its mass properties
  // stay those of its detailed shape, already in the description).
  if (scene->world.geometry == Geometry::train &&
      std::any_of(scene->bodies.begin(), scene->bodies.end(),
                  [](const BodyDesc& b) { return b.train_shape.has_value(); })) {
    auto trained = std::make_shared<Scene>(*scene);
    for (BodyDesc& b : trained->bodies)
      if (b.train_shape)
        b.shape = *std::exchange(b.train_shape, std::nullopt);
    scene = std::move(trained);
  }
  if (scene->materials.empty()) {
    auto with_default = std::make_shared<Scene>(*scene);
    with_default->materials.push_back(Material{"default"});
    scene = std::move(with_default);
  }
  scene_ = std::move(scene);
  derive();
}

void Model::derive() {
  const Scene& s = *scene_;
  const std::size_t n = s.bodies.size();
  masses_.clear();
  bounding_radii_.clear();
  flat_shape_.clear();
  shape_type_.clear();
  bounded_.clear();
  material_.clear();
  motion_.clear();
  kinematic_.clear();
  masses_.reserve(n);
  bounding_radii_.reserve(n);
  flat_shape_.reserve(n);
  motion_.reserve(n);
  kinematic_count_ = 0;
  for (const BodyDesc& d : s.bodies) {
    const bool removed = removed_.size() > masses_.size() && removed_[masses_.size()] != 0;
    const Motion m = removed       ? Motion::removed
                     : d.is_static ? Motion::static_body
                     : d.kinematic ? Motion::kinematic
                                   : Motion::dynamic;
    motion_.push_back(m);
    kinematic_.push_back(m == Motion::kinematic ? 1 : 0);
    kinematic_count_ += m == Motion::kinematic ? 1 : 0;
    masses_.push_back(BodyMass::make(d.mass, d.inertia, m != Motion::dynamic));
    bounding_radii_.push_back(d.shape.is_bounded() ? bounding_radius(d.shape) : Real(0));
    const ShapeType t = d.shape.type;
    flat_shape_.push_back(t == ShapeType::box || t == ShapeType::plane || t == ShapeType::hull ||
                          t == ShapeType::mesh);
    shape_type_.push_back(t);
    bounded_.push_back(d.shape.is_bounded() ? 1 : 0);
    material_.push_back(static_cast<std::int32_t>(d.material));
  }
  material_count_ = s.materials.size();
  friction_.resize(material_count_ * material_count_);
  restitution_.resize(material_count_ * material_count_);
  for (std::size_t a = 0; a < material_count_; ++a) {
    for (std::size_t b = 0; b < material_count_; ++b) {
      const Material& ma = s.materials[a];
      const Material& mb = s.materials[b];
      const Real mu =
          s.friction_mixing ? s.friction_mixing(ma, mb) : default_friction_mixing(ma, mb);
      const Real e =
          s.restitution_mixing ? s.restitution_mixing(ma, mb) : default_restitution_mixing(ma, mb);
      // A user's rule is checked like a material: the solver assumes these ranges.
      if (!(mu >= 0 && mu <= 100))
        throw SceneError(s.source, 0, 0, "friction_mixing",
                         "the rule gave " + number_text(mu) + " for materials '" + ma.name +
                             "' and '" + mb.name + "'; expected 0 to 100");
      if (!(e >= 0 && e <= 1))
        throw SceneError(s.source, 0, 0, "restitution_mixing",
                         "the rule gave " + number_text(e) + " for materials '" + ma.name +
                             "' and '" + mb.name + "'; expected 0 to 1");
      friction_[a * material_count_ + b] = mu;
      restitution_[a * material_count_ + b] = e;
    }
  }
}

std::size_t Model::removed_count() const {
  std::size_t count = 0;
  for (const Motion m : motion_)
    count += m == Motion::removed ? 1 : 0;
  return count;
}

std::shared_ptr<const Model> Model::with_body(const BodyDesc& desc, std::size_t slot) const {
  auto scene = std::make_shared<Scene>(*scene_);
  auto model = std::make_shared<Model>();
  model->removed_ = removed_;
  model->removed_.resize(scene->bodies.size(), 0);
  BodyDesc placed = desc;
  if (scene->world.geometry == Geometry::train && placed.train_shape)
    placed.shape = *std::exchange(placed.train_shape, std::nullopt);
  if (slot < scene->bodies.size()) {
    scene->bodies[slot] = placed;
    model->removed_[slot] = 0;
  } else {
    scene->bodies.push_back(placed);
    model->removed_.push_back(0);
  }
  model->scene_ = std::move(scene);
  // Bodies added one by one are described by the running scene itself.
  model->described_ = model->scene_;
  model->derive();
  return model;
}

std::shared_ptr<const Model> Model::without_body(std::size_t slot) const {
  // The slot keeps a static, nameless copy of the body (so the scene's lists keep their length and
  // order); the model marks it removed, and the world keeps it out of everything.
  auto scene = std::make_shared<Scene>(*scene_);
  BodyDesc& d = scene->bodies[slot];
  d.name.clear();
  d.is_static = true;
  d.kinematic = false;
  d.mass = 0;
  d.inertia.setZero();
  d.velocity.setZero();
  d.angular_velocity.setZero();
  auto model = std::make_shared<Model>();
  model->removed_ = removed_;
  model->removed_.resize(scene->bodies.size(), 0);
  model->removed_[slot] = 1;
  model->scene_ = std::move(scene);
  model->described_ = model->scene_;
  model->derive();
  return model;
}

}  // namespace tumble
