// The compiled model of a scene (include/tumble/model.hpp): everything a world derives from the
// scene once, shared by every world of it. Built by compile() after check_scene(); a world that
// adds or removes bodies makes its own model (with_body, without_body) and leaves the shared one.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "dynamics/rigid_body.hpp"
#include "tumble/model.hpp"
#include "tumble/scene.hpp"

namespace tumble {

// How a body moves. Static and kinematic bodies (and empty slots) have infinite mass: the solver
// never changes their velocity, and they join no island.
enum class Motion : std::uint8_t { dynamic, static_body, kinematic, removed };

class Model {
 public:
  // The model of a scene that passed check_scene (compile() checks; this does not).
  static std::shared_ptr<const Model> build(std::shared_ptr<const Scene> scene);
  // build()'s work done over this model, keeping its tables' storage (a model that nothing else
  // holds, rebuilt for a new draw of its scene: engine/draw_storage.hpp).
  // `drawn_from`: the checked scene `scene` is a randomized draw of, if it is one.
  void assign(std::shared_ptr<const Scene> scene, std::shared_ptr<const Scene> drawn_from = {});
  // Lets go of the scenes (so that their holder may write over them before the next assign).
  void release_scenes();

  const Scene& scene() const { return *scene_; }
  // The scene as described, before training geometry replaced any shape: what a randomized
  // world is drawn from (tumble/randomization.hpp), so that both geometries draw alike.
  const Scene& described_scene() const { return *described_; }
  const std::shared_ptr<const Scene>& scene_pointer() const { return scene_; }
  const std::shared_ptr<const Scene>& described_pointer() const { return described_; }
  // Whether both models are randomized draws (DrawStorage's models) of one scene. Two such draws
  // have the same bodies, each static, kinematic or moving alike, and the same static bodies:
  // draws leave static bodies as they are.
  bool drawn_from_same_scene(const Model& other) const {
    return drawn_from_ != nullptr && drawn_from_ == other.drawn_from_;
  }
  std::size_t body_count() const { return masses_.size(); }

  const std::vector<BodyMass>& masses() const { return masses_; }
  const std::vector<Real>& bounding_radii() const { return bounding_radii_; }
  // Contact points on a curved surface (sphere, capsule, cylinder; compounds may have them) slide
  // over it as the body turns, so a point carried rigidly with the body would lag: only pairs of
  // flat-faced shapes recycle their manifolds.
  const std::vector<std::uint8_t>& flat_shape() const { return flat_shape_; }
  // Each body's shape type, whether its shape is bounded, and its material: the descriptions'
  // fields in tables of their own, for the stages that read them per pair per step (a batch's
  // worlds missed the cache on each body's large description).
  ShapeType shape_type(std::size_t body) const { return shape_type_[body]; }
  bool is_bounded(std::size_t body) const { return bounded_[body] != 0; }
  int material(std::size_t body) const { return material_[body]; }
  Motion motion(std::size_t body) const { return motion_[body]; }
  const std::vector<Motion>& motions() const { return motion_; }
  // Static, kinematic or removed: infinite mass, in no island, never integrated by the solver.
  bool is_fixed(std::size_t body) const { return motion_[body] != Motion::dynamic; }
  bool is_kinematic(std::size_t body) const { return motion_[body] == Motion::kinematic; }
  // The description's `is_static` (a removed slot keeps a static description), from this compact
  // table: a batch of worlds reads it per body per step, and the descriptions are large.
  bool is_static(std::size_t body) const {
    return motion_[body] == Motion::static_body || motion_[body] == Motion::removed;
  }
  bool is_removed(std::size_t body) const { return motion_[body] == Motion::removed; }
  bool has_kinematic() const { return kinematic_count_ > 0; }
  // One flag per body, 1 for kinematic (the contact solver's view).
  const std::vector<std::uint8_t>& kinematic_flags() const { return kinematic_; }
  // Slots that hold no body (removed, free for the next add).
  std::size_t removed_count() const;

  // The combined friction and restitution of two materials, by the scene's rules (computed once
  // per pair of materials).
  Real friction(int material_a, int material_b) const {
    return friction_[std::size_t(material_a) * material_count_ + std::size_t(material_b)];
  }
  Real restitution(int material_a, int material_b) const {
    return restitution_[std::size_t(material_a) * material_count_ + std::size_t(material_b)];
  }

  // A copy with `desc` in slot `slot` (an empty one, or the end), and one with slot `slot`
  // emptied. Neither checks `desc`; the caller does.
  std::shared_ptr<const Model> with_body(const BodyDesc& desc, std::size_t slot) const;
  std::shared_ptr<const Model> without_body(std::size_t slot) const;

 private:
  void derive();

  std::shared_ptr<const Scene> scene_;
  std::shared_ptr<const Scene> described_;
  std::shared_ptr<const Scene> drawn_from_;
  std::vector<BodyMass> masses_;
  std::vector<Real> bounding_radii_;
  std::vector<std::uint8_t> flat_shape_;
  std::vector<ShapeType> shape_type_;
  std::vector<std::uint8_t> bounded_;
  std::vector<std::int32_t> material_;
  std::vector<Motion> motion_;
  std::vector<std::uint8_t> kinematic_;
  std::vector<std::uint8_t> removed_;  // per slot, 1 = removed (may be shorter: the rest are 0)
  int kinematic_count_ = 0;
  std::size_t material_count_ = 0;
  std::vector<Real> friction_;
  std::vector<Real> restitution_;
};

}  // namespace tumble
