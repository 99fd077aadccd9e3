// The world stepper behind tumble::World (include/tumble/world.hpp). `Simulation::step` reads as
// the outline of the algorithm (docs/architecture.md, "One step"); each phase is a named function
// with its own timer. Bodies are addressed by slot; the World checks ids and arguments before it
// calls in here.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "collision/broad_phase/broad_phase.hpp"
#include "collision/cache_prefetch.hpp"
#include "collision/narrow_phase/box_batch.hpp"
#include "collision/narrow_phase/manifold_recycling.hpp"
#include "collision/narrow_phase/sphere_batch.hpp"
#include "dynamics/contact_solver.hpp"
#include "dynamics/integrator.hpp"
#include "dynamics/parallel_runner.hpp"
#include "dynamics/penalty_solver.hpp"
#include "engine/continuous_collision.hpp"
#include "engine/islands.hpp"
#include "engine/model.hpp"
#include "engine/state.hpp"
#include "engine/step_statistics.hpp"
#include "engine/step_ticks.hpp"
#include "engine/step_workspace.hpp"

namespace tumble {

// Heap bytes a world holds (capacities), split into what grows with the bodies and what grows
// with the contacts; the broad phase's own structure is not counted.
struct WorldMemory {
  std::size_t body_bytes = 0;
  std::size_t contact_bytes = 0;
  std::size_t scratch_bytes = 0;  // its own StepWorkspace (none in a batch, which lends them)
};

class Simulation {
 public:
  // A simulation of `scene`, compiled without check_scene (tumble::World checks; tests may build
  // scenes the check would refuse).
  explicit Simulation(std::shared_ptr<const Scene> scene);
  explicit Simulation(std::shared_ptr<const Model> model);

  const Scene& scene() const { return *scene_; }
  const Model& model() const { return *model_; }
  const std::shared_ptr<const Model>& model_pointer() const { return model_; }
  const State& state() const { return state_; }
  const BodyMass& mass(int body) const { return masses_[std::size_t(body)]; }
  // The broad-phase structure in use (the scene's choice, or the one `auto` picked).
  BroadPhaseType broad_phase_type() const { return broad_phase_type_; }

  // Replaces the state (reset, restore, replay). The broad phase is rebuilt from the new poses.
  void set_state(const State& state);
  void reset() { set_state(initial_state_); }
  // Puts the world in the initial state of `model`, a model of the same bodies (static, kinematic
  // and moving alike: a randomized draw of the same scene), keeping every buffer: the world then
  // steps as a new Simulation(model) would, bit for bit, without being built again.
  void reset(std::shared_ptr<const Model> model);
  // Whether reset(model) takes `model`: the same bodies, each static, kinematic or moving as here.
  bool can_reset_to(const Model& model) const;

  // Moves one body to a new pose at once, keeping its velocities (a teleport, not motion). The
  // warm-start cache of every pair the body is in is dropped: last step's impulses belong to
  // contacts that no longer exist. reset() and set_state() bring their own cache (empty for
  // reset), so they need no such step.
  void teleport(int body, const Vec3& position, const Quat& orientation);

  // Loads for the next step (tumble::World's add_force, add_torque), cleared by it [N, N m].
  void add_force(int body, const Vec3& force);
  void add_torque(int body, const Vec3& torque);
  // Changes the velocities at once: an impulse [N s] at a world point, or new velocities.
  void apply_impulse(int body, const Vec3& impulse, const Vec3& world_point);
  void set_velocity(int body, const Vec3& linear, const Vec3& angular);
  // A kinematic body's pose at the end of the next step.
  void set_kinematic_target(int body, const Vec3& position, const Quat& orientation);
  // Wakes a sleeping body (its island wakes with it in the next step).
  void wake(int body);
  // Adds a body (in the lowest removed slot, else at the end) and returns its slot; removes one,
  // leaving its slot empty. Between steps; the broad phase is updated, not rebuilt.
  int add_body(const BodyDesc& desc);
  void remove_body(int body);

  // Advances by scene().world.dt, in scene().world.substeps equal substeps, with the world's own
  // scratch arrays.
  void step();
  // The same step with scratch arrays lent for it (a batch's thread's, used by one step at a
  // time): the same bits whatever the workspace held before.
  void step(StepWorkspace& scratch);

  // Threads a step uses: scene().world.threads, or the machine's cores for `auto`.
  int threads() const { return runner_->threads(); }
  // Uses `threads` from the next step on (<= 0: the machine's cores). The results do not change.
  void set_threads(int threads);

  const StepStatistics& last_step_statistics() const { return last_step_; }
  // state_hash() of the current state (computed on request, not by every step).
  std::uint64_t state_hash() const { return tumble::state_hash(state_); }

  // What the last step's collision stages found, for debug views: the broad phase's candidate
  // pairs and the touching pairs with their manifolds (poses at the start of that step). Empty
  // before the first step.
  std::span<const ProxyPair> candidate_pairs() const { return candidate_pairs_; }
  std::span<const PairContact> contacts() const { return contacts_; }

  WorldMemory memory() const;

  // Ask for what the next step reads (collision/cache_prefetch.hpp), in two calls a step apart:
  // the arrays' addresses are in this object, so it must arrive first. A batch asks for the
  // object two worlds ahead of the world it steps, and records the arrays of the one after it in
  // the workspace of the step, which asks for them a slice at a time between its stages.
  void prefetch_self() const { CachePrefetch::issue_now(*this); }
  void prefetch_step_arrays(CachePrefetch& requests) const;

  // The contact force on each body over the last step [N] (its contacts' impulses over dt), as
  // x, y, z per body, and the number of touching pairs it was in; both overwritten whole.
  void contact_forces(std::span<Real> xyz, std::span<std::int32_t> counts) const;
  // What the kept impulses (state().contacts) are multiplied by to give a step's impulse: the
  // impulse solver keeps the step's, the penalty solver one substep's.
  Real report_impulse_scale() const {
    return scene_->world.solver == SolverType::penalty ? Real(penalty_substeps_) : Real(1);
  }

  // The body the segment origin + t direction, t in [0, max_distance] (direction unit), meets
  // first, and where; body -1 when none.
  struct RayResult {
    int body = -1;
    Real distance = 0;
    Vec3 normal = Vec3::UnitZ();
  };
  // Not const: it first brings the broad phase's boxes to the bodies' current poses when a step
  // has moved them (the boxes are those of the start of the last step).
  RayResult ray_cast(const Vec3& origin, const Vec3& direction, Real max_distance);

  // Totals over all bodies [J]: kinetic, and gravitational potential relative to the origin.
  Real kinetic_energy() const;
  Real potential_energy() const;

  // Substeps per step of the penalty solver: the scene's `substeps`, raised so that the stiffest
  // spring on the lightest body is resolved (h < 2 / omega, the explicit stability limit) while
  // that costs at most kMaxPenaltySubsteps; beyond, the implicit update alone keeps it stable.
  int penalty_substeps() const { return penalty_substeps_; }
  static constexpr int kMaxPenaltySubsteps = 64;
  // The penalty solver iterates each substep to convergence, at most this many passes (or the
  // scene's `iterations` when larger).
  static constexpr int kMaxPenaltyIterations = 64;
  // Contact recycling (collision/narrow_phase/manifold_recycling.hpp): a pair reuses its manifold
  // while B's pose relative to A stays within this fraction of the smaller body's bounding radius
  // and this angle [rad] of the pose it was computed at. A thousandth of the size keeps the
  // recycled points within that of where a fresh query puts them (docs/narrow-phase.md,
  // "Recycling").
  static constexpr Real kRecycleDistance = Real(1e-3);
  static constexpr Real kRecycleAngle = Real(2e-3);

 private:
  const Shape& shape_now(std::int32_t body, Shape& storage) const;
  bool field_changing_now(std::int32_t body) const;
  void update_bounds(Real dt);
  void find_candidate_pairs();
  void collide_candidate_pairs();
  void prepare_contacts();
  void choose_substeps();
  void integrate_velocities(int group, Real h);
  void solve_contacts(int group);
  void integrate_positions(int group, Real h);
  void relax_contacts(int group);
  void finish_contacts();
  void rebuild_broad_phase();
  void wake_touched_islands();
  bool find_resting_bodies();
  void reserve_sleep_lists();
  bool out_of_solver(std::int32_t body) const;
  void update_sleep(Real dt);
  void sweep_fast_bodies();

  void step_on_runner();
  void adopt(std::shared_ptr<const Model> model);
  // set_state, keeping the broad phase's structure only if `may_keep_broad_phase` (reset(model):
  // the static bodies kept their boxes) and no static body moved.
  void set_state(const State& state, bool may_keep_broad_phase);
  void resize_body_arrays();
  void choose_penalty_substeps();
  void drop_pairs_of(int body);
  void wake_near(const Aabb& box);
  void clear_loads();
  void start_kinematic_motion(Real dt);
  void move_kinematic_bodies(Real fraction, Real dt);
  template <class Update>
  void for_each_awake_chunk(int group, const Update& update);

  std::shared_ptr<const Model> model_;
  const Scene* scene_ = nullptr;  // model_'s scene
  State initial_state_;           // initial_state(*scene_), kept for reset()
  State state_;
  std::unique_ptr<ParallelRunner> runner_;

  // Fixed per model (views of model_).
  std::span<const BodyMass> masses_;
  std::span<const Real> bounding_radii_;
  std::span<const std::uint8_t> flat_shape_;  // recycles its manifolds (collide_candidate_pairs)
  // Loads for the next step: per body, its force and torque and whether it has any.
  std::vector<Vec3> force_;
  std::vector<Vec3> torque_;
  std::vector<std::uint8_t> loaded_;
  std::vector<std::int32_t> loaded_bodies_;
  // Kinematic bodies: their slots, their poses at the start of the step, and the targets set for
  // the next step (has_target_ per body).
  std::vector<std::int32_t> kinematic_bodies_;
  std::vector<Transform> kinematic_start_;
  std::vector<Transform> kinematic_target_;
  std::vector<std::uint8_t> has_target_;
  std::vector<std::uint8_t> field_changes_;  // per body: its shape is a field changing with time
  // The broad phase's boxes are those of the start of the last step, not the current poses.
  bool bounds_stale_ = false;
  std::vector<std::int32_t> query_scratch_;
  BroadPhaseType broad_phase_type_ = BroadPhaseType::brute;
  std::unique_ptr<BroadPhase> broad_phase_;

  // Scratch kept across steps so that a step does not allocate once capacities settle.
  std::vector<Real> speculative_margin_;
  std::vector<ProxyPair> candidate_pairs_;
  std::vector<PairContact> contacts_;
  // The step's scratch: the world's own, or one a batch lends for the step (step(workspace)).
  std::unique_ptr<StepWorkspace> own_scratch_;
  StepWorkspace* scratch_ = nullptr;
  // Substep groups of this step (docs/architecture.md, "Substeps per island"): group g's
  // settings, its moving awake bodies, and each contact's group. Group 0 runs the scene's
  // `substeps` and holds the bodies that touch nothing.
  std::vector<ContactSolverSettings> group_settings_;
  std::vector<std::int32_t> group_body_start_;  // group g's awake bodies: [start[g], start[g + 1])
  std::vector<std::int32_t> group_bodies_;
  std::vector<std::int32_t> group_of_contact_;
  PenaltySolver penalty_solver_;
  std::vector<PenaltyPair> penalty_springs_;  // one per contacts_ entry
  int penalty_substeps_ = 1;                  // fixed per scene (penalty_substeps())
  // Sleeping islands the narrow phase leaves out (find_resting_bodies): islands of the resting
  // touches, whether a body that does not rest meets one, and per body whether its resting pairs
  // are taken from State::resting_touches this step.
  Islands rest_islands_;
  std::vector<std::uint8_t> rest_disturbed_;  // per root of rest_islands_
  std::vector<std::uint8_t> rest_skips_;      // per body
  // Whether a sleeping body may have woken since the last wake_touched_islands (wake(), a new
  // state or model, or that stage itself): only then can a pair of State::sleeping_contacts be
  // active again.
  bool sleepers_may_have_woken_ = true;
  std::vector<std::uint8_t> island_awake_;  // per root body
  std::vector<Real> island_slow_time_;      // per root body: the least of its bodies'
  std::unique_ptr<ContinuousCollision> continuous_;
  bool sweeps_ = false;  // whether the scene ever sweeps a body (continuous_ then holds its tables)

  StepStatistics current_;
  StepTicks ticks_;  // the stage timers' counts during a step, in current_ at its end
  StepStatistics last_step_;
};

}  // namespace tumble
