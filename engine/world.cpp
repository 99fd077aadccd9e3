#include "engine/world.hpp"

#include <chrono>
#include <cmath>

#include "collision/broad_phase_factory.hpp"
#include "collision/narrow_phase.hpp"
#include "engine/broad_phase_choice.hpp"

namespace tumble {
namespace {

class StageTimer {
 public:
  StageTimer(StepStatistics& stats, Stage stage)
      : stats_(stats), stage_(static_cast<int>(stage)), start_(std::chrono::steady_clock::now()) {
    stats_.ran[stage_] = true;
  }
  ~StageTimer() {
    const auto end = std::chrono::steady_clock::now();
    stats_.seconds[stage_] += std::chrono::duration<double>(end - start_).count();
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  StepStatistics& stats_;
  int stage_;
  std::chrono::steady_clock::time_point start_;
};

Transform pose_of(const BodyState& b) {
  return {b.position, b.orientation};
}

}  // namespace

World::World(std::shared_ptr<const Scene> scene) : scene_(std::move(scene)) {
  const std::size_t n = scene_->bodies.size();
  masses_.reserve(n);
  bounding_radii_.reserve(n);
  for (const BodyDesc& d : scene_->bodies) {
    masses_.push_back(BodyMass::make(d.mass, d.inertia, d.is_static));
    bounding_radii_.push_back(d.shape.is_bounded() ? bounding_radius(d.shape) : Real(0));
  }
  carries_.resize(n);
  speculative_margin_.resize(n);
  shape_poses_.resize(n);
  broad_phase_type_ = choose_broad_phase(scene_->world.broadphase, *scene_);
  set_state(initial_state(*scene_));
}

void World::set_state(const State& state) {
  state_ = state;
  rebuild_broad_phase();
}

void World::teleport(int body, const Vec3& position, const Quat& orientation) {
  BodyState& b = state_.bodies[std::size_t(body)];
  b.position = position;
  b.orientation = orientation.normalized();
  std::erase_if(state_.contacts,
                [body](const CachedManifold& m) { return m.body_a == body || m.body_b == body; });
  rebuild_broad_phase();
}

void World::rebuild_broad_phase() {
  broad_phase_ = make_broad_phase(broad_phase_type_);
  for (std::size_t i = 0; i < scene_->bodies.size(); ++i) {
    const BodyDesc& d = scene_->bodies[i];
    broad_phase_->insert(static_cast<std::int32_t>(i),
                         world_aabb(d.shape, pose_of(state_.bodies[i])), d.is_static);
  }
}

// One step, as design.md outlines it. Collision runs once; the solver then runs substeps of
// velocity integration, warm start, soft solve, position integration, relax and restitution
// (the soft step of docs/architecture.md); the impulses are then kept for the next step. Continuous
// collision detection is not part of the pipeline yet, so that stage is reported as not run.
void World::step() {
  current_ = StepStatistics{};
  const WorldSettings& w = scene_->world;
  const int substeps = std::max(1, w.substeps);
  const Real h = w.dt / substeps;

  update_bounds(w.dt);
  find_candidate_pairs();
  collide_candidate_pairs();
  prepare_contacts(h);
  for (int s = 0; s < substeps; ++s) {
    integrate_velocities(h);
    solve_contacts(/*use_bias=*/true, w.iterations);
    integrate_positions(h);
    solve_contacts(/*use_bias=*/false, w.relax_iterations);
    apply_restitution();
  }
  finish_contacts();

  state_.step += 1;
  // Time is counted in steps, not summed, so that it does not drift by rounding.
  state_.time = static_cast<Real>(state_.step) * w.dt;
  current_.state_hash = state_hash(state_);
  last_step_ = current_;
}

void World::integrate_velocities(Real h) {
  StageTimer timer(current_, Stage::integrate_velocities);
  const Vec3 g = scene_->world.gravity;
  for (std::size_t i = 0; i < state_.bodies.size(); ++i) {
    integrate_velocity(state_.bodies[i], masses_[i], g, h, carries_[i]);
  }
}

// Each dynamic body's box grows by how far its surface can move in this step (speed, plus what
// gravity adds within the step, plus angular speed times its bounding radius) and half the
// contact margin, so a pair that can touch within the step is always a candidate.
void World::update_bounds(Real dt) {
  StageTimer timer(current_, Stage::bounds);
  const Real half_margin = Real(0.5) * scene_->world.contact_margin;
  const Real gravity_speed = scene_->world.gravity.norm() * dt;
  for (std::size_t i = 0; i < state_.bodies.size(); ++i) {
    const BodyState& b = state_.bodies[i];
    shape_poses_[i] = pose_of(b);
    if (scene_->bodies[i].is_static) {
      speculative_margin_[i] = half_margin;
      continue;
    }
    const Real reach =
        dt * (b.velocity.norm() + gravity_speed + b.angular_velocity.norm() * bounding_radii_[i]);
    speculative_margin_[i] = half_margin + reach;
    broad_phase_->update(
        static_cast<std::int32_t>(i),
        world_aabb(scene_->bodies[i].shape, shape_poses_[i]).inflated(speculative_margin_[i]));
  }
}

void World::find_candidate_pairs() {
  StageTimer timer(current_, Stage::broad_phase);
  broad_phase_->find_pairs(candidate_pairs_);
  current_.candidate_pairs += static_cast<std::int64_t>(candidate_pairs_.size());
}

void World::collide_candidate_pairs() {
  StageTimer timer(current_, Stage::narrow_phase);
  contacts_.clear();
  const auto& bodies = scene_->bodies;
  const auto& materials = scene_->materials;
  for (const ProxyPair& pair : candidate_pairs_) {
    const BodyDesc& a = bodies[pair.a];
    const BodyDesc& b = bodies[pair.b];
    PairContact pc;
    const Real margin = speculative_margin_[pair.a] + speculative_margin_[pair.b];
    if (collide(a.shape, shape_poses_[pair.a], b.shape, shape_poses_[pair.b], margin,
                pc.manifold) == 0) {
      continue;
    }
    pc.body_a = pair.a;
    pc.body_b = pair.b;
    const Material& ma = materials[a.material];
    const Material& mb = materials[b.material];
    pc.friction = std::sqrt(ma.friction * mb.friction);
    pc.restitution = std::max(ma.restitution, mb.restitution);
    // A twentieth of the smaller body's size: far below the spacing of distinct contact
    // points, far above the drift of one point between steps.
    pc.match_distance =
        Real(0.05) *
        std::min(a.shape.is_bounded() ? bounding_radii_[pair.a] : bounding_radii_[pair.b],
                 b.shape.is_bounded() ? bounding_radii_[pair.b] : bounding_radii_[pair.a]);
    contacts_.push_back(pc);
  }
  current_.touching_pairs += static_cast<std::int64_t>(contacts_.size());
}

void World::prepare_contacts(Real h) {
  StageTimer timer(current_, Stage::solve);
  const WorldSettings& w = scene_->world;
  ContactSolverSettings settings;
  settings.substep = h;
  settings.penetration_slop = w.penetration_slop;
  // A spring stiffer than a quarter of the substep rate is not resolved by the substeps.
  settings.contact_hertz = std::min(w.contact_hertz, Real(0.25) / h);
  settings.contact_damping_ratio = w.contact_damping_ratio;
  settings.max_push_velocity = w.max_push_velocity;
  settings.restitution_threshold = w.restitution_threshold;
  solver_.prepare(contacts_, state_.contacts, state_.bodies, masses_, settings);
  current_.contact_points += solver_.point_count();
}

void World::solve_contacts(bool use_bias, int passes) {
  StageTimer timer(current_, Stage::solve);
  if (use_bias)
    solver_.warm_start(state_.bodies);
  for (int it = 0; it < passes; ++it)
    solver_.solve(state_.bodies, use_bias);
  current_.solver_iterations += passes;
}

void World::apply_restitution() {
  StageTimer timer(current_, Stage::solve);
  solver_.apply_restitution(state_.bodies);
}

void World::finish_contacts() {
  StageTimer timer(current_, Stage::solve);
  solver_.store(state_.contacts);
}

void World::integrate_positions(Real h) {
  StageTimer timer(current_, Stage::integrate_positions);
  for (std::size_t i = 0; i < state_.bodies.size(); ++i) {
    if (scene_->bodies[i].is_static)
      continue;
    integrate_position(state_.bodies[i], carries_[i], h);
  }
}

Real World::kinetic_energy() const {
  Real e = 0;
  for (std::size_t i = 0; i < state_.bodies.size(); ++i) {
    e += tumble::kinetic_energy(state_.bodies[i], masses_[i]);
  }
  return e;
}

Real World::potential_energy() const {
  Real e = 0;
  for (std::size_t i = 0; i < state_.bodies.size(); ++i) {
    if (masses_[i].inverse_mass == 0)
      continue;
    e -= scene_->world.gravity.dot(state_.bodies[i].position) / masses_[i].inverse_mass;
  }
  return e;
}

}  // namespace tumble
