// A Scene is what a world *is*: settings, materials and body descriptions. It is constant while
// the world steps; everything a step changes lives in the world's state. This split (MuJoCo's
// model and data) makes reset, copy, hashing, replay and batches of worlds cheap. A scene comes
// from a YAML file (tumble/load_scene.hpp) or is built in code; either way it is checked once
// when a world is made from it (tumble/model.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tumble/math.hpp"
#include "tumble/randomization.hpp"
#include "tumble/settings.hpp"
#include "tumble/shape.hpp"

namespace tumble {

// Contact material. Pairs combine friction by the geometric mean and restitution by the maximum,
// unless the scene replaces the rule (Scene::friction_mixing, restitution_mixing).
struct Material {
  std::string name;
  Real friction = Real(0.5);  // Coulomb coefficient [1]
  Real restitution = 0;       // [1], 0 = plastic, 1 = elastic
  // Penalty solver only (docs/stability.md): the contact spring and damper of a pair, the
  // smaller stiffness and the larger damping of the two materials, shared among the manifold's
  // points.
  Real stiffness = 1e6;  // k [N/m]
  Real damping = 1e3;    // c [N s/m]
};

// The default rules: friction sqrt(mu_a mu_b), restitution max(e_a, e_b) (Box2D's).
Real default_friction_mixing(const Material& a, const Material& b);
Real default_restitution_mixing(const Material& a, const Material& b);
using MixingRule = std::function<Real(const Material& a, const Material& b)>;

struct BodyDesc {
  std::string name;
  Shape shape;
  Vec3 position = Vec3::Zero();          // m, centre of mass
  Quat orientation = Quat::Identity();   // unit, body to world
  Vec3 velocity = Vec3::Zero();          // m/s
  Vec3 angular_velocity = Vec3::Zero();  // rad/s, world frame
  Real mass = 0;                         // kg; 0 for static bodies
  Mat3 inertia = Mat3::Zero();           // kg m^2 about the centre of mass, body frame
  int material = 0;                      // index into Scene::materials
  bool is_static = false;
  // Moved by the program, not by forces (World::set_kinematic_target, set_velocity): infinite
  // mass, pushes dynamic bodies, ignores contacts and gravity. `mass` and `inertia` are unused.
  bool kinematic = false;
  bool fast = false;  // always swept by continuous collision detection
  // A simpler collision shape for training (world.geometry = train), in this body's frame: a
  // primitive, a compound_in_frame, or fit_shape(shape, ...). The body keeps the mass, inertia
  // and centre of mass of `shape` in either geometry.
  std::optional<Shape> train_shape;
};

// Bodies built in code, with mass and inertia from the shape. A dynamic body of `density`
// [kg/m^3] (1000 when not given, except for a signed distance field, whose volume is integrated
// over its cells and which needs it given); a static body; a kinematic body. Throws
// tumble::Error for a plane or mesh made dynamic or kinematic, a field without a density, or a
// density that is not positive and finite.
BodyDesc dynamic_body(std::string name, Shape shape, std::optional<Real> density = std::nullopt);
BodyDesc static_body(std::string name, Shape shape);
BodyDesc kinematic_body(std::string name, Shape shape);

struct Camera {
  Vec3 position{6, -6, 4};  // m
  Vec3 target{0, 0, 1};     // m
  Real fov = 45;            // vertical field of view, degrees
};

struct Scene {
  std::string source;  // where the scene came from (file path), for messages
  WorldSettings world;
  // materials[0] is the default, which a body gets unless it names another. Left empty, the
  // world uses Material{"default"} (friction 0.5, restitution 0).
  std::vector<Material> materials;
  std::vector<BodyDesc> bodies;
  std::optional<Camera> camera;
  // The rules that combine two materials into a pair's friction and restitution; empty: the
  // defaults. Evaluated once per pair of materials when a world is made, never in the step; a
  // batch compiles its randomized draws on several threads, so a rule must be safe to call from
  // several threads at once (a pure function of its arguments is).
  MixingRule friction_mixing;
  MixingRule restitution_mixing;
  // What each world of a batch draws at its reset (tumble/randomization.hpp); a lone World
  // draws nothing: make it from randomized(scene, seed).
  Randomization randomize;

  // The index of the body or material of that name, or -1.
  int find_body(std::string_view name) const;
  int find_material(std::string_view name) const;
};

}  // namespace tumble
