#include "engine/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <type_traits>
#include <utility>

#include "collision/broad_phase/broad_phase_factory.hpp"
#include "collision/ccd/ray_cast.hpp"
#include "collision/narrow_phase/box_axis_cache.hpp"
#include "collision/narrow_phase/manifold_recycling.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"
#include "collision/narrow_phase/sphere_batch.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "engine/broad_phase_choice.hpp"
#include "engine/number_text.hpp"
#include "engine/scene_limits.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

// The entry of `sorted` (a list sorted by pair) for the pair (a, b), or null. The cursor only
// moves forward, so candidates visited in pair order find all their entries in one walk.
template <class Entry>
const Entry* find_pair(const std::vector<Entry>& sorted, std::size_t& cursor, std::int32_t a,
                       std::int32_t b) {
  while (cursor < sorted.size() &&
         std::pair{sorted[cursor].body_a, sorted[cursor].body_b} < std::pair{a, b})
    ++cursor;
  return cursor < sorted.size() && sorted[cursor].body_a == a && sorted[cursor].body_b == b
             ? &sorted[cursor]
             : nullptr;
}

// Moves the entries of `from` for which `moves` holds into `to`; both are sorted by pair and
// share no pair, and stay so. In place (merged from the back): neither list allocates unless `to`
// outgrows its capacity.
template <class Entry, class Moves>
void move_pairs_if(std::vector<Entry>& from, std::vector<Entry>& to, const Moves& moves) {
  std::size_t count = 0;
  for (const Entry& e : from)
    count += moves(e) ? 1 : 0;
  if (count == 0)
    return;
  const auto key = [](const Entry& e) { return std::pair{e.body_a, e.body_b}; };
  std::size_t left_in_to = to.size();
  to.resize(left_in_to + count);
  std::size_t write = to.size();
  std::size_t read = from.size();
  for (; count > 0; --count) {
    do
      --read;
    while (!moves(from[read]));
    while (left_in_to > 0 && key(to[left_in_to - 1]) > key(from[read]))
      to[--write] = to[--left_in_to];
    to[--write] = from[read];
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    if (!moves(from[i]))
      from[kept++] = from[i];
  }
  from.resize(kept);
}

// Drops the entries of `list` whose pair has `body` in it.
template <class Entry>
void erase_pairs_of(std::vector<Entry>& list, int body) {
  std::erase_if(list, [body](const Entry& e) { return e.body_a == body || e.body_b == body; });
}

// Times one stage of the step, or one phase of the solve stage (which counts toward the stage
// too), in ticks of the step's clock (engine/step_ticks.hpp). A stage is reported as run once a
// timer has been made for it, unless the timer is told that the stage had nothing to do.
class StageTimer {
 public:
  StageTimer(StepStatistics& stats, StepTicks& ticks, Stage stage)
      : stats_(stats), ticks_(ticks), stage_(static_cast<int>(stage)), start_(read_ticks()) {
    stats_.ran[std::size_t(stage_)] = true;
  }
  StageTimer(StepStatistics& stats, StepTicks& ticks, SolvePhase phase)
      : StageTimer(stats, ticks, Stage::solve) {
    phase_ = static_cast<int>(phase);
  }
  ~StageTimer() {
    const std::uint64_t elapsed = read_ticks() - start_;
    ticks_.stage[std::size_t(stage_)] += elapsed;
    if (phase_ >= 0)
      ticks_.phase[std::size_t(phase_)] += elapsed;
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;
  // The stage's time still counts, but it is not reported as run (for this step).
  void had_nothing_to_do(bool ran_before) { stats_.ran[std::size_t(stage_)] = ran_before; }

 private:
  StepStatistics& stats_;
  StepTicks& ticks_;
  int stage_;
  int phase_ = -1;
  std::uint64_t start_;
};

// Work per chunk on the runner's threads: enough that a chunk outweighs handing it over.
constexpr std::int32_t kBodiesPerChunk = 128;
constexpr std::int32_t kPairsPerChunk = 32;
constexpr std::int32_t kBoxPairsPerChunk = 128;
constexpr std::int32_t kSortedPairsPerChunk = 256;  // recycling a pair: about 50 ns

// How the narrow phase answers a candidate pair (StepWorkspace::candidate_route): the kind in the
// low bits, and what the caches gave, for the counts.
constexpr std::uint8_t kRouteDone = 0;  // recycled, kept apart by its cached axis, or ignored
constexpr std::uint8_t kRouteBoxQuery = 1;
constexpr std::uint8_t kRouteSphere = 2;
constexpr std::uint8_t kRouteOther = 3;
constexpr std::uint8_t kRouteKind = 3;
constexpr std::uint8_t kRouteAxisTried = 4;      // a cached separating axis was tested
constexpr std::uint8_t kRouteAxisHit = 8;        // and still separates
constexpr std::uint8_t kRouteWarm = 16;          // GJK starts from last step's simplex
constexpr std::uint8_t kRouteResting = 32;       // two resting bodies: not collided again
constexpr std::uint8_t kRouteRestingTouch = 64;  // and they touched when last collided

Transform pose_of(const BodyState& b) {
  return {b.position, b.orientation};
}

}  // namespace

Simulation::Simulation(std::shared_ptr<const Scene> scene)
    : Simulation(Model::build(std::move(scene))) {}

Simulation::Simulation(std::shared_ptr<const Model> model)
    : runner_(std::make_unique<ParallelRunner>(model->scene().world.threads)) {
  // At most one group per doubling of the substeps (a count is a power of two times the base,
  // at most 1000): room for all of them now, so that a new group never allocates mid-run.
  constexpr std::size_t kMostGroups = 11;
  group_settings_.reserve(kMostGroups);
  group_body_start_.reserve(kMostGroups + 1);
  broad_phase_type_ = choose_broad_phase(model->scene().world.broadphase, model->scene());
  adopt(std::move(model));
  set_state(initial_state_);
}

// Takes a (new) model: its views, the per-body scratch, the penalty substeps and continuous
// collision follow it.
void Simulation::adopt(std::shared_ptr<const Model> model) {
  model_ = std::move(model);
  scene_ = &model_->scene();
  masses_ = model_->masses();
  bounding_radii_ = model_->bounding_radii();
  flat_shape_ = model_->flat_shape();
  const std::size_t n = scene_->bodies.size();
  speculative_margin_.resize(n);
  force_.resize(n, Vec3::Zero());
  torque_.resize(n, Vec3::Zero());
  loaded_.resize(n, 0);
  kinematic_target_.resize(n);
  has_target_.resize(n, 0);
  kinematic_bodies_.clear();
  field_changes_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (model_->is_kinematic(i))
      kinematic_bodies_.push_back(static_cast<std::int32_t>(i));
    const Shape& shape = scene_->bodies[i].shape;
    field_changes_[i] = shape.type == ShapeType::sdf && shape.sdf->changes_with_time();
  }
  kinematic_start_.resize(kinematic_bodies_.size());
  // Another model may give a sleeping body another shape: its contacts are found again before
  // they are taken from the resting touches.
  for (std::uint8_t& asleep : state_.asleep)
    asleep = std::min<std::uint8_t>(asleep, 1);
  sleepers_may_have_woken_ = true;
  initial_state_into(*scene_, initial_state_);
  choose_penalty_substeps();
  // The tables are kept across resets (a world reset to a drawn model of the same bodies
  // allocates none); `sweeps_` says whether this scene uses them.
  if (continuous_)
    continuous_->rebuild(*scene_);
  else
    continuous_ = std::make_unique<ContinuousCollision>(*scene_);
  sweeps_ = continuous_->enabled();
}

bool Simulation::can_reset_to(const Model& model) const {
  if (model.drawn_from_same_scene(*model_))
    return true;
  // The models' compact motion tables answer without reading the scenes (a reset in a large
  // batch finds this world's scene out of the cache); a removed slot keeps its description's
  // flags, which the motion table does not show (equal tables: both have removed slots or neither).
  if (model.motions() != model_->motions())
    return false;
  if (model.removed_count() == 0)
    return true;
  const Scene& next = model.scene();
  if (next.bodies.size() != scene_->bodies.size())
    return false;
  for (std::size_t i = 0; i < next.bodies.size(); ++i) {
    if (next.bodies[i].is_static != scene_->bodies[i].is_static ||
        next.bodies[i].kinematic != scene_->bodies[i].kinematic ||
        model.is_removed(i) != model_->is_removed(i))
      return false;
  }
  return true;
}

void Simulation::reset(std::shared_ptr<const Model> model) {
  if (!model)
    throw Error("tumble::World::reset: the model is null");
  // Another draw of the scene this world's model was drawn from has its bodies and its static
  // bodies' descriptions (a batch's randomized reset): neither needs comparing, and the old
  // scene, out of the cache in a large batch, is not read.
  const bool redraw = model->drawn_from_same_scene(*model_);
  if (!can_reset_to(*model))
    throw Error(
        "tumble::World::reset: the model's bodies are not this world's (the same count, "
        "each static, kinematic or moving as before)");
  // The broad phase keeps its structure only where the static bodies keep their boxes (where it
  // holds them now, at their current poses): a drawn size or pose moves them, and so does
  // another structure.
  const Scene& next = model->scene();
  const BroadPhaseType type = choose_broad_phase(next.world.broadphase, next);
  bool statics_kept = type == broad_phase_type_;
  for (std::size_t i = 0; statics_kept && !redraw && i < next.bodies.size(); ++i) {
    if (!next.bodies[i].is_static)
      continue;
    const Aabb before = world_aabb(scene_->bodies[i].shape, pose_of(state_.bodies[i]));
    const BodyDesc& b = next.bodies[i];
    const Aabb after = world_aabb(b.shape, {b.position, b.orientation});
    statics_kept = before.min == after.min && before.max == after.max;
  }
  adopt(std::move(model));
  broad_phase_type_ = type;
  set_state(initial_state_, statics_kept);
}

void Simulation::choose_penalty_substeps() {
  penalty_substeps_ = std::max(1, scene_->world.substeps);
  if (scene_->world.solver != SolverType::penalty)
    return;
  Real stiffest = 0;
  for (const Material& m : scene_->materials)
    stiffest = std::max(stiffest, m.stiffness);
  Real lightest = 0;
  for (const BodyMass& m : masses_)
    lightest = std::max(lightest, m.inverse_mass);
  // omega = sqrt(k / m); explicit symplectic Euler needs h omega < 2.
  const Real omega = std::sqrt(stiffest * lightest);
  const Real wanted = std::ceil(scene_->world.dt * omega / 2);
  if (wanted > penalty_substeps_)
    penalty_substeps_ = static_cast<int>(std::min<Real>(wanted, kMaxPenaltySubsteps));
}

void Simulation::set_threads(int threads) {
  runner_ = std::make_unique<ParallelRunner>(threads);
}

void Simulation::set_state(const State& state) {
  set_state(state, true);
}

void Simulation::set_state(const State& state, bool may_keep_broad_phase) {
  if (state.bodies.size() != scene_->bodies.size())
    throw Error("Simulation::set_state: the state has " + std::to_string(state.bodies.size()) +
                " bodies, the world " + std::to_string(scene_->bodies.size()));
  // The broad phase keeps its structure when only moving bodies change pose (a reset, a replay):
  // their boxes are updated in place, which is what makes a reset cheap. A static body that
  // moved, or a first state, rebuilds it.
  bool keep_broad_phase = may_keep_broad_phase && broad_phase_ != nullptr &&
                          state_.bodies.size() == state.bodies.size();
  for (std::size_t i = 0; keep_broad_phase && i < state.bodies.size(); ++i) {
    if (scene_->bodies[i].is_static &&
        (state.bodies[i].position != state_.bodies[i].position ||
         state.bodies[i].orientation.coeffs() != state_.bodies[i].orientation.coeffs()))
      keep_broad_phase = false;
  }
  state_ = state;
  sleepers_may_have_woken_ = true;
  // What the last step found and what was asked of the next one belong to the state left behind.
  contacts_.clear();
  penalty_springs_.clear();
  candidate_pairs_.clear();
  clear_loads();
  std::fill(has_target_.begin(), has_target_.end(), std::uint8_t(0));
  // A state made by hand may leave the sleep records out: nothing sleeps then.
  state_.slow_time.resize(state_.bodies.size(), 0);
  state_.asleep.resize(state_.bodies.size(), 0);
  state_.substep_level.resize(state_.bodies.size(), 0);
  state_.substep_hold.resize(state_.bodies.size(), 0);
  if (!keep_broad_phase) {
    rebuild_broad_phase();
    return;
  }
  for (std::size_t i = 0; i < state_.bodies.size(); ++i) {
    if (scene_->bodies[i].is_static)
      continue;
    broad_phase_->update(static_cast<std::int32_t>(i),
                         world_aabb(scene_->bodies[i].shape, pose_of(state_.bodies[i])));
  }
  bounds_stale_ = false;
}

void Simulation::teleport(int body, const Vec3& position, const Quat& orientation) {
  BodyState& b = state_.bodies[std::size_t(body)];
  const Shape& shape = scene_->bodies[std::size_t(body)].shape;
  // What rested on the body where it was, and what it lands among, must notice.
  if (shape.is_bounded())
    wake_near(world_aabb(shape, pose_of(b)));
  b.position = position;
  b.orientation = orientation.normalized();
  drop_pairs_of(body);
  rebuild_broad_phase();
  if (shape.is_bounded())
    wake_near(world_aabb(shape, pose_of(b)));
  if (!model_->is_fixed(std::size_t(body)))
    wake(body);
}

// Forces and torques act for one step (or are dropped with the state they were meant for).
void Simulation::clear_loads() {
  for (const std::int32_t i : loaded_bodies_) {
    force_[std::size_t(i)].setZero();
    torque_[std::size_t(i)].setZero();
    loaded_[std::size_t(i)] = 0;
  }
  loaded_bodies_.clear();
}

// Wakes every moving body whose box, grown by the contact margin, meets `box`.
void Simulation::wake_near(const Aabb& box) {
  if (!scene_->world.sleeping)
    return;
  broad_phase_->query(box.inflated(scene_->world.contact_margin), query_scratch_);
  for (const std::int32_t i : query_scratch_) {
    if (!model_->is_fixed(std::size_t(i)))
      wake(i);
  }
}

// The kept caches of every pair the body is in.
void Simulation::drop_pairs_of(int body) {
  erase_pairs_of(state_.contacts, body);
  erase_pairs_of(state_.manifolds, body);
  erase_pairs_of(state_.box_axes, body);
  erase_pairs_of(state_.gjk_caches, body);
  erase_pairs_of(state_.hull_axes, body);
  erase_pairs_of(state_.resting_touches, body);
  erase_pairs_of(state_.sleeping_contacts, body);
}

void Simulation::wake(int body) {
  sleepers_may_have_woken_ = true;
  state_.asleep[std::size_t(body)] = 0;
  state_.slow_time[std::size_t(body)] = 0;
}

void Simulation::add_force(int body, const Vec3& force) {
  const std::size_t i = std::size_t(body);
  if (loaded_[i] == 0) {
    loaded_[i] = 1;
    loaded_bodies_.push_back(body);
  }
  force_[i] += force;
  wake(body);
}

void Simulation::add_torque(int body, const Vec3& torque) {
  add_force(body, Vec3::Zero());
  torque_[std::size_t(body)] += torque;
}

void Simulation::apply_impulse(int body, const Vec3& impulse, const Vec3& world_point) {
  BodyState& b = state_.bodies[std::size_t(body)];
  const BodyMass& m = masses_[std::size_t(body)];
  const Mat3 r = b.orientation.toRotationMatrix();
  b.velocity += impulse * m.inverse_mass;
  b.angular_velocity +=
      r * (m.inverse_inertia * (r.transpose() * (world_point - b.position).cross(impulse)));
  wake(body);
}

void Simulation::set_velocity(int body, const Vec3& linear, const Vec3& angular) {
  BodyState& b = state_.bodies[std::size_t(body)];
  b.velocity = linear;
  b.angular_velocity = angular;
  wake(body);
}

void Simulation::set_kinematic_target(int body, const Vec3& position, const Quat& orientation) {
  kinematic_target_[std::size_t(body)] = {position, orientation.normalized()};
  has_target_[std::size_t(body)] = 1;
}

int Simulation::add_body(const BodyDesc& desc) {
  std::size_t slot = scene_->bodies.size();
  for (std::size_t i = 0; i < scene_->bodies.size(); ++i) {
    if (model_->is_removed(i)) {
      slot = i;
      break;
    }
  }
  adopt(model_->with_body(desc, slot));
  const std::size_t n = scene_->bodies.size();
  state_.bodies.resize(n);
  state_.slow_time.resize(n, 0);
  state_.asleep.resize(n, 0);
  state_.substep_level.resize(n, 0);
  state_.substep_hold.resize(n, 0);
  state_.bodies[slot] = {desc.position, desc.orientation.normalized(), desc.velocity,
                         desc.angular_velocity};
  state_.slow_time[slot] = 0;
  state_.asleep[slot] = 0;
  state_.substep_level[slot] = 0;
  state_.substep_hold[slot] = 0;
  broad_phase_->insert(static_cast<std::int32_t>(slot),
                       world_aabb(desc.shape, pose_of(state_.bodies[slot])), desc.is_static);
  return static_cast<int>(slot);
}

void Simulation::remove_body(int body) {
  const std::size_t i = std::size_t(body);
  // What rested on it falls: wake it (a plane's box is the whole half-space).
  wake_near(world_aabb(scene_->bodies[i].shape, pose_of(state_.bodies[i])));
  broad_phase_->remove(body);
  drop_pairs_of(body);
  const auto involves = [body](const auto& e) { return e.body_a == body || e.body_b == body; };
  std::size_t kept = 0;
  for (std::size_t c = 0; c < contacts_.size(); ++c) {
    if (involves(contacts_[c]))
      continue;
    contacts_[kept] = contacts_[c];
    if (c < penalty_springs_.size())
      penalty_springs_[kept] = penalty_springs_[c];
    ++kept;
  }
  contacts_.resize(kept);
  penalty_springs_.resize(std::min(penalty_springs_.size(), kept));
  std::erase_if(candidate_pairs_,
                [body](const ProxyPair& p) { return p.a == body || p.b == body; });
  adopt(model_->without_body(i));
  state_.bodies[i].velocity.setZero();
  state_.bodies[i].angular_velocity.setZero();
  state_.slow_time[i] = 0;
  state_.asleep[i] = 0;
  state_.substep_level[i] = 0;
  state_.substep_hold[i] = 0;
  force_[i].setZero();
  torque_[i].setZero();
  has_target_[i] = 0;
}

void Simulation::rebuild_broad_phase() {
  broad_phase_ = make_broad_phase(broad_phase_type_);
  bounds_stale_ = false;
  for (std::size_t i = 0; i < scene_->bodies.size(); ++i) {
    if (model_->is_removed(i))
      continue;
    const BodyDesc& d = scene_->bodies[i];
    broad_phase_->insert(static_cast<std::int32_t>(i),
                         world_aabb(d.shape, pose_of(state_.bodies[i])), d.is_static);
  }
}

// A kinematic body moves with the constant velocity that takes it to its target within the step
// (the target's rotation the short way round); without a target it keeps its velocity.
void Simulation::start_kinematic_motion(Real dt) {
  for (std::size_t k = 0; k < kinematic_bodies_.size(); ++k) {
    const std::size_t i = std::size_t(kinematic_bodies_[k]);
    BodyState& b = state_.bodies[i];
    kinematic_start_[k] = pose_of(b);
    if (has_target_[i] == 0)
      continue;
    const Transform& target = kinematic_target_[i];
    b.velocity = (target.translation - b.position) / dt;
    Quat turn = target.rotation * b.orientation.conjugate();
    if (turn.w() < 0)
      turn.coeffs() = -turn.coeffs();
    const Real sine = turn.vec().norm();
    const Real angle = 2 * std::atan2(sine, turn.w());
    b.angular_velocity = sine > 0 ? Vec3(turn.vec() * (angle / (sine * dt))) : Vec3::Zero();
  }
}

// Kinematic bodies at `fraction` of the step (exactly at their targets at its end), so that the
// solver's separations see them move through the substeps.
void Simulation::move_kinematic_bodies(Real fraction, Real dt) {
  for (std::size_t k = 0; k < kinematic_bodies_.size(); ++k) {
    const std::size_t i = std::size_t(kinematic_bodies_[k]);
    BodyState& b = state_.bodies[i];
    if (fraction >= 1 && has_target_[i] != 0) {
      b.position = kinematic_target_[i].translation;
      b.orientation = kinematic_target_[i].rotation;
      continue;
    }
    const Transform& start = kinematic_start_[k];
    const Real t = fraction * dt;
    b.position = start.translation + b.velocity * t;
    const Real speed = b.angular_velocity.norm();
    b.orientation =
        speed > 0
            ? (Quat(Eigen::AngleAxis<Real>(speed * t, b.angular_velocity / speed)) * start.rotation)
                  .normalized()
            : start.rotation;
  }
}

// One step, as docs/architecture.md tells it, for both solvers. Collision runs once; the solver
// then runs, group of islands by group, substeps of velocity integration, warm start and soft
// passes, position integration, relax passes and restitution (the soft step; the penalty solver
// iterates its springs instead and has no relax); continuous collision then stops fast bodies at
// their first time of impact (engine/continuous_collision.hpp), and the impulses are kept for
// the next step.
namespace {

// Throws NonFiniteStateError for the first body whose state a step left non-finite: a NaN
// carried on silently would fill every later row (13 comparisons a body, nothing next to a step).
void check_finite(const State& state, const Scene& scene, const std::vector<Transform>& start) {
  for (std::size_t i = 0; i < state.bodies.size(); ++i) {
    const BodyState& b = state.bodies[i];
    const char* what = !b.position.allFinite()               ? "position"
                       : !b.orientation.coeffs().allFinite() ? "orientation"
                       : !b.velocity.allFinite()             ? "velocity"
                       : !b.angular_velocity.allFinite()     ? "angular velocity"
                                                             : nullptr;
    if (what == nullptr)
      continue;
    std::string message = "step ";
    message += std::to_string(state.step);
    message += ": body '";
    message += scene.bodies[i].name;
    message += "' (index ";
    message += std::to_string(i);
    message += ") has a non-finite ";
    message += what;
    message += "; at the start of the step it was at position ";
    message += vector_text(start[i].translation);
    const Quat& q = start[i].rotation;
    message += ", orientation (w x y z) (";
    message += number_text(q.w());
    message += ", ";
    message += vector_text(q.vec()).substr(1);
    throw NonFiniteStateError(message);
  }
}

}  // namespace

void Simulation::step() {
  // Made at the first step, so that a batch's worlds, which borrow their thread's, hold none.
  if (!own_scratch_)
    own_scratch_ = std::make_unique<StepWorkspace>();
  step(*own_scratch_);
}

void Simulation::step(StepWorkspace& scratch) {
  struct Lent {
    StepWorkspace*& slot;
    ~Lent() { slot = nullptr; }  // returned even when the step throws
  } lent{scratch_};
  scratch_ = &scratch;
  scratch.solver.set_runner(runner_.get());
  const std::int64_t split_before = runner_->split_loops();
  runner_->run([this] { step_on_runner(); });
  last_step_.split_loops = runner_->split_loops() - split_before;
  check_finite(state_, *scene_, scratch_->shape_poses);
}

void Simulation::step_on_runner() {
  current_ = StepStatistics{};
  ticks_.begin();
  const WorldSettings& w = scene_->world;
  scratch_->shape_poses.resize(state_.bodies.size());
  scratch_->carries.resize(state_.bodies.size());
  // What a batch recorded for the world it steps next (prefetch_step_arrays), asked for a slice
  // after each stage and each substep rather than in one burst (collision/cache_prefetch.hpp);
  // nothing for a lone world.
  CachePrefetch& next_world = scratch_->next_world;
  constexpr std::size_t kLinesPerSlice = 48;
  current_.lines_asked_ahead = static_cast<std::int64_t>(next_world.pending_lines());
  start_kinematic_motion(w.dt);
  update_bounds(w.dt);
  next_world.issue(kLinesPerSlice);
  find_candidate_pairs();
  next_world.issue(kLinesPerSlice);
  collide_candidate_pairs();
  next_world.issue(kLinesPerSlice);
  wake_touched_islands();
  prepare_contacts();
  next_world.issue(kLinesPerSlice);
  for (int g = 0; g < static_cast<int>(group_settings_.size()); ++g) {
    const ContactSolverSettings& group = group_settings_[std::size_t(g)];
    for (int s = 0; s < group.substeps; ++s) {
      integrate_velocities(g, group.substep);
      solve_contacts(g);
      integrate_positions(g, group.substep);
      move_kinematic_bodies(Real(s + 1) / Real(group.substeps), w.dt);
      relax_contacts(g);
      next_world.issue(kLinesPerSlice);
    }
  }
  next_world.issue_all();
  move_kinematic_bodies(1, w.dt);
  for (const std::int32_t i : kinematic_bodies_)
    has_target_[std::size_t(i)] = 0;
  clear_loads();
  sweep_fast_bodies();
  finish_contacts();
  update_sleep(w.dt);

  bounds_stale_ = true;
  state_.step += 1;
  // Time is counted in steps, not summed, so that it does not drift by rounding.
  state_.time = static_cast<Real>(state_.step) * w.dt;
  ticks_.finish_into(current_);
  last_step_ = current_;
}

// Islands of this step's contact graph (static bodies excluded). An island with one awake body
// wakes whole; the pairs of sleeping islands (and their static supports) leave the solver, and
// most of them the narrow phase too (find_resting_bodies). Their warm-start impulses wait in
// State::sleeping_contacts (finish_contacts), and a woken island starts from them.
void Simulation::wake_touched_islands() {
  if (!scene_->world.sleeping)
    return;
  StageTimer timer(current_, ticks_, SolvePhase::islands_and_sleep);
  const std::size_t n = state_.bodies.size();
  Islands& islands = scratch_->islands;
  islands.reset(n);
  const Model& model = *model_;
  for (const PairContact& pc : contacts_) {
    if (!model.is_fixed(std::size_t(pc.body_a)) && !model.is_fixed(std::size_t(pc.body_b)))
      islands.join(pc.body_a, pc.body_b);
  }
  island_awake_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!model.is_fixed(i) && state_.asleep[i] == 0)
      island_awake_[islands.root(static_cast<std::int32_t>(i))] = 1;
  }
  // A moving kinematic body, or a field changing with time this step, wakes what it touches.
  for (const PairContact& pc : contacts_) {
    for (const auto& [k, other] :
         {std::pair{pc.body_a, pc.body_b}, std::pair{pc.body_b, pc.body_a}}) {
      const BodyState& kb = state_.bodies[std::size_t(k)];
      const bool moving = model.is_kinematic(std::size_t(k)) &&
                          (kb.velocity.squaredNorm() > 0 || kb.angular_velocity.squaredNorm() > 0);
      if ((moving || field_changing_now(k)) && !model.is_fixed(std::size_t(other)))
        island_awake_[islands.root(other)] = 1;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (state_.asleep[i] != 0 && island_awake_[islands.root(static_cast<std::int32_t>(i))]) {
      state_.asleep[i] = 0;
      state_.slow_time[i] = 0;
      sleepers_may_have_woken_ = true;
    }
  }
  const auto inactive = [&](std::int32_t b) { return out_of_solver(b); };
  // The impulses a woken pair slept with go back to warm-start it (finish_contacts put them
  // aside). Only a wake can make a pair active again, so without one there is nothing to look at.
  if (sleepers_may_have_woken_ && !state_.sleeping_contacts.empty()) {
    move_pairs_if(state_.sleeping_contacts, state_.contacts, [&](const CachedManifold& m) {
      return !inactive(m.body_a) || !inactive(m.body_b);
    });
  }
  sleepers_may_have_woken_ = false;
  std::size_t kept = 0;
  for (std::size_t c = 0; c < contacts_.size(); ++c) {
    if (inactive(contacts_[c].body_a) && inactive(contacts_[c].body_b))
      continue;
    contacts_[kept] = contacts_[c];
    penalty_springs_[kept] = penalty_springs_[c];
    ++kept;
  }
  contacts_.resize(kept);
  penalty_springs_.resize(kept);
}

// A body the solver leaves out: fixed (static or kinematic), or asleep. A pair of two such bodies
// is left out of the solve (wake_touched_islands) and its impulses set aside (finish_contacts).
bool Simulation::out_of_solver(std::int32_t body) const {
  return model_->is_fixed(std::size_t(body)) || state_.asleep[std::size_t(body)] != 0;
}

// A body is slow when |v| + |w| r is below the sleep speed; an island whose bodies have all
// been slow for the sleep time falls asleep at rest.
void Simulation::update_sleep(Real dt) {
  const WorldSettings& w = scene_->world;
  if (!w.sleeping)
    return;
  StageTimer timer(current_, ticks_, SolvePhase::islands_and_sleep);
  const std::size_t n = state_.bodies.size();
  const Model& model = *model_;
  Islands& islands = scratch_->islands;  // this step's (wake_touched_islands, choose_substeps)
  island_slow_time_.assign(n, std::numeric_limits<Real>::infinity());
  for (std::size_t i = 0; i < n; ++i) {
    if (model.is_fixed(i) || state_.asleep[i] != 0)
      continue;
    const BodyState& b = state_.bodies[i];
    const Real speed = b.velocity.norm() + b.angular_velocity.norm() * bounding_radii_[i];
    state_.slow_time[i] = speed < w.sleep_speed ? state_.slow_time[i] + dt : Real(0);
    Real& least = island_slow_time_[islands.root(static_cast<std::int32_t>(i))];
    least = std::min(least, state_.slow_time[i]);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (model.is_fixed(i) || state_.asleep[i] != 0)
      continue;
    if (island_slow_time_[islands.root(static_cast<std::int32_t>(i))] >= w.sleep_time) {
      state_.asleep[i] = 1;
      state_.bodies[i].velocity.setZero();
      state_.bodies[i].angular_velocity.setZero();
    }
  }
}

// Fast bodies are swept from their pose at the start of the step (the workspace's shape_poses, set
// by update_bounds) to where the solver put them; the stage is reported as run only in steps where
// a swept body had a candidate to be tested against.
void Simulation::sweep_fast_bodies() {
  if (!sweeps_)
    return;
  const bool ran_before = current_.ran[static_cast<int>(Stage::continuous)];
  StageTimer timer(current_, ticks_, Stage::continuous);
  const ContinuousCollisionCounts counts = continuous_->run(
      *model_, scratch_->shape_poses, *broad_phase_, state_.bodies, masses_, *runner_);
  current_.swept_bodies += counts.swept_bodies;
  current_.ccd_candidate_pairs += counts.candidate_pairs;
  current_.stopped_bodies += counts.stopped_bodies;
  current_.impact_rounds += counts.impact_rounds;
  if (counts.toi_queries == 0)
    timer.had_nothing_to_do(ran_before);  // nothing near a swept body: no sweep was needed
}

void Simulation::integrate_velocities(int group, Real h) {
  StageTimer timer(current_, ticks_, Stage::integrate_velocities);
  VelocityIntegration in;
  in.states = state_.bodies.data();
  in.masses = masses_.data();
  in.carries = scratch_->carries.data();
  in.gravity = scene_->world.gravity;
  in.loaded = loaded_.data();
  in.forces = force_.data();
  in.h = h;
  for_each_awake_chunk(group, [&](const std::int32_t* bodies, int count) {
    tumble::integrate_velocities(in, bodies, count);
    // A body with a torque turns after the gyroscopic update, through the world inverse inertia
    // at the substep's orientation.
    for (int k = 0; k < count; ++k) {
      const std::size_t i = std::size_t(bodies[k]);
      if (loaded_[i] == 0 || !(torque_[i].squaredNorm() > 0))
        continue;
      BodyState& b = state_.bodies[i];
      const Mat3 r = b.orientation.toRotationMatrix();
      b.angular_velocity += r * (masses_[i].inverse_inertia * (r.transpose() * torque_[i])) * h;
    }
  });
}

// Calls update(bodies, count) with the awake bodies of substep group `group` (its list holds no
// others: choose_substeps), a chunk of the group's list at a time, on the runner's threads (each
// call touches its bodies alone; a run on one thread gets the whole list at once).
template <class Update>
void Simulation::for_each_awake_chunk(int group, const Update& update) {
  const std::int32_t first = group_body_start_[std::size_t(group)];
  const std::int32_t* list = group_bodies_.data() + first;
  runner_->for_chunks(group_body_start_[std::size_t(group) + 1] - first, kBodiesPerChunk,
                      [&](std::int32_t begin, std::int32_t end) {
                        update(list + begin, static_cast<int>(end - begin));
                      });
}

// Each dynamic body's box grows by how far its surface can move in this step (speed, plus what
// gravity adds within the step, plus angular speed times its bounding radius) and half the
// contact margin, so a pair that can touch within the step is always a candidate. With
// continuous collision the growth stops at the body's sweep threshold: a body that moves farther
// is swept over its whole motion by sweep_fast_bodies, so growing its box along its path would
// only pair it with everything it passes (thousands of speculative contacts in
// scenes/high_speed.yaml) for nothing the sweep does not already catch.
void Simulation::update_bounds(Real dt) {
  StageTimer timer(current_, ticks_, Stage::bounds);
  const Real half_margin = Real(0.5) * scene_->world.contact_margin;
  const Real gravity_speed = scene_->world.gravity.norm() * dt;
  for (std::size_t i = 0; i < state_.bodies.size(); ++i) {
    const BodyState& b = state_.bodies[i];
    scratch_->shape_poses[i] = pose_of(b);
    if (model_->is_static(i)) {
      speculative_margin_[i] = half_margin;
      continue;
    }
    Real reach =
        dt * (b.velocity.norm() + gravity_speed + b.angular_velocity.norm() * bounding_radii_[i]);
    // A kinematic body is not swept (nothing stops it), so its box covers its whole motion.
    if (sweeps_ && !model_->is_kinematic(i))
      reach = std::min(reach, continuous_->sweep_threshold(i));
    speculative_margin_[i] = half_margin + reach;
    broad_phase_->update(static_cast<std::int32_t>(i),
                         world_aabb(scene_->bodies[i].shape, scratch_->shape_poses[i])
                             .inflated(speculative_margin_[i]));
  }
}

void Simulation::find_candidate_pairs() {
  StageTimer timer(current_, ticks_, Stage::broad_phase);
  broad_phase_->find_pairs(candidate_pairs_);
  current_.candidate_pairs += static_cast<std::int64_t>(candidate_pairs_.size());
  // Thousands of bodies in one place pair each with each; the narrow phase would then exhaust the
  // memory. Stop with the reason instead.
  const auto bodies = static_cast<std::int64_t>(state_.bodies.size());
  const std::int64_t limit = std::max(scene_limits::kMinCandidatePairLimit,
                                      scene_limits::kMaxCandidatePairsPerBody * bodies);
  const auto pairs = static_cast<std::int64_t>(candidate_pairs_.size());
  if (pairs > limit) {
    std::string message = "step ";
    message += std::to_string(state_.step);
    message += ": the broad phase found ";
    message += std::to_string(pairs);
    message += " candidate pairs among ";
    message += std::to_string(bodies);
    message += " bodies, more than the limit of ";
    message += std::to_string(limit);
    message += " (64 per body, at least 1,000,000): bodies overlap en masse; spread them out";
    throw StepLimitError(message);
  }
}

// The lists of sleeping pairs and of warm-start impulses hold at most one entry per candidate
// pair: given that room while anything sleeps, they do not grow (allocate) when an island falls
// asleep or wakes later on, only when the candidate pairs themselves outgrow their room.
void Simulation::reserve_sleep_lists() {
  if (std::find_if(state_.asleep.begin(), state_.asleep.end(),
                   [](std::uint8_t a) { return a != 0; }) == state_.asleep.end())
    return;
  const std::size_t room = candidate_pairs_.capacity();
  state_.resting_touches.reserve(room);
  scratch_->next_resting_touches.reserve(room);
  state_.sleeping_contacts.reserve(room);
  state_.contacts.reserve(room);
}

// Which bodies' pairs the narrow phase takes from State::resting_touches this step (rest_skips_);
// false when none. A body rests when it is static (its shape not changing with time) or has been
// asleep since before the last narrow phase (asleep == 2): its pose and its box are the ones that
// phase saw, so a pair of two resting bodies would give what it gave then. Such a pair is not
// collided again unless its island (through the resting touches) may wake: a candidate pair of
// one of its bodies with a body that does not rest puts the whole island through the narrow
// phase, so that an island woken in this step has all its contacts in this step's solve, as Bullet
// keeps the manifolds of the pairs it stops colliding (btCollisionDispatcher::needsCollision).
bool Simulation::find_resting_bodies() {
  const std::size_t n = state_.bodies.size();
  bool any = false;
  for (std::size_t i = 0; i < n && !any; ++i)
    any = state_.asleep[i] == 2;
  if (!any)
    return false;
  const auto& bodies = scene_->bodies;
  const auto rests = [&](std::int32_t b) {
    const std::size_t i = std::size_t(b);
    return bodies[i].is_static ? field_changes_[i] == 0 : state_.asleep[i] == 2;
  };
  rest_islands_.reset(n);
  for (const RestingTouch& t : state_.resting_touches) {
    if (!bodies[std::size_t(t.body_a)].is_static && !bodies[std::size_t(t.body_b)].is_static &&
        rests(t.body_a) && rests(t.body_b))
      rest_islands_.join(t.body_a, t.body_b);
  }
  rest_disturbed_.assign(n, 0);
  for (const ProxyPair& pair : candidate_pairs_) {
    const bool a_rests = rests(pair.a);
    if (a_rests == rests(pair.b))
      continue;  // both rest (left out unless disturbed), or neither (collided)
    const std::int32_t resting = a_rests ? pair.a : pair.b;
    if (!bodies[std::size_t(resting)].is_static)
      rest_disturbed_[std::size_t(rest_islands_.root(resting))] = 1;
  }
  rest_skips_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto b = static_cast<std::int32_t>(i);
    rest_skips_[i] = rests(b) && (bodies[i].is_static ||
                                  rest_disturbed_[std::size_t(rest_islands_.root(b))] == 0);
  }
  return true;
}

// Narrow phase. A pair whose relative pose moved less than the recycling tolerances since its
// manifold was computed reuses it (collision/narrow_phase/manifold_recycling.hpp); the others
// collide: box-box pairs, the most common in box scenes, through the batched path all at once
// (collide_box_pairs answers each as collide() does), sphere-sphere pairs through the sphere
// batch (collide_sphere_pairs_dense, collide()'s bits), the rest pair by pair, in order.
void Simulation::collide_candidate_pairs() {
  const std::vector<Transform>& shape_poses = scratch_->shape_poses;
  StageTimer timer(current_, ticks_, Stage::narrow_phase);
  // The pass that sorts the candidates (recycling the kept manifolds as it goes) and the queries
  // of the rest are timed apart, so that recycled and recomputed pairs have each their cost.
  const std::uint64_t sort_start = read_ticks();
  contacts_.clear();
  penalty_springs_.clear();
  const auto& bodies = scene_->bodies;
  const auto& materials = scene_->materials;
  const WorldSettings& w = scene_->world;
  const auto margin_of = [&](const ProxyPair& pair) {
    return speculative_margin_[pair.a] + speculative_margin_[pair.b];
  };
  // Types, bounds and materials from the model's tables, not the bodies' descriptions (a miss
  // per body in a batch of small worlds).
  const Model& model = *model_;
  const auto is_box_pair = [&](const ProxyPair& pair) {
    return model.shape_type(pair.a) == ShapeType::box && model.shape_type(pair.b) == ShapeType::box;
  };
  const auto is_sphere_pair = [&](const ProxyPair& pair) {
    return model.shape_type(pair.a) == ShapeType::sphere &&
           model.shape_type(pair.b) == ShapeType::sphere;
  };
  const auto smaller_radius = [&](const ProxyPair& pair) {
    return std::min(model.is_bounded(pair.a) ? bounding_radii_[pair.a] : bounding_radii_[pair.b],
                    model.is_bounded(pair.b) ? bounding_radii_[pair.b] : bounding_radii_[pair.a]);
  };
  // What each candidate's manifold comes from: the kept manifold (its index in
  // state_.manifolds), or a fresh query (-1).
  const std::size_t n = candidate_pairs_.size();
  scratch_->candidate_manifolds.resize(n);
  scratch_->candidate_kept.assign(n, -1);
  scratch_->candidate_axis.assign(n, kNoBoxAxis);
  scratch_->candidate_uses_gjk.assign(n, 0);
  scratch_->candidate_is_hull_pair.assign(n, 0);
  if (scratch_->candidate_hull_axis.size() < n)
    scratch_->candidate_hull_axis.resize(n);
  if (scratch_->candidate_gjk.size() < n)
    scratch_->candidate_gjk.resize(n);
  scratch_->box_queries.clear();
  scratch_->box_candidates.clear();
  scratch_->sphere_x.clear();
  scratch_->sphere_y.clear();
  scratch_->sphere_z.clear();
  scratch_->sphere_radius.clear();
  scratch_->sphere_pairs.clear();
  scratch_->sphere_candidates.clear();
  scratch_->other_candidates.clear();
  const std::vector<RecyclableManifold>& kept = state_.manifolds;
  static const Real recycle_half_sine = std::sin(Real(0.5) * kRecycleAngle);
  const std::vector<CachedBoxAxis>& axes = state_.box_axes;
  const std::vector<PairGjkCache>& gjk_kept = state_.gjk_caches;
  const std::vector<CachedHullAxis>& hull_kept = state_.hull_axes;
  scratch_->candidate_route.resize(n);
  if (w.sleeping)
    reserve_sleep_lists();
  const bool some_rest = w.sleeping && find_resting_bodies();
  const std::vector<RestingTouch>& touches = state_.resting_touches;
  // First each candidate on its own, on the threads: recycled, kept apart by last step's box axis,
  // or which query answers it (with its cached axis or warm start). A chunk finds its first entry
  // of each kept list by bisection, then walks (the candidates and every kept list are sorted by
  // pair).
  runner_->for_chunks(
      static_cast<std::int32_t>(n), kSortedPairsPerChunk,
      [&](std::int32_t begin, std::int32_t end) {
        const ProxyPair& first = candidate_pairs_[std::size_t(begin)];
        const auto start_of = [&](const auto& list) {
          return std::size_t(
              std::lower_bound(list.begin(), list.end(), first,
                               [](const auto& e, const ProxyPair& p) {
                                 return std::pair{e.body_a, e.body_b} < std::pair{p.a, p.b};
                               }) -
              list.begin());
        };
        std::size_t cursor = start_of(kept);
        std::size_t axis_cursor = start_of(axes);
        std::size_t gjk_cursor = start_of(gjk_kept);
        std::size_t hull_cursor = start_of(hull_kept);
        std::size_t touch_cursor = some_rest ? start_of(touches) : 0;
        for (std::size_t i = std::size_t(begin); i < std::size_t(end); ++i) {
          const ProxyPair& pair = candidate_pairs_[i];
          std::uint8_t& route = scratch_->candidate_route[i];
          // Two bodies of infinite mass (kinematic against static or kinematic) ignore each
          // other.
          if (model_->is_fixed(std::size_t(pair.a)) && model_->is_fixed(std::size_t(pair.b))) {
            scratch_->candidate_manifolds[i].count = 0;
            route = kRouteDone;
            continue;
          }
          // Two resting bodies (find_resting_bodies): whether they touched, and their caches, as
          // the last narrow phase left them. The solver would drop their contact anyway.
          if (some_rest && rest_skips_[std::size_t(pair.a)] != 0 &&
              rest_skips_[std::size_t(pair.b)] != 0) {
            scratch_->candidate_manifolds[i].count = 0;
            route = kRouteDone | kRouteResting;
            if (find_pair(touches, touch_cursor, pair.a, pair.b) != nullptr)
              route |= kRouteRestingTouch;
            if (const RecyclableManifold* manifold = find_pair(kept, cursor, pair.a, pair.b))
              scratch_->candidate_kept[i] = static_cast<std::int32_t>(manifold - kept.data());
            if (const CachedBoxAxis* cached = find_pair(axes, axis_cursor, pair.a, pair.b))
              scratch_->candidate_axis[i] = cached->axis;
            if (const PairGjkCache* cached = find_pair(gjk_kept, gjk_cursor, pair.a, pair.b)) {
              scratch_->candidate_uses_gjk[i] = 1;
              scratch_->candidate_gjk[i] = cached->cache;
            }
            if (const CachedHullAxis* cached = find_pair(hull_kept, hull_cursor, pair.a, pair.b)) {
              scratch_->candidate_is_hull_pair[i] = 1;
              scratch_->candidate_hull_axis[i] = cached->axis;
            }
            continue;
          }
          const RecyclableManifold* manifold = find_pair(kept, cursor, pair.a, pair.b);
          if (w.contact_recycling && flat_shape_[pair.a] && flat_shape_[pair.b] &&
              manifold != nullptr &&
              recycle_within_half_sine(*manifold, shape_poses[pair.a], shape_poses[pair.b],
                                       kRecycleDistance * smaller_radius(pair), recycle_half_sine,
                                       scratch_->candidate_manifolds[i])) {
            scratch_->candidate_kept[i] = static_cast<std::int32_t>(manifold - kept.data());
            route = kRouteDone;
            continue;
          }
          if (is_box_pair(pair)) {
            route = kRouteBoxQuery;
            // The axis that kept the boxes apart last step, if it still does: no contact, and
            // no query (collision/narrow_phase/box_axis_cache.hpp).
            if (const CachedBoxAxis* cached = find_pair(axes, axis_cursor, pair.a, pair.b)) {
              route |= kRouteAxisTried;
              const std::uint8_t axis = cached->axis;
              if (box_axis_separates(bodies[pair.a].shape.half_extents, shape_poses[pair.a],
                                     bodies[pair.b].shape.half_extents, shape_poses[pair.b], axis,
                                     margin_of(pair))) {
                scratch_->candidate_axis[i] = axis;
                scratch_->candidate_manifolds[i].count = 0;
                route = kRouteDone | kRouteAxisTried | kRouteAxisHit;
              }
            }
          } else if (is_sphere_pair(pair)) {
            route = kRouteSphere;
          } else {
            route = kRouteOther;
            if (model.shape_type(pair.a) == ShapeType::hull &&
                model.shape_type(pair.b) == ShapeType::hull) {
              // Last step's separating direction of a hull pair, tried in the query loop below.
              const CachedHullAxis* cached = find_pair(hull_kept, hull_cursor, pair.a, pair.b);
              scratch_->candidate_is_hull_pair[i] = 1;
              scratch_->candidate_hull_axis[i] = cached != nullptr ? cached->axis : HullAxis{};
              route |= cached != nullptr ? kRouteAxisTried : 0;
            } else if (collides_by_gjk(model.shape_type(pair.a), model.shape_type(pair.b))) {
              // Last step's separating axis of a pair GJK answers, if it has one.
              const PairGjkCache* cached = find_pair(gjk_kept, gjk_cursor, pair.a, pair.b);
              scratch_->candidate_uses_gjk[i] = 1;
              scratch_->candidate_gjk[i] = cached != nullptr ? cached->cache : GjkCache{};
              route |= cached != nullptr ? kRouteWarm : 0;
            }
          }
        }
      });
  // Then, in pair order, the queries' lists.
  std::int64_t axis_tries = 0, axis_hits = 0, gjk_warm = 0, hull_tries = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t route = scratch_->candidate_route[i];
    const ProxyPair& pair = candidate_pairs_[i];
    switch (route & kRouteKind) {
      case kRouteDone:
        axis_tries += (route & kRouteAxisTried) != 0;
        axis_hits += (route & kRouteAxisHit) != 0;
        break;
      case kRouteBoxQuery:
        axis_tries += (route & kRouteAxisTried) != 0;
        scratch_->box_queries.push_back({bodies[pair.a].shape.half_extents, shape_poses[pair.a],
                                         bodies[pair.b].shape.half_extents, shape_poses[pair.b],
                                         margin_of(pair)});
        scratch_->box_candidates.push_back(static_cast<std::int32_t>(i));
        break;
      case kRouteSphere: {
        for (const std::int32_t body : {pair.a, pair.b}) {
          const Vec3& c = shape_poses[std::size_t(body)].translation;
          scratch_->sphere_x.push_back(c.x());
          scratch_->sphere_y.push_back(c.y());
          scratch_->sphere_z.push_back(c.z());
          scratch_->sphere_radius.push_back(bodies[std::size_t(body)].shape.radius);
        }
        const auto first = static_cast<std::int32_t>(scratch_->sphere_candidates.size() * 2);
        scratch_->sphere_pairs.push_back({first, first + 1});
        scratch_->sphere_candidates.push_back(static_cast<std::int32_t>(i));
        break;
      }
      default:
        hull_tries += (route & kRouteAxisTried) != 0;
        gjk_warm += (route & kRouteWarm) != 0;
        scratch_->other_candidates.push_back(static_cast<std::int32_t>(i));
        break;
    }
  }
  const std::uint64_t query_start = read_ticks();
  scratch_->hull_hits.assign(scratch_->other_candidates.size(), 0);
  if (scratch_->box_manifolds.size() < scratch_->box_queries.size())
    scratch_->box_manifolds.resize(scratch_->box_queries.size());
  scratch_->box_axes_found.resize(scratch_->box_queries.size());
  // Each query's answer is its own (collide_box_pairs answers a pair as collide() does, in any
  // batch), so the batch splits over the threads.
  runner_->for_chunks(
      static_cast<std::int32_t>(scratch_->box_queries.size()), kBoxPairsPerChunk,
      [&](std::int32_t begin, std::int32_t end) {
        const auto count = std::size_t(end - begin);
        collide_box_pairs(std::span(scratch_->box_queries).subspan(std::size_t(begin), count),
                          std::span(scratch_->box_manifolds).subspan(std::size_t(begin), count));
        // The pairs found apart keep the axis that separates them most.
        for (std::size_t k = std::size_t(begin); k < std::size_t(end); ++k) {
          const BoxPairQuery& q = scratch_->box_queries[k];
          scratch_->box_axes_found[k] =
              scratch_->box_manifolds[k].count == 0
                  ? best_separating_box_axis(q.half_a, q.pose_a, q.half_b, q.pose_b, q.margin)
                  : kNoBoxAxis;
        }
      });
  runner_->for_chunks(
      static_cast<std::int32_t>(scratch_->other_candidates.size()), kPairsPerChunk,
      [&](std::int32_t begin, std::int32_t end) {
        for (std::int32_t k = begin; k < end; ++k) {
          const std::size_t i = std::size_t(scratch_->other_candidates[std::size_t(k)]);
          const ProxyPair& pair = candidate_pairs_[i];
          if (scratch_->candidate_is_hull_pair[i] != 0) {
            // Apart along last step's direction: no contact, no query.
            // Otherwise the query, and a direction for next step if apart.
            const ConvexHull& hull_a = *bodies[pair.a].shape.hull;
            const ConvexHull& hull_b = *bodies[pair.b].shape.hull;
            HullAxis& axis = scratch_->candidate_hull_axis[i];
            if (hull_axis_separates(hull_a, shape_poses[pair.a], hull_b, shape_poses[pair.b], axis,
                                    margin_of(pair))) {
              scratch_->candidate_manifolds[i] = Manifold{};
              scratch_->hull_hits[std::size_t(k)] = 1;
              continue;
            }
            collide(bodies[pair.a].shape, shape_poses[pair.a], bodies[pair.b].shape,
                    shape_poses[pair.b], margin_of(pair), scratch_->candidate_manifolds[i]);
            axis = scratch_->candidate_manifolds[i].count == 0
                       ? separating_hull_axis(hull_a, shape_poses[pair.a], hull_b,
                                              shape_poses[pair.b], margin_of(pair))
                       : HullAxis{};
          } else if (scratch_->candidate_uses_gjk[i] != 0) {
            collide(bodies[pair.a].shape, shape_poses[pair.a], bodies[pair.b].shape,
                    shape_poses[pair.b], margin_of(pair), scratch_->candidate_manifolds[i],
                    scratch_->candidate_gjk[i]);
          } else if (field_changes_[std::size_t(pair.a)] | field_changes_[std::size_t(pair.b)]) {
            Shape timed_a, timed_b;
            collide(shape_now(pair.a, timed_a), shape_poses[pair.a], shape_now(pair.b, timed_b),
                    shape_poses[pair.b], margin_of(pair), scratch_->candidate_manifolds[i]);
          } else {
            collide(bodies[pair.a].shape, shape_poses[pair.a], bodies[pair.b].shape,
                    shape_poses[pair.b], margin_of(pair), scratch_->candidate_manifolds[i]);
          }
        }
      });
  for (std::size_t k = 0; k < scratch_->box_candidates.size(); ++k) {
    scratch_->candidate_manifolds[std::size_t(scratch_->box_candidates[k])] =
        scratch_->box_manifolds[k];
    scratch_->candidate_axis[std::size_t(scratch_->box_candidates[k])] =
        scratch_->box_axes_found[k];
  }
  // Sphere-sphere pairs through the vectorised batch, which gives collide()'s bits; each pair
  // keeps its own margin.
  if (!scratch_->sphere_pairs.empty()) {
    const std::size_t m = scratch_->sphere_pairs.size();
    scratch_->sphere_out.resize(7 * m);
    const SphereContactArrays out{
        scratch_->sphere_out.data(),         scratch_->sphere_out.data() + m,
        scratch_->sphere_out.data() + 2 * m, scratch_->sphere_out.data() + 3 * m,
        scratch_->sphere_out.data() + 4 * m, scratch_->sphere_out.data() + 5 * m,
        scratch_->sphere_out.data() + 6 * m};
    collide_sphere_pairs_dense({scratch_->sphere_x.data(), scratch_->sphere_y.data(),
                                scratch_->sphere_z.data(), scratch_->sphere_radius.data()},
                               scratch_->sphere_pairs, 0, out);
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t i = std::size_t(scratch_->sphere_candidates[k]);
      Manifold& manifold = scratch_->candidate_manifolds[i];
      manifold.count = 0;
      if (!(out.depth[k] >= -margin_of(candidate_pairs_[i])))
        continue;
      manifold.normal = Vec3(out.normal_x[k], out.normal_y[k], out.normal_z[k]);
      manifold.add(Vec3(out.x[k], out.y[k], out.z[k]), out.depth[k],
                   {detail::feature::kSphere, detail::feature::kSphere});
    }
  }

  const std::uint64_t query_end = read_ticks();
  ticks_.recycle += query_start - sort_start;
  ticks_.recompute += query_end - query_start;
  scratch_->next_manifolds.clear();
  scratch_->next_box_axes.clear();
  scratch_->next_gjk_caches.clear();
  scratch_->next_hull_axes.clear();
  scratch_->next_resting_touches.clear();
  // A body that can rest: static (its shape not changing), or asleep.
  const auto inactive = [&](std::int32_t b) {
    const std::size_t k = std::size_t(b);
    return model.is_static(k) ? field_changes_[k] == 0 : state_.asleep[k] != 0;
  };
  std::int64_t recycled = 0, resting = 0;
  std::int64_t sdf_refined = 0, sdf_refine_capped = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const ProxyPair& pair = candidate_pairs_[i];
    if (scratch_->candidate_axis[i] != kNoBoxAxis)
      scratch_->next_box_axes.push_back({pair.a, pair.b, scratch_->candidate_axis[i]});
    if (scratch_->candidate_uses_gjk[i] != 0 && scratch_->candidate_gjk[i].valid)
      scratch_->next_gjk_caches.push_back({pair.a, pair.b, scratch_->candidate_gjk[i]});
    if (scratch_->candidate_is_hull_pair[i] != 0 &&
        scratch_->candidate_hull_axis[i].direction_in_a.squaredNorm() > 0)
      scratch_->next_hull_axes.push_back({pair.a, pair.b, scratch_->candidate_hull_axis[i]});
    Manifold& manifold = scratch_->candidate_manifolds[i];
    const std::uint8_t route = scratch_->candidate_route[i];
    if ((route & kRouteResting) != 0) {
      ++resting;
      if (scratch_->candidate_kept[i] >= 0)
        scratch_->next_manifolds.push_back(kept[std::size_t(scratch_->candidate_kept[i])]);
      if ((route & kRouteRestingTouch) != 0)
        scratch_->next_resting_touches.push_back({pair.a, pair.b});
      continue;
    }
    if (w.sleeping && manifold.count > 0 && inactive(pair.a) && inactive(pair.b))
      scratch_->next_resting_touches.push_back({pair.a, pair.b});
    if (scratch_->candidate_kept[i] >= 0) {
      ++recycled;
      scratch_->next_manifolds.push_back(kept[std::size_t(scratch_->candidate_kept[i])]);
    } else {
      if (manifold.count > 0 && w.contact_recycling && flat_shape_[pair.a] && flat_shape_[pair.b]) {
        scratch_->next_manifolds.push_back(
            make_recyclable(pair.a, pair.b, manifold, shape_poses[pair.a], shape_poses[pair.b]));
      }
    }
    if (manifold.count == 0)
      continue;
    if (scratch_->candidate_kept[i] < 0 && (model.shape_type(pair.a) == ShapeType::sdf ||
                                            model.shape_type(pair.b) == ShapeType::sdf)) {
      sdf_refined += manifold.refined;
      sdf_refine_capped += manifold.refine_capped;
    }
    const int material_a = model.material(pair.a);
    const int material_b = model.material(pair.b);
    const Material& ma = materials[std::size_t(material_a)];
    const Material& mb = materials[std::size_t(material_b)];
    // Made whole and then copied into the list (a default PairContact, filled and then copied,
    // wrote each contact three times). A twentieth of the smaller body's size: far below the
    // spacing of distinct contact points, far above the drift of one point between steps.
    contacts_.push_back(PairContact{pair.a, pair.b, model.friction(material_a, material_b),
                                    model.restitution(material_a, material_b),
                                    Real(0.05) * smaller_radius(pair), manifold});
    // The softer material sets the spring, the more damped one the damper: a rubber ball on
    // steel deforms like rubber.
    penalty_springs_.push_back(
        PenaltyPair{std::min(ma.stiffness, mb.stiffness), std::max(ma.damping, mb.damping)});
  }
  state_.manifolds.swap(scratch_->next_manifolds);
  state_.box_axes.swap(scratch_->next_box_axes);
  state_.gjk_caches.swap(scratch_->next_gjk_caches);
  state_.hull_axes.swap(scratch_->next_hull_axes);
  if (w.sleeping) {
    state_.resting_touches.swap(scratch_->next_resting_touches);
    // Every sleeping body has now been through a narrow phase where it rests.
    for (std::uint8_t& asleep : state_.asleep)
      asleep = asleep != 0 ? 2 : 0;
  }
  std::int64_t hull_hits = 0;
  for (std::size_t k = 0; k < scratch_->other_candidates.size(); ++k)
    hull_hits += scratch_->hull_hits[k];
  current_.axis_cache_tries += hull_tries;
  current_.axis_cache_hits += hull_hits;
  current_.gjk_warm_starts += gjk_warm;
  current_.sdf_refinements += sdf_refined;
  current_.sdf_refinements_capped += sdf_refine_capped;
  current_.axis_cache_tries += axis_tries;
  current_.axis_cache_hits += axis_hits;
  current_.touching_pairs += static_cast<std::int64_t>(contacts_.size());
  current_.recycled_pairs += recycled;
  current_.resting_pairs += resting;
  current_.recomputed_pairs += static_cast<std::int64_t>(n) - recycled - resting;
}

void Simulation::prepare_contacts() {
  const WorldSettings& w = scene_->world;
  if (w.solver == SolverType::penalty) {
    // The penalty solver runs every moving body in one group, at penalty_substeps().
    {
      StageTimer timer(current_, ticks_, SolvePhase::islands_and_sleep);
      group_settings_.resize(1);
      group_settings_[0].substeps = penalty_substeps_;
      group_settings_[0].substep = w.dt / penalty_substeps_;
      group_bodies_.clear();
      for (std::size_t i = 0; i < state_.bodies.size(); ++i) {
        if (!model_->is_fixed(i) && state_.asleep[i] == 0)
          group_bodies_.push_back(static_cast<std::int32_t>(i));
      }
      group_body_start_.assign({0, static_cast<std::int32_t>(group_bodies_.size())});
      current_.max_substeps = penalty_substeps_;
    }
    StageTimer timer(current_, ticks_, SolvePhase::prepare);
    PenaltySolverSettings settings;
    settings.substep = group_settings_[0].substep;
    settings.min_iterations = w.iterations;
    settings.max_iterations = std::max(w.iterations, kMaxPenaltyIterations);
    penalty_solver_.prepare(contacts_, penalty_springs_, state_.contacts, state_.bodies, masses_,
                            settings);
    current_.contact_points += penalty_solver_.point_count();
    return;
  }
  {
    StageTimer timer(current_, ticks_, SolvePhase::prepare);
    scratch_->solver.build(contacts_, state_.contacts, state_.bodies, masses_, w.dt, w.gravity);
  }
  {
    StageTimer timer(current_, ticks_, SolvePhase::islands_and_sleep);
    choose_substeps();
  }
  StageTimer timer(current_, ticks_, SolvePhase::prepare);
  scratch_->solver.pack(group_of_contact_, group_settings_, model_->kinematic_flags());
  current_.contact_points += scratch_->solver.point_count();
}

// Substeps per island (docs/architecture.md). A soft contact of angular frequency omega settles
// load / (m_eff omega^2) deep under its load; omega grows with the substep rate (an eighth of it
// between moving bodies, a quarter against a static one), so an island whose warm-started load
// would sink a contact deeper than the sag tolerance doubles its substeps until it does not, up
// to max_substeps. Islands with the same count form one group, solved together.
void Simulation::choose_substeps() {
  StepWorkspace& work = *scratch_;
  Islands& islands = work.islands;
  std::vector<std::int32_t>& root_of = work.root_of;
  std::vector<std::int32_t>& substeps_of_root = work.substeps_of_root;
  std::vector<std::int32_t>& group_of_root = work.group_of_root;
  std::vector<std::int32_t>& contacts_wanting = work.contacts_wanting;
  std::vector<std::uint8_t>& level_needed = work.level_needed;
  std::vector<std::uint8_t>& level_before = work.level_before;
  std::vector<std::uint8_t>& hold_before = work.hold_before;
  std::vector<std::uint8_t>& weighed_level = work.weighed_level;
  std::vector<Real>& island_mass = work.island_mass;
  const WorldSettings& w = scene_->world;
  const std::size_t n = state_.bodies.size();
  const int base = std::max(1, w.substeps);
  const int cap = std::max(base, w.max_substeps);
  int top_level = 0;
  while ((base << (top_level + 1)) <= cap)
    ++top_level;
  islands.reset(n);
  for (const PairContact& pc : contacts_) {
    if (!model_->is_fixed(std::size_t(pc.body_a)) && !model_->is_fixed(std::size_t(pc.body_b)))
      islands.join(pc.body_a, pc.body_b);
  }
  // Each body's island root, found once: the loops below ask it several times per body.
  root_of.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    root_of[i] = islands.root(std::int32_t(i));
  // Per island root: the level its loads need now, the level it had, and its mass (a contact in
  // an island at rest carries at most the island's weight; more is an impact, which needs no
  // stiffer spring to hold it up).
  level_needed.assign(n, 0);
  level_before.assign(n, 0);
  hold_before.assign(n, 0);
  island_mass.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (model_->is_fixed(i))
      continue;
    const std::size_t root = std::size_t(root_of[i]);
    level_before[root] = std::max(level_before[root], state_.substep_level[i]);
    hold_before[root] = std::max(hold_before[root], state_.substep_hold[i]);
    if (masses_[i].inverse_mass > 0)
      island_mass[root] += 1 / masses_[i].inverse_mass;
  }
  // Per island root and level L (row root * levels): how many of its contacts need L or more
  // (column 0 counts every contact of the island), and the level the weights on its contacts
  // need.
  const std::size_t levels = std::size_t(top_level) + 1;
  contacts_wanting.assign(n * levels, 0);
  weighed_level.assign(n, 0);
  const std::span<const ContactLoad> load = scratch_->solver.contact_loads();
  if (!w.contact_hertz) {
    constexpr Real kPi = std::numbers::pi_v<Real>;
    const Real gravity = w.gravity.norm();
    const auto level_for = [&](Real needed_substeps) {
      int level = 0;
      while (level < top_level && Real(base << level) < needed_substeps)
        ++level;
      return level;
    };
    for (std::size_t c = 0; c < contacts_.size(); ++c) {
      const PairContact& pc = contacts_[c];
      const bool a_static = model_->is_fixed(std::size_t(pc.body_a));
      const bool b_static = model_->is_fixed(std::size_t(pc.body_b));
      const std::int32_t moving = a_static ? pc.body_b : pc.body_a;
      const std::size_t root = std::size_t(root_of[std::size_t(moving)]);
      ++contacts_wanting[root * levels];
      const Real radius = std::min(a_static ? bounding_radii_[std::size_t(pc.body_b)]
                                            : bounding_radii_[std::size_t(pc.body_a)],
                                   b_static ? bounding_radii_[std::size_t(pc.body_a)]
                                            : bounding_radii_[std::size_t(pc.body_b)]);
      const Real tolerance = w.sag_tolerance * radius;
      if (!(tolerance > 0))
        continue;
      // What the contact carried last step counts only while the pair rests (its points close or
      // part slower than the restitution threshold), and then at most the island's weight: more
      // is an impact, which a stiffer spring need not hold up.
      const BodyState& sa = state_.bodies[std::size_t(pc.body_a)];
      const BodyState& sb = state_.bodies[std::size_t(pc.body_b)];
      const Vec3& p = pc.manifold.points[0].position;
      const Real approach =
          pc.manifold.normal.dot(sa.velocity + sa.angular_velocity.cross(p - sa.position) -
                                 sb.velocity - sb.angular_velocity.cross(p - sb.position));
      const bool resting = std::abs(approach) <= w.restitution_threshold;
      const Real at_rest = gravity * island_mass[root] * load[c].inverse_effective_mass;
      const Real warm = resting ? std::min(load[c].warm, at_rest) : Real(0);
      // omega = 2 pi (substeps / dt) / 8 between moving bodies, / 4 against a static one.
      const Real per_substep = (a_static || b_static ? 2 : 4) * w.dt / kPi;
      const int weighed = level_for(per_substep * std::sqrt(load[c].weight / tolerance));
      weighed_level[root] = std::max(weighed_level[root], std::uint8_t(weighed));
      // The same level again when the warm start carries no more than the weight (most resting
      // contacts), without its square root.
      const int wanted =
          warm <= load[c].weight
              ? weighed
              : level_for(per_substep * std::sqrt(std::max(load[c].weight, warm) / tolerance));
      for (int level = 1; level <= wanted; ++level)
        ++contacts_wanting[root * levels + std::size_t(level)];
    }
  }
  // An island takes the level that all its contacts but one in kSagOutliers find stiff enough
  // (all of them in an island of fewer than kSagOutliers contacts): in a pile of thousands a few
  // contacts always carry a passing spike of their warm-started loads. The weight of a body on
  // another is no spike, so the contact that needs the most for it counts wherever it is (a
  // heavy box on a light one in a large island).
  constexpr std::int32_t kSagOutliers = 100;
  for (std::size_t r = 0; r < n; ++r) {
    const std::int32_t* wanting = &contacts_wanting[r * levels];
    const std::int32_t enough = 1 + wanting[0] / kSagOutliers;
    std::uint8_t wanted = 0;
    for (std::size_t level = 1; level < levels; ++level) {
      if (wanting[level] >= enough)
        wanted = std::uint8_t(level);
    }
    level_needed[r] = std::max(wanted, weighed_level[r]);
  }
  // Up at once; down one level at a time, and only after kSubstepHold steps of needing less, so
  // that a load near a boundary does not switch the spring's stiffness back and forth (each
  // switch up pushes out the softer spring's sag, and that energy comes back as motion).
  constexpr std::uint8_t kSubstepHold = 30;
  for (std::size_t i = 0; i < n; ++i) {
    if (root_of[i] != std::int32_t(i))
      continue;
    std::uint8_t& level = level_needed[i];
    std::uint8_t& hold = hold_before[i];
    if (level >= level_before[i]) {
      hold = level > 0 ? kSubstepHold : 0;
    } else if (hold > 0) {
      level = level_before[i];
      --hold;
    } else {
      level = std::uint8_t(level_before[i] - 1);
      hold = level > 0 ? kSubstepHold : 0;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t root = std::size_t(root_of[i]);
    state_.substep_level[i] = model_->is_fixed(i) ? 0 : level_needed[root];
    state_.substep_hold[i] = model_->is_fixed(i) ? 0 : hold_before[root];
  }
  substeps_of_root.assign(n, base);
  std::uint8_t top_needed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    substeps_of_root[i] = base << level_needed[i];
    if (root_of[i] == std::int32_t(i))
      top_needed = std::max(top_needed, level_needed[i]);
  }

  // Groups: one per distinct count, ascending from the base (group 0, always there).
  group_settings_.clear();
  const auto group_of = [&](int substeps) {
    for (std::size_t g = 0; g < group_settings_.size(); ++g)
      if (group_settings_[g].substeps == substeps)
        return static_cast<std::int32_t>(g);
    ContactSolverSettings settings;
    settings.substeps = substeps;
    settings.substep = w.dt / substeps;
    settings.penetration_slop = w.penetration_slop;
    const Real rate = Real(1) / settings.substep;
    if (w.contact_hertz) {
      settings.contact_hertz = std::min(*w.contact_hertz, Real(0.25) * rate);
      settings.static_contact_hertz = std::min(2 * *w.contact_hertz, Real(0.25) * rate);
    } else {
      settings.contact_hertz = Real(0.125) * rate;
      settings.static_contact_hertz = Real(0.25) * rate;
    }
    settings.contact_damping_ratio = w.contact_damping_ratio;
    settings.max_push_velocity = w.max_push_velocity;
    settings.restitution_threshold = w.restitution_threshold;
    group_settings_.push_back(settings);
    return static_cast<std::int32_t>(group_settings_.size() - 1);
  };
  group_of(base);
  int most = base;
  // Visit the counts in ascending order so that group numbers do not depend on island order.
  // No root needs more than top_needed levels, so no larger count has islands.
  for (int substeps = 2 * base; substeps <= cap && substeps <= (base << top_needed);
       substeps *= 2) {
    for (std::size_t i = 0; i < n; ++i) {
      if (substeps_of_root[i] == substeps && root_of[i] == std::int32_t(i)) {
        group_of(substeps);
        most = substeps;
        break;
      }
    }
  }
  // Each root's group, looked up once per root (group_of searches the groups).
  group_of_root.assign(n, -1);
  const auto body_group = [&](std::int32_t body) {
    const std::size_t root = std::size_t(root_of[std::size_t(body)]);
    std::int32_t& group = group_of_root[root];
    if (group < 0)
      group = group_of(substeps_of_root[root]);
    return group;
  };
  group_of_contact_.resize(contacts_.size());
  for (std::size_t c = 0; c < contacts_.size(); ++c) {
    const PairContact& pc = contacts_[c];
    group_of_contact_[c] =
        body_group(model_->is_fixed(std::size_t(pc.body_a)) ? pc.body_b : pc.body_a);
  }
  const std::size_t groups = group_settings_.size();
  group_body_start_.assign(groups + 1, 0);
  // The awake moving bodies only: nothing wakes or falls asleep during the substeps, so the lists
  // the integration walks every substep are filtered here once.
  for (std::size_t i = 0; i < n; ++i) {
    if (!model_->is_fixed(i) && state_.asleep[i] == 0)
      ++group_body_start_[std::size_t(body_group(std::int32_t(i))) + 1];
  }
  for (std::size_t g = 0; g < groups; ++g)
    group_body_start_[g + 1] += group_body_start_[g];
  group_bodies_.resize(std::size_t(group_body_start_[groups]));
  std::vector<std::int32_t>& cursor = work.group_fill;
  cursor.assign(group_body_start_.begin(), group_body_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    if (!model_->is_fixed(i) && state_.asleep[i] == 0) {
      const std::size_t g = std::size_t(body_group(std::int32_t(i)));
      group_bodies_[std::size_t(cursor[g]++)] = std::int32_t(i);
    }
  }
  current_.max_substeps = std::max(current_.max_substeps, most);
}

// Before the bodies move: the warm start and the pairwise impacts, then the soft passes (the
// penalty solver: its passes until the springs converge).
void Simulation::solve_contacts(int group) {
  const WorldSettings& w = scene_->world;
  if (w.solver == SolverType::penalty) {
    StageTimer timer(current_, ticks_, SolvePhase::soft_passes);
    penalty_solver_.begin_substep(state_.bodies);
    const PenaltySolverSettings& settings = penalty_solver_.settings();
    for (int it = 0; it < settings.max_iterations; ++it) {
      const Real change = penalty_solver_.solve(state_.bodies);
      current_.solver_iterations += 1;
      current_.point_passes += penalty_solver_.point_count();
      if (it + 1 >= settings.min_iterations && change <= settings.tolerance)
        break;
    }
    return;
  }
  {
    StageTimer timer(current_, ticks_, SolvePhase::warm_start);
    scratch_->solver.load_velocities(group, state_.bodies);
    // Impacts first, on the velocities the bodies arrive with: after the warm start they would
    // reflect the approach the cached impulses add, which the passes may take back but the
    // bounce keeps (a sphere squeezed between a box and a capsule left at 22 m/s from 16).
    scratch_->solver.resolve_impacts(group);
    scratch_->solver.warm_start(group);
  }
  StageTimer timer(current_, ticks_, SolvePhase::soft_passes);
  for (int it = 0; it < w.iterations; ++it)
    scratch_->solver.solve(group, /*use_bias=*/true);
  scratch_->solver.store_velocities(group, state_.bodies);
  current_.solver_iterations += w.iterations;
  current_.point_passes += std::int64_t(w.iterations) * scratch_->solver.group_point_count(group);
}

// After the bodies moved: the separations, the relax passes that take out the push-out speed,
// and restitution. The penalty solver has none of these (the spring is the physics, not a
// correction to remove, and the damper sets the bounce).
void Simulation::relax_contacts(int group) {
  const WorldSettings& w = scene_->world;
  if (w.solver == SolverType::penalty)
    return;
  {
    StageTimer timer(current_, ticks_, SolvePhase::relax_passes);
    scratch_->solver.update_separations(group, state_.bodies);
    scratch_->solver.load_velocities(group, state_.bodies);
    for (int it = 0; it < w.relax_iterations; ++it)
      scratch_->solver.solve(group, /*use_bias=*/false);
    current_.solver_iterations += w.relax_iterations;
    current_.point_passes +=
        std::int64_t(w.relax_iterations) * scratch_->solver.group_point_count(group);
  }
  StageTimer timer(current_, ticks_, SolvePhase::restitution);
  scratch_->solver.apply_restitution(group);
  scratch_->solver.store_velocities(group, state_.bodies);
}

void Simulation::finish_contacts() {
  StageTimer timer(current_, ticks_, SolvePhase::store_impulses);
  // The solver stores the impulses of the pairs it solved; those of pairs that now sleep (left
  // out by wake_touched_islands) are put aside until their island wakes, as Box2D's sleeping
  // islands keep their constraints and Bullet's persistent manifolds their applied impulses.
  if (scene_->world.sleeping) {
    move_pairs_if(state_.contacts, state_.sleeping_contacts, [&](const CachedManifold& m) {
      return out_of_solver(m.body_a) && out_of_solver(m.body_b);
    });
  }
  if (scene_->world.solver == SolverType::penalty)
    penalty_solver_.store(state_.contacts);
  else
    scratch_->solver.store(state_.contacts);
}

void Simulation::integrate_positions(int group, Real h) {
  StageTimer timer(current_, ticks_, Stage::integrate_positions);
  PositionIntegration in;
  in.states = state_.bodies.data();
  in.carries = scratch_->carries.data();
  in.h = h;
  for_each_awake_chunk(group, [&](const std::int32_t* bodies, int count) {
    tumble::integrate_positions(in, bodies, count);
  });
}

// The arrays every step of a world of small bodies reads, in the order it first reads them.
void Simulation::prefetch_step_arrays(CachePrefetch& requests) const {
  requests.record_each(state_.bodies, loaded_, has_target_, speculative_margin_);
  if (broad_phase_)
    broad_phase_->prefetch(requests);
  requests.record_each(candidate_pairs_, state_.manifolds, contacts_, state_.contacts,
                       state_.slow_time, state_.asleep, state_.substep_level, state_.substep_hold,
                       group_body_start_, group_bodies_, group_of_contact_);
  if (sweeps_)
    continuous_->prefetch(requests);
}

WorldMemory Simulation::memory() const {
  WorldMemory m;
  const auto bytes = [](const auto& v) {
    return v.capacity() * sizeof(typename std::decay_t<decltype(v)>::value_type);
  };
  m.body_bytes = bytes(state_.bodies) + bytes(state_.slow_time) + bytes(state_.asleep) +
                 bytes(state_.substep_level) + bytes(state_.substep_hold) +
                 bytes(model_->masses()) + bytes(model_->bounding_radii()) +
                 bytes(speculative_margin_) + bytes(group_bodies_) + bytes(island_awake_) +
                 bytes(island_slow_time_) + bytes(rest_disturbed_) + bytes(rest_skips_);
  m.contact_bytes = bytes(state_.contacts) + bytes(state_.sleeping_contacts) +
                    bytes(state_.resting_touches) + bytes(state_.manifolds) +
                    bytes(state_.box_axes) + bytes(state_.gjk_caches) + bytes(state_.hull_axes) +
                    bytes(candidate_pairs_) + bytes(contacts_) + bytes(penalty_springs_) +
                    bytes(group_of_contact_);
  m.scratch_bytes = own_scratch_ ? own_scratch_->bytes_reserved() : 0;
  return m;
}

void Simulation::contact_forces(std::span<Real> xyz, std::span<std::int32_t> counts) const {
  std::fill(xyz.begin(), xyz.end(), Real(0));
  std::fill(counts.begin(), counts.end(), 0);
  const Real per_second = report_impulse_scale() / scene_->world.dt;
  const std::vector<CachedManifold>& impulses = state_.contacts;
  std::size_t cursor = 0;
  for (const PairContact& pc : contacts_) {
    const CachedManifold* kept = find_pair(impulses, cursor, pc.body_a, pc.body_b);
    ++counts[std::size_t(pc.body_a)];
    ++counts[std::size_t(pc.body_b)];
    if (kept == nullptr)
      continue;
    Vec3 total = Vec3::Zero();
    for (int k = 0; k < kept->count; ++k) {
      const CachedContactPoint& p = kept->points[std::size_t(k)];
      total += pc.manifold.normal * p.normal_impulse + p.friction_impulse;
    }
    // The impulse pushes A along the normal and B against it.
    for (int c = 0; c < 3; ++c) {
      xyz[3 * std::size_t(pc.body_a) + std::size_t(c)] += total[c] * per_second;
      xyz[3 * std::size_t(pc.body_b) + std::size_t(c)] -= total[c] * per_second;
    }
  }
}

// A body's shape as the narrow phase and ray casts see it now: its own, or for a field that
// changes with time a copy (shared data: a few reference counts, no allocation) evaluated at the
// world's time.
const Shape& Simulation::shape_now(std::int32_t body, Shape& storage) const {
  const Shape& shape = scene_->bodies[std::size_t(body)].shape;
  if (field_changes_[std::size_t(body)] == 0)
    return shape;
  storage = shape;
  storage.field_time = state_.time;
  return storage;
}

// Whether body k's field changes between this step's start and end.
bool Simulation::field_changing_now(std::int32_t k) const {
  if (field_changes_[std::size_t(k)] == 0)
    return false;
  const SdfShape& field = *scene_->bodies[std::size_t(k)].shape.sdf;
  return state_.time + scene_->world.dt > field.changes_from() &&
         state_.time < field.changes_until();
}

Simulation::RayResult Simulation::ray_cast(const Vec3& origin, const Vec3& direction,
                                           Real max_distance) {
  if (bounds_stale_) {
    // The next step sets every moving body's box again, and the broad phase's pairs do not
    // depend on the boxes it held before, so this changes no result.
    for (std::size_t i = 0; i < state_.bodies.size(); ++i) {
      if (scene_->bodies[i].is_static)
        continue;
      broad_phase_->update(static_cast<std::int32_t>(i),
                           world_aabb(scene_->bodies[i].shape, pose_of(state_.bodies[i])));
    }
    bounds_stale_ = false;
  }
  std::vector<std::int32_t>& candidates = query_scratch_;
  broad_phase_->ray_cast(origin, direction, max_distance, candidates);
  RayResult best;
  best.distance = max_distance;
  const Vec3 delta = direction * max_distance;
  for (const std::int32_t id : candidates) {
    const std::size_t i = std::size_t(id);
    Shape timed;
    const ShapeRayHit hit =
        tumble::ray_cast(shape_now(id, timed), pose_of(state_.bodies[i]), origin, delta);
    if (!hit.hit)
      continue;
    const Real distance = hit.fraction * max_distance;
    // Ties go to the lower slot (candidates ascend), so the answer does not depend on order.
    if (best.body < 0 || distance < best.distance) {
      best.body = id;
      best.distance = distance;
      best.normal = hit.normal;
    }
  }
  return best;
}

Real Simulation::kinetic_energy() const {
  Real e = 0;
  for (std::size_t i = 0; i < state_.bodies.size(); ++i) {
    e += tumble::kinetic_energy(state_.bodies[i], masses_[i]);
  }
  return e;
}

Real Simulation::potential_energy() const {
  Real e = 0;
  for (std::size_t i = 0; i < state_.bodies.size(); ++i) {
    if (masses_[i].inverse_mass == 0)
      continue;
    e -= scene_->world.gravity.dot(state_.bodies[i].position) / masses_[i].inverse_mass;
  }
  return e;
}

}  // namespace tumble
