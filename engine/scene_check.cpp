// check_scene (include/tumble/model.hpp): every field of a Scene against the ranges of
// engine/scene_limits.hpp, the same table the YAML loader reads with, so that a scene built in
// code gets the message a file with the same value gets (without a line: there is none).
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <unordered_set>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/shape.hpp"
#include "engine/number_text.hpp"
#include "engine/scene_check.hpp"
#include "engine/scene_limits.hpp"
#include "tumble/error.hpp"
#include "tumble/model.hpp"

namespace tumble {
namespace {

using namespace scene_limits;

// A field's name ("bodies[3].shape.half_extents[0]"), put together only when a check fails: a
// valid scene, checked again at every randomized reset of a batch's world, built thousands of
// strings for names nobody read. A Field refers to its parent, so it lives no longer than the
// call it is made for.
class Field {
 public:
  Field(const char* root) : member_(root) {}
  Field(const Field& parent, const char* member) : parent_(&parent), member_(member) {}
  Field(const Field& parent, std::size_t index) : parent_(&parent), index_(index) {}

  std::string text() const {
    std::string out = parent_ != nullptr ? parent_->text() : std::string();
    if (member_ != nullptr)
      out += member_;
    if (index_ != kNoIndex) {
      out += '[';
      out += std::to_string(index_);
      out += ']';
    }
    return out;
  }

 private:
  static constexpr std::size_t kNoIndex = static_cast<std::size_t>(-1);
  const Field* parent_ = nullptr;
  const char* member_ = nullptr;
  std::size_t index_ = kNoIndex;
};

class Checker {
 public:
  explicit Checker(const Scene& scene) : scene_(scene) {}

  [[noreturn]] void fail(const Field& field, const std::string& reason) const {
    throw SceneError(scene_.source.empty() ? std::string("scene") : scene_.source, 0, 0,
                     field.text(), reason);
  }

  // The test inline, the message out of line: a scene checks thousands of numbers and fails on
  // at most one (a batch checks every randomized draw).
  void real(Real v, const RealSpec& spec, const Field& field) const {
    const bool above = spec.lo_open ? v > spec.lo : v >= spec.lo;
    if (std::isfinite(v) && above && v <= spec.hi) [[likely]]
      return;
    real_failed(v, spec, field);
  }
  [[noreturn, gnu::cold, gnu::noinline]] void real_failed(Real v, const RealSpec& spec,
                                                          const Field& field) const {
    std::string reason = "expected " + std::string(spec.what);
    if (!spec.range.empty())
      reason += " (" + std::string(spec.range) + ")";
    fail(field, reason + ", got " + number_text(v));
  }

  void integer(std::int64_t v, const IntSpec& spec, const Field& field) const {
    if (v >= spec.lo && v <= spec.hi)
      return;
    fail(field, "expected " + std::string(spec.what) + " (" + std::string(spec.range) + "), got " +
                    std::to_string(v));
  }

  void vector(const Vec3& v, const RealSpec& spec, const Field& field) const {
    for (int k = 0; k < 3; ++k)
      real(v[k], spec, Field(field, std::size_t(k)));
  }

  void orientation(const Quat& q, const Field& field) const {
    for (int k = 0; k < 4; ++k)
      real(q.coeffs()[k], kQuatComponent, field);
    if (!(std::abs(q.norm() - 1) <= kQuatTolerance))
      fail(field, "expected a unit quaternion (| |q| - 1 | <= 1e-6), got one of norm " +
                      number_text(q.norm()));
  }

  void world(const WorldSettings& w) const {
    vector(w.gravity, kAcceleration, "world.gravity");
    real(w.dt, kTimeStep, "world.dt");
    real(w.duration, kDuration, "world.duration");
    if (w.steps)
      integer(*w.steps, kSteps, "world.steps");
    integer(w.substeps, kSubsteps, "world.substeps");
    integer(w.max_substeps, kSubsteps, "world.max_substeps");
    if (w.solver != SolverType::impulse && w.solver != SolverType::penalty)
      fail("world.solver", "expected one of: impulse, penalty");
    integer(w.iterations, kIterations, "world.iterations");
    integer(w.relax_iterations, kRelaxIterations, "world.relax_iterations");
    if (static_cast<int>(w.broadphase) > static_cast<int>(BroadPhaseType::hgrid))
      fail("world.broadphase",
           "expected one of: auto, brute, sap, hash, bvh, lbvh, octree, "
           "kdtree, grid, hgrid");
    if (w.geometry != Geometry::deploy && w.geometry != Geometry::train)
      fail("world.geometry", "expected one of: deploy, train");
    if (static_cast<int>(w.ccd) > static_cast<int>(CcdMode::off))
      fail("world.ccd", "expected one of: auto, on, off");
    real(w.contact_margin, kDistance, "world.contact_margin");
    real(w.penetration_slop, kDistance, "world.penetration_slop");
    if (w.contact_hertz)
      real(*w.contact_hertz, kFrequency, "world.contact_hertz");
    real(w.sag_tolerance, kSagTolerance, "world.sag_tolerance");
    real(w.contact_damping_ratio, kDampingRatio, "world.contact_damping_ratio");
    real(w.max_push_velocity, kPushSpeed, "world.max_push_velocity");
    real(w.restitution_threshold, kSpeedThreshold, "world.restitution_threshold");
    real(w.sleep_speed, kPushSpeed, "world.sleep_speed");
    real(w.sleep_time, kDuration, "world.sleep_time");
    if (w.threads != 0)
      integer(w.threads, kThreads, "world.threads");
    if (!w.steps && !(std::ceil(w.duration / w.dt) <= static_cast<Real>(kMaxSteps)))
      fail("world.duration",
           "duration / dt gives more than 1e9 steps (raise dt or shorten "
           "duration)");
  }

  void material(const Material& m, const Field& field) const {
    real(m.friction, kFriction, Field(field, ".friction"));
    real(m.restitution, kRestitution, Field(field, ".restitution"));
    real(m.stiffness, kStiffness, Field(field, ".stiffness"));
    real(m.damping, kDamping, Field(field, ".damping"));
  }

  void shape(const Shape& s, const Field& field) const {
    switch (s.type) {
      case ShapeType::sphere:
        real(s.radius, kSize, Field(field, ".radius"));
        return;
      case ShapeType::box:
        vector(s.half_extents, kSize, Field(field, ".half_extents"));
        return;
      case ShapeType::capsule:
        real(s.radius, kSize, Field(field, ".radius"));
        real(s.half_length, kHalfLength, Field(field, ".half_length"));
        return;
      case ShapeType::cylinder:
        real(s.radius, kSize, Field(field, ".radius"));
        real(s.half_length, kSize, Field(field, ".half_length"));
        return;
      case ShapeType::plane:
        return;
      case ShapeType::hull:
        if (!s.hull)
          fail(field, "a hull shape without its hull (build it with tumble::hull_from_points)");
        return;
      case ShapeType::mesh:
        if (!s.mesh)
          fail(field, "a mesh shape without its mesh (build it with tumble::mesh_from_triangles)");
        return;
      case ShapeType::compound:
        if (!s.compound)
          fail(field,
               "a compound shape without its parts (build it with tumble::compound_from_parts)");
        for (std::size_t i = 0; i < s.compound->parts().size(); ++i)
          shape(s.compound->parts()[i].shape, Field(Field(Field(field, ".parts"), i), ".shape"));
        return;
      case ShapeType::sdf:
        if (!s.sdf)
          fail(field, "an sdf shape without its field (build it with tumble::sdf_shape)");
        return;
    }
    fail(Field(field, ".type"), "unknown shape type " + std::to_string(static_cast<int>(s.type)));
  }

  void body(const BodyDesc& b, const Field& field, std::size_t materials) const {
    if (b.name.size() > kMaxNameLength)
      fail(Field(field, ".name"),
           "a name of at most 256 characters, got " + std::to_string(b.name.size()));
    shape(b.shape, Field(field, ".shape"));
    if (b.train_shape) {
      shape(*b.train_shape, Field(field, ".train_shape"));
      const ShapeType t = b.train_shape->type;
      if (!b.is_static && (t == ShapeType::plane || t == ShapeType::mesh))
        fail(Field(field, ".train_shape"),
             "a moving body's training shape must be bounded and convex or a compound, not a " +
                 std::string(shape_type_name(t)));
    }
    vector(b.position, kCoordinate, Field(field, ".position"));
    orientation(b.orientation, Field(field, ".orientation"));
    vector(b.velocity, kVelocity, Field(field, ".velocity"));
    vector(b.angular_velocity, kAngularVelocity, Field(field, ".angular_velocity"));
    if (b.material < 0 || std::size_t(b.material) >= std::max<std::size_t>(materials, 1))
      fail(Field(field, ".material"), "expected an index into the scene's " +
                                          std::to_string(materials) + " materials, got " +
                                          std::to_string(b.material));
    if (b.is_static && b.kinematic)
      fail(Field(field, ".kinematic"), "a body is static or kinematic, not both");
    if (b.is_static && !(b.velocity.isZero(0) && b.angular_velocity.isZero(0)))
      fail(Field(field, ".velocity"),
           "a static body never moves, so its velocities must be zero (make "
           "it kinematic to move it)");
    const bool unbounded = b.shape.type == ShapeType::plane || b.shape.type == ShapeType::mesh;
    if (unbounded && !b.is_static)
      fail(Field(field, ".static"), std::string("a ") +
                                        (b.shape.type == ShapeType::plane ? "plane" : "mesh") +
                                        " can only be static; set is_static");
    if (b.shape.type == ShapeType::sdf && b.shape.sdf && b.shape.sdf->changes_with_time() &&
        !b.is_static && !b.kinematic)
      fail(Field(field, ".shape"),
           "a field that changes with time (a morph) is an obstacle: its body must be static or "
           "kinematic");
    if (b.is_static || b.kinematic)
      return;
    real(b.mass, kMass, Field(field, ".mass"));
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        real(b.inertia(r, c), RealSpec{"a finite moment in kg m^2", "", -kMaxMoment, kMaxMoment},
             Field(field, ".inertia"));
    if (!((b.inertia - b.inertia.transpose()).cwiseAbs().maxCoeff() <=
          1e-9 * b.inertia.cwiseAbs().maxCoeff()))
      fail(Field(field, ".inertia"), "expected a symmetric inertia tensor");
    // A diagonal tensor (a primitive's, about its own axes) is its own principal moments, in
    // the solver's ascending order: exact, and without the iterative solve a batch would pay
    // on every randomized draw.
    Vec3 moments;
    if (b.inertia.isDiagonal(0)) {
      moments = b.inertia.diagonal();
      std::sort(moments.data(), moments.data() + 3);
    } else {
      moments = Eigen::SelfAdjointEigenSolver<Mat3>(b.inertia).eigenvalues();
    }
    static const char* const kPrincipal[3] = {".inertia (principal moment 0)",
                                              ".inertia (principal moment 1)",
                                              ".inertia (principal moment 2)"};
    for (int k = 0; k < 3; ++k)
      real(moments[k], kMoment, Field(field, kPrincipal[k]));
    // A moment no mass within the shape can have lets the solver turn the body faster than its
    // contacts can hold.
    const std::string impossible =
        impossible_moment(b.mass, moments.maxCoeff(), bounding_radius(b.shape));
    if (!impossible.empty())
      fail(Field(field, ".inertia"), impossible);
  }

  void interval(const std::optional<Interval>& i, const RealSpec& spec, const Field& field) const {
    if (!i)
      return;
    real(i->low, spec, Field(field, std::size_t(0)));
    real(i->high, spec, Field(field, std::size_t(1)));
    if (!(i->low <= i->high))
      fail(field, "expected [low, high] with low <= high, got [" + number_text(i->low) + ", " +
                      number_text(i->high) + "]");
  }

  void randomization(const Randomization& r) const {
    interval(r.friction, kFriction, "randomize.friction");
    interval(r.restitution, kRestitution, "randomize.restitution");
    interval(r.mass_scale, kMassScale, "randomize.mass_scale");
    real(r.size_noise, kSizeNoise, "randomize.size_noise");
    real(r.position_noise, kDistance, "randomize.position_noise");
    real(r.orientation_noise, kAngleNoise, "randomize.orientation_noise");
    if (r.gravity_low.has_value() != r.gravity_high.has_value())
      fail("randomize.gravity", "expected both low and high gravity, or neither");
    if (!r.gravity_low)
      return;
    vector(*r.gravity_low, kAcceleration, "randomize.gravity.low");
    vector(*r.gravity_high, kAcceleration, "randomize.gravity.high");
    for (int k = 0; k < 3; ++k)
      if (!((*r.gravity_low)[k] <= (*r.gravity_high)[k]))
        fail("randomize.gravity",
             "expected low <= high on every axis, got " + number_text((*r.gravity_low)[k]) + " > " +
                 number_text((*r.gravity_high)[k]) + " on axis " + std::to_string(k));
  }

  void drawn() const {
    world(scene_.world);
    for (std::size_t m = 0; m < scene_.materials.size(); ++m)
      material(scene_.materials[m], Field(Field("materials"), m));
    for (std::size_t i = 0; i < scene_.bodies.size(); ++i) {
      if (!scene_.bodies[i].is_static)
        body(scene_.bodies[i], Field(Field("bodies"), i), scene_.materials.size());
    }
  }

  void scene() const {
    world(scene_.world);
    randomization(scene_.randomize);
    for (std::size_t m = 0; m < scene_.materials.size(); ++m)
      material(scene_.materials[m], Field(Field("materials"), m));
    if (scene_.bodies.size() > kMaxBodies)
      fail("bodies", "at most 1000000 bodies, got " + std::to_string(scene_.bodies.size()));
    // Duplicate names: by pairs in a small scene (a batch checks every randomized draw, and a
    // set's nodes were most of the allocations of a reset), through a set in a large one; either
    // way the first body whose name came before is named.
    constexpr std::size_t kPairwiseNames = 32;
    const bool pairwise = scene_.bodies.size() <= kPairwiseNames;
    std::unordered_set<std::string_view> names;
    for (std::size_t i = 0; i < scene_.bodies.size(); ++i) {
      const BodyDesc& b = scene_.bodies[i];
      const Field bodies("bodies");
      const Field field(bodies, i);
      body(b, field, scene_.materials.size());
      if (b.name.empty())
        continue;
      bool seen = false;
      if (pairwise) {
        for (std::size_t j = 0; j < i && !seen; ++j)
          seen = scene_.bodies[j].name == b.name;
      } else {
        seen = !names.insert(b.name).second;
      }
      if (seen)
        fail(Field(field, ".name"), "duplicate body name '" + b.name + "'");
    }
    if (scene_.camera) {
      vector(scene_.camera->position, kCoordinate, "camera.position");
      vector(scene_.camera->target, kCoordinate, "camera.target");
      real(scene_.camera->fov, kFov, "camera.fov");
      // The view direction is the difference of the two: closer than this it has no direction
      // worth the name (1e-300 m apart gave blank frames).
      const Real apart = (scene_.camera->target - scene_.camera->position).norm();
      if (!(apart >= kMinCameraDistance))
        fail("camera.target",
             "must be at least 1e-6 m from camera.position, got " + number_text(apart) + " m");
    }
  }

 private:
  const Scene& scene_;
};

}  // namespace

std::string impossible_moment(Real mass, Real largest_moment, Real radius) {
  const Real most = mass * radius * radius;
  if (largest_moment <= most * (1 + 1e-9))
    return {};
  std::string reason = "a principal moment of ";
  reason += number_text(largest_moment);
  reason += " kg m^2 is more than any mass of ";
  reason += number_text(mass);
  reason += " kg within the shape's bounding radius of ";
  reason += number_text(radius);
  reason += " m can have (m R^2 = ";
  reason += number_text(most);
  reason += ")";
  return reason;
}

void check_scene(const Scene& scene) {
  Checker(scene).scene();
}

void check_drawn_scene(const Scene& draw) {
  Checker(draw).drawn();
}

void check_body(const Scene& scene, const BodyDesc& body, std::size_t slot) {
  Checker(scene).body(body, Field(Field("bodies"), slot), scene.materials.size());
}

}  // namespace tumble
