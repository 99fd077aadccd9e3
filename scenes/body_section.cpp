// The `materials` and `bodies` sections of a scene file (docs/scene-format.md).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/shape.hpp"
#include "engine/scene_check.hpp"
#include "scenes/yaml_reader.hpp"

namespace tumble::scene_yaml {
namespace {

constexpr std::array<std::string_view, 1> kInertiaKeys{"override"};

constexpr std::array<std::string_view, 4> kMaterialKeys{"friction", "restitution", "stiffness",
                                                        "damping"};
constexpr std::array<std::string_view, 14> kBodyKeys{
    "name", "shape",      "position", "orientation", "velocity", "angular_velocity",
    "mass", "density",    "inertia",  "material",    "static",   "kinematic",
    "fast", "train_shape"};
constexpr std::array<std::string_view, 1> kFitKeys{"fit"};

}  // namespace

void Loader::load_materials(const Entry* e, std::vector<Material>& materials) const {
  materials.clear();
  materials.push_back(Material{"default", Real(0.5), 0, 1e6, 1e3});
  if (e == nullptr) {
    return;
  }
  const Fields f =
      read_map(e->value, e->mark(), "materials",
               "a map from material names to {friction, restitution, stiffness, damping}", true);
  for (const Entry& m : f.entries) {
    const std::string path = child("materials", m.key);
    Node key;  // the name as a node, so that it reads like any other value
    key.kind = Node::Kind::scalar;
    key.mark = m.key_mark;
    key.scalar = m.key;
    const Entry name_entry{m.key, m.key_mark, key};
    const std::string name = read_name(name_entry, path, "a material name");
    const Fields props = read_map(m.value, m.mark(), path, "a map {friction, restitution}", false);
    check_known(props, kMaterialKeys);
    Material mat;
    mat.name = name;
    if (const Entry* x = props.find("friction")) {
      mat.friction = read_real(*x, child(path, "friction"), kFriction);
    }
    if (const Entry* x = props.find("restitution")) {
      mat.restitution = read_real(*x, child(path, "restitution"), kRestitution);
    }
    if (const Entry* x = props.find("stiffness")) {
      mat.stiffness = read_real(*x, child(path, "stiffness"), kStiffness);
    }
    if (const Entry* x = props.find("damping")) {
      mat.damping = read_real(*x, child(path, "damping"), kDamping);
    }
    // `default` keeps slot 0 so that a body without a material needs no lookup.
    if (name == "default") {
      materials[0] = mat;
    } else {
      materials.push_back(mat);
    }
  }
}

// A training shape (docs/scene-format.md, "train_shape"): {fit: box | sphere | capsule | hull}
// around the detailed shape, or a shape of its own. A primitive is centred on the body's centre
// of mass; a hull's points and a compound's parts are in the frame of the detailed shape's own
// points (which the centre of mass is measured from), so they are moved into the body's frame.
Shape Loader::load_train_shape(const Entry& e, const std::string& path, const Shape& detailed,
                               const Vec3& centre_of_mass) const {
  const Fields f = read_map(e.value, e.mark(), path,
                            "a shape map, or {fit: box | sphere | capsule | hull}", false);
  if (const Entry* fit = f.find("fit")) {
    check_known(f, kFitKeys);
    const std::string kind =
        read_word(*fit, child(path, "fit"), "a fit (box, sphere, capsule, hull)");
    ShapeFit which = ShapeFit::box;
    if (kind == "sphere")
      which = ShapeFit::sphere;
    else if (kind == "capsule")
      which = ShapeFit::capsule;
    else if (kind == "hull")
      which = ShapeFit::hull;
    else if (kind != "box")
      fail(fit->mark(), child(path, "fit"),
           "expected one of: box, sphere, capsule, hull, got " + describe(fit->value));
    if (!detailed.is_bounded())
      fail(fit->mark(), child(path, "fit"), "a plane is unbounded: nothing to fit around");
    return fit_shape(detailed, which);
  }
  Vec3 own_centre = Vec3::Zero();
  Shape shape = load_shape(e, path, &own_centre);
  // From the shape's own centre of mass (where load_shape centred it) to the body's.
  const Vec3 shift = own_centre - centre_of_mass;
  if (shape.type == ShapeType::hull) {
    std::vector<Vec3> points(shape.hull->vertices().begin(), shape.hull->vertices().end());
    for (Vec3& p : points)
      p += shift;
    return hull_in_frame(points);
  }
  if (shape.type == ShapeType::compound) {
    std::vector<CompoundPart> parts = shape.compound->parts();
    for (CompoundPart& p : parts)
      p.pose.translation += shift;
    return compound_in_frame(std::move(parts));
  }
  return shape;
}

BodyDesc Loader::load_body(const Node& node, const YAML::Mark& mark, std::size_t i,
                           const MaterialIndex& materials,
                           std::optional<YAML::Mark>& name_mark) const {
  const std::string path = index("bodies", i);
  const Fields f = read_map(node, mark, path, "a map describing a body", false);
  check_known(f, kBodyKeys);
  const auto at = [&](std::string_view key) { return child(path, key); };
  BodyDesc b;
  if (const Entry* x = f.find("name")) {
    b.name = read_name(*x, at("name"), "a body name");
    name_mark = x->mark();
  } else {
    b.name = "body" + std::to_string(i);
    name_mark.reset();
  }

  const Entry* shape = f.find("shape");
  if (shape == nullptr) {
    fail(f.mark, at("shape"),
         "missing required field 'shape', such as {type: sphere, radius: 0.5}");
  }
  Vec3 centre_of_mass = Vec3::Zero();
  b.shape = load_shape(*shape, at("shape"), &centre_of_mass);

  const Entry* is_static = f.find("static");
  if (is_static != nullptr) {
    b.is_static = read_bool(*is_static, at("static"));
  }
  const Entry* kinematic = f.find("kinematic");
  if (kinematic != nullptr) {
    b.kinematic = read_bool(*kinematic, at("kinematic"));
    if (b.kinematic && b.is_static)
      fail(kinematic->mark(), at("kinematic"),
           "a body is static or kinematic, not both; remove one of them");
    if (b.kinematic && (!b.shape.is_bounded() || b.shape.type == ShapeType::mesh))
      fail(kinematic->mark(), at("kinematic"),
           std::string("a ") + (b.shape.is_bounded() ? "triangle mesh" : "plane") +
               " can only be static");
  }
  if (const Entry* x = f.find("fast")) {
    b.fast = read_bool(*x, at("fast"));
  }
  if (const Entry* x = f.find("train_shape")) {
    b.train_shape = load_train_shape(*x, at("train_shape"), b.shape, centre_of_mass);
  }
  if (!b.shape.is_bounded() && !b.is_static) {
    const YAML::Mark where = is_static != nullptr ? is_static->mark() : shape->mark();
    fail(where, at("static"),
         "a plane is infinite, so it has no finite mass and must be static; add 'static: true'");
  }
  if (b.shape.type == ShapeType::sdf && b.shape.sdf->changes_with_time() && !b.is_static &&
      !b.kinematic)
    fail(shape->mark(), at("shape"),
         "a field that changes with time (a morph) is an obstacle: its body must be static or "
         "kinematic (its mass would change with it); add 'static: true' or 'kinematic: true'");
  if (b.shape.type == ShapeType::mesh && !b.is_static) {
    const YAML::Mark where = is_static != nullptr ? is_static->mark() : shape->mark();
    fail(where, at("static"),
         "a triangle mesh is a surface without a solid inside for collision, so it must be "
         "static; add 'static: true' (use a compound of boxes, spheres or capsules for a moving "
         "body)");
  }

  if (const Entry* x = f.find("position")) {
    b.position = read_vector<3>(*x, at("position"), "[x, y, z]", "metres", kCoordinate);
  }
  if (const Entry* x = f.find("orientation")) {
    const Eigen::Matrix<Real, 4, 1> q =
        read_vector<4>(*x, at("orientation"), "[w, x, y, z]", "", kQuatComponent);
    const Real norm = q.norm();
    // A quaternion typed by hand with few digits is caught here rather than silently
    // renormalised, since a wrong component usually means a wrong rotation, not rounding.
    if (!(std::abs(norm - 1) <= kQuatTolerance)) {
      fail(
          x->mark(), at("orientation"),
          "expected a unit quaternion [w, x, y, z] (norm within 1e-6 of 1), got norm " + fmt(norm));
    }
    b.orientation = Quat(q[0], q[1], q[2], q[3]);
    b.orientation.normalize();
  }
  // Hulls and compounds are re-centred at their centre of mass: move the body there so the
  // shape stays where the scene put it.
  b.position += b.orientation * centre_of_mass;
  const auto check_still = [&](const Entry& x, const Vec3& v, std::string_view what) {
    if (b.is_static && !v.isZero(0)) {
      fail(x.mark(), at(x.key),
           "a static body never moves, so its " + std::string(what) +
               " must be zero or absent, got [" + fmt(v.x()) + ", " + fmt(v.y()) + ", " +
               fmt(v.z()) + "]");
    }
  };
  if (const Entry* x = f.find("velocity")) {
    b.velocity = read_vector<3>(*x, at("velocity"), "[x, y, z]", "m/s", kVelocity);
    check_still(*x, b.velocity, "velocity");
  }
  if (const Entry* x = f.find("angular_velocity")) {
    b.angular_velocity =
        read_vector<3>(*x, at("angular_velocity"), "[x, y, z]", "rad/s", kAngularVelocity);
    check_still(*x, b.angular_velocity, "angular velocity");
  }

  const Entry* mass = f.find("mass");
  const Entry* density = f.find("density");
  const Entry* inertia = f.find("inertia");
  if (b.is_static || b.kinematic) {
    for (const Entry* x : {mass, density, inertia}) {
      if (x != nullptr) {
        fail(x->key_mark, at(x->key),
             std::string(b.is_static ? "static" : "kinematic") +
                 " bodies have no mass (it is infinite); remove '" + x->key + "' or set '" +
                 (b.is_static ? "static" : "kinematic") + ": false'");
      }
    }
  } else {
    if (mass != nullptr && density != nullptr) {
      fail(density->key_mark, at("density"),
           "give either mass or density, not both (mass is on line " +
               std::to_string(mass->key_mark.line + 1) + ")");
    }
    if (mass == nullptr && density == nullptr && b.shape.type == ShapeType::sdf) {
      // A field's volume is integrated over its cells (docs/sdf.md): a
      // default density would hide a mass that depends on the field's resolution.
      fail(shape->key_mark, at("shape"),
           "a moving body of type sdf needs 'mass' or 'density' (a field's mass is not assumed)");
    }
    if (mass != nullptr) {
      b.mass = read_real(*mass, at("mass"), kMass);
    } else {
      const Real rho =
          density != nullptr ? read_real(*density, at("density"), kDensity) : kDefaultDensity;
      b.mass = rho * volume(b.shape);
      // Sizes and density are each bounded, but their product can still leave the mass range.
      if (!(b.mass >= kMinMass && b.mass <= kMaxMass)) {
        const Entry* culprit = density != nullptr ? density : shape;
        fail(culprit->mark(), at(culprit->key),
             "density " + fmt(rho) + " kg/m^3 times the shape's volume " + fmt(volume(b.shape)) +
                 " m^3 gives a mass of " + fmt(b.mass) +
                 " kg; expected a mass of 1e-12 to 1e15 kg");
      }
    }
    if (inertia != nullptr) {
      // [Ixx, Iyy, Izz], checked for plausibility against the shape below, or {override: [...]}
      // for a mass distribution the file means to be unusual.
      const Entry* moments = inertia;
      std::string moments_path = at("inertia");
      bool override_shape = false;
      std::optional<Fields> wrapper;
      if (inertia->value.is_map()) {
        wrapper.emplace(read_map(inertia->value, inertia->mark(), at("inertia"),
                                 "[Ixx, Iyy, Izz] or {override: [Ixx, Iyy, Izz]}", false));
        check_known(*wrapper, kInertiaKeys);
        moments = wrapper->find("override");
        if (moments == nullptr)
          fail(wrapper->mark, child(at("inertia"), "override"),
               "missing required field 'override' ([Ixx, Iyy, Izz] in kg m^2)");
        moments_path = child(at("inertia"), "override");
        override_shape = true;
      }
      const Vec3 m = read_vector<3>(*moments, moments_path, "[Ixx, Iyy, Izz]", "kg m^2", kMoment);
      // Principal moments of any real mass distribution obey the triangle inequality; a
      // tensor that does not is unphysical and makes the solver gain energy.
      const Real tol = 1e-9 * m.sum();
      if (m.x() > m.y() + m.z() + tol || m.y() > m.x() + m.z() + tol ||
          m.z() > m.x() + m.y() + tol) {
        fail(moments->mark(), moments_path,
             "principal moments must satisfy the triangle inequality (each at most the sum of "
             "the other two), got [" +
                 fmt(m.x()) + ", " + fmt(m.y()) + ", " + fmt(m.z()) + "]");
      }
      // Plausibility: a hundredth of the shape's own moments (uniform density) would need almost
      // all the mass at the centre; a 1 kg unit box given 1e-6 kg m^2 turned through its floor.
      // Files that mean it say so with {override: ...}. The upper limit, m R^2, is physics and
      // is checked for every scene (engine/scene_check.cpp).
      const std::string impossible =
          impossible_moment(b.mass, m.maxCoeff(), bounding_radius(b.shape));
      if (!impossible.empty())
        fail(moments->mark(), moments_path, impossible);
      const Real own = b.mass * unit_inertia(b.shape).trace();
      if (!override_shape && m.sum() < own / 100) {
        std::string reason = "principal moments [";
        reason += fmt(m.x());
        reason += ", ";
        reason += fmt(m.y());
        reason += ", ";
        reason += fmt(m.z());
        reason +=
            "] are less than a hundredth of what this shape of uniform density has (their sum ";
        reason += fmt(own);
        reason +=
            " kg m^2); write inertia: {override: [...]} if the mass is meant to sit at the centre";
        fail(moments->mark(), moments_path, reason);
      }
      b.inertia = m.asDiagonal();
    } else {
      b.inertia = b.mass * unit_inertia(b.shape);
    }
  }

  if (const Entry* x = f.find("material")) {
    const std::string name = read_word(*x, at("material"), "a material name");
    const auto found = materials.index.find(name);
    if (found == materials.index.end()) {
      std::string defined;
      for (const Material& m : materials.list) {
        defined += (defined.empty() ? "" : ", ") + m.name;
      }
      fail(x->mark(), at("material"),
           "undefined material '" + printable(name) + "'; defined: " + defined);
    }
    b.material = found->second;
  }
  return b;
}

void Loader::load_bodies(const Fields& top, Scene& scene) const {
  const Entry* e = top.find("bodies");
  if (e == nullptr) {
    fail(top.mark, "bodies", "missing required field 'bodies' (a list of at least one body)");
  }
  const Node& list = e->value;
  if (!list.is_sequence() || list.size() == 0) {
    fail(e->mark(), "bodies", "expected a non-empty list of bodies, got " + describe(list));
  }
  if (list.size() > kMaxBodies) {
    fail(e->mark(), "bodies",
         "expected at most 1000000 bodies, got " + std::to_string(list.size()));
  }
  struct NameUse {
    std::size_t body;
    bool is_default;
  };
  std::unordered_map<std::string, NameUse> names;
  const MaterialIndex materials(scene.materials);
  scene.bodies.reserve(list.size());
  for (std::size_t i = 0; i < list.items.size(); ++i) {
    const Node& node = *list.items[i];
    const YAML::Mark mark = mark_or(node, e->mark());
    std::optional<YAML::Mark> name_mark;
    BodyDesc body = load_body(node, mark, i, materials, name_mark);
    const auto [used, inserted] = names.try_emplace(body.name, NameUse{i, !name_mark});
    if (!inserted) {
      const std::string other = "bodies[" + std::to_string(used->second.body) + "]";
      const std::string path = child(index("bodies", i), "name");
      if (!name_mark) {
        fail(mark, path,
             "the default name '" + body.name + "' is already used by " + other +
                 "; give this body a name");
      }
      fail(*name_mark, path,
           "duplicate body name '" + printable(body.name) + "', already used by " + other +
               (used->second.is_default ? " (its default name)" : ""));
    }
    scene.bodies.push_back(std::move(body));
  }
}

}  // namespace tumble::scene_yaml
