// A world: a scene's bodies in motion, stepped by tumble's collision pipeline and solver. This is
// the one class a program drives; docs/api.md describes every call with its units, frames, when
// it takes effect and what it throws.
//
//   auto scene = tumble::load_scene("scene.yaml");
//   tumble::World world(scene);
//   tumble::BodyId box = world.body("box");
//   world.add_force(box, {0, 0, 20});
//   world.step();
//   tumble::BodyState s = world.body_state(box);
//
// Every call checks its arguments and throws tumble::Error naming the body and the value when
// they are wrong; none has undefined behaviour. A world is used from one thread at a time (its
// const calls too: reports and ray casts fill caches); different worlds may run on different
// threads at once. The engine behind the world stays hidden, so a
// program that includes this header sees no collision or solver code.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tumble/body_state.hpp"
#include "tumble/math.hpp"
#include "tumble/model.hpp"
#include "tumble/scene.hpp"

namespace tumble {

class Simulation;  // the engine behind a World (engine/simulation.hpp), not part of the API

// A body of a world. It stays valid until the body is removed; a removed body's id then fails
// cleanly in every call, even when a new body takes its slot (the generation differs).
struct BodyId {
  std::int32_t index = -1;       // the body's slot in the world's body list
  std::uint32_t generation = 0;  // how many bodies held the slot before this one

  bool operator==(const BodyId&) const = default;
};

// One point of a touching pair.
struct ContactPointReport {
  Vec3 position = Vec3::Zero();  // world, midway between the surfaces [m]
  Real depth = 0;                // penetration (positive) or gap (negative) [m]
  // What the solver applied at this point over the last step: along the normal (pushing A away
  // from B, >= 0) and in the contact plane (world frame) [N s].
  Real normal_impulse = 0;
  Vec3 friction_impulse = Vec3::Zero();
};

// A pair of bodies in contact during the last step. The geometry is what collision found at the
// start of that step; the impulses are what the solver applied in it.
struct ContactReport {
  BodyId body_a;
  BodyId body_b;
  Vec3 normal = Vec3::UnitZ();  // unit, from B to A
  int point_count = 0;
  std::array<ContactPointReport, 4> points{};
};

struct RayHit {
  BodyId body;
  Real distance = 0;            // along the ray from its origin [m]
  Vec3 point = Vec3::Zero();    // world [m]
  Vec3 normal = Vec3::UnitZ();  // outward surface normal at the point (world)
};

class World {
 public:
  // A world in the scene's initial state. Checks the scene first (tumble/model.hpp) and throws
  // SceneError naming the field when it is not valid.
  explicit World(std::shared_ptr<const Scene> scene);
  // A world of a compiled model, which many worlds may share.
  explicit World(std::shared_ptr<const Model> model);
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // The scene as the world now holds it: the original's, with added bodies appended (or in
  // freed slots) and removed ones left as empty slots. add_body and remove_body replace it: a
  // reference taken before them is no longer valid after.
  const Scene& scene() const;

  // --- Bodies ---------------------------------------------------------------------------------
  // The body of that name; throws Error when there is none.
  BodyId body(std::string_view name) const;
  std::optional<BodyId> find_body(std::string_view name) const;
  bool is_valid(BodyId id) const;
  std::string name(BodyId id) const;
  // The bodies that exist now, in slot order.
  std::vector<BodyId> bodies() const;
  int body_count() const;

  // Adds a body between steps, in the lowest free slot or at the end; checked like a scene's
  // body (SceneError naming the field). Its name must be unique when not empty.
  BodyId add_body(const BodyDesc& desc);
  // Removes a body between steps: it leaves the broad phase and every contact it was in.
  void remove_body(BodyId id);

  // --- Forces and motion (dynamic bodies; a body that sleeps wakes up) ------------------------
  // Forces [N] and torques [N m], world frame. They add up until the next step, act during it,
  // and are then cleared. add_force acts at the centre of mass; add_force_at at a world point,
  // adding the torque (point - centre) x force.
  void add_force(BodyId id, const Vec3& force);
  void add_torque(BodyId id, const Vec3& torque);
  void add_force_at(BodyId id, const Vec3& force, const Vec3& world_point);
  // An impulse [N s] at a world point: the velocities change at once.
  void apply_impulse(BodyId id, const Vec3& impulse, const Vec3& world_point);
  // Linear [m/s] and angular [rad/s] velocity, world frame, at once (dynamic or kinematic).
  void set_velocity(BodyId id, const Vec3& linear, const Vec3& angular);
  // Moves a body to a pose at once, keeping its velocities (a teleport, for resets). Its contacts'
  // warm-start impulses are dropped.
  void set_pose(BodyId id, const Vec3& position, const Quat& orientation);
  // A kinematic body reaches this pose at the end of the next step, moving with the constant
  // velocity that takes it there (and keeps that velocity afterwards, until told otherwise).
  void set_kinematic_target(BodyId id, const Vec3& position, const Quat& orientation);

  // --- Stepping --------------------------------------------------------------------------------
  // Advances by the scene's dt, `n` times.
  void step();
  void step(int n);
  // Back to the scene's initial state (bodies added since stay, at their descriptions' poses).
  void reset();
  // To the initial state of another model of the same bodies, each static, kinematic or moving
  // as here (a randomized draw of the same scene, tumble/randomization.hpp): the world then steps
  // exactly as World(model) would, without being built again. Throws tumble::Error otherwise.
  void reset(std::shared_ptr<const Model> model);
  // Threads a step uses (<= 0: the machine's cores); the results are the same bits on any count.
  void set_threads(int threads);
  int threads() const;

  // --- Reading ---------------------------------------------------------------------------------
  BodyState body_state(BodyId id) const;
  Real time() const;  // s, steps taken times dt
  std::int64_t step_count() const;
  // The pairs in contact in the last step (empty before the first).
  std::span<const ContactReport> contact_reports() const;
  // The first body surface the ray origin + t direction / |direction|, 0 <= t <= max_distance,
  // meets, or nothing. A ray starting inside a body hits it at distance 0.
  std::optional<RayHit> ray_cast(const Vec3& origin, const Vec3& direction,
                                 Real max_distance) const;
  // A 64-bit hash of the whole state, equal across runs, thread counts and machines.
  std::uint64_t state_hash() const;

  // The engine behind the world, for tumble's own tools (its header is not installed).
  Simulation& simulation() { return live(); }
  const Simulation& simulation() const { return live(); }

 private:
  Simulation& live() const;               // the simulation, or throws for a moved-from world
  std::int32_t checked(BodyId id) const;  // the slot, or throws
  std::int32_t checked_dynamic(BodyId id, std::string_view call) const;
  void refresh_reports() const;

  std::unique_ptr<Simulation> simulation_;
  std::vector<std::uint32_t> generation_;  // per slot
  mutable std::vector<ContactReport> reports_;
  mutable std::int64_t reports_step_ = -1;
};

}  // namespace tumble
