// tumble::World (include/tumble/world.hpp): checks every call's ids and values, then hands it to
// the Simulation behind it.
#include "tumble/world.hpp"

#include <charconv>
#include <cmath>
#include <string>
#include <utility>

#include "engine/kinematic_target_check.hpp"
#include "engine/model.hpp"
#include "engine/number_text.hpp"
#include "engine/scene_check.hpp"
#include "engine/simulation.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

// Forces, impulses and velocities beyond these are typos or blow-ups, not physics; they would
// overflow a step long before they meant anything.
constexpr Real kMaxLoad = 1e15;  // N, N m, N s
constexpr Real kMaxSpeed = 1e6;  // m/s, rad/s
constexpr Real kMaxCoordinate = 1e9;

}  // namespace

World::World(std::shared_ptr<const Scene> scene) : World(compile(std::move(scene))) {}

World::World(std::shared_ptr<const Model> model) {
  if (!model)
    throw Error("tumble::World: the model is null");
  simulation_ = std::make_unique<Simulation>(std::move(model));
  generation_.assign(simulation_->scene().bodies.size(), 0);
}

World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

const Scene& World::scene() const {
  return live().scene();
}

Simulation& World::live() const {
  if (!simulation_)
    throw Error("tumble::World: this world was moved from");
  return *simulation_;
}

std::int32_t World::checked(BodyId id) const {
  live();
  if (!is_valid(id)) {
    const bool in_range = id.index >= 0 && std::size_t(id.index) < generation_.size();
    throw Error("tumble::World: body id {" + std::to_string(id.index) + ", " +
                std::to_string(id.generation) + "} " +
                (in_range ? "names a body that was removed" : "is not a body of this world"));
  }
  return id.index;
}

std::int32_t World::checked_dynamic(BodyId id, std::string_view call) const {
  const std::int32_t i = checked(id);
  if (live().model().is_fixed(std::size_t(i)))
    throw Error("tumble::World::" + std::string(call) + ": body '" + name(id) + "' is " +
                (live().model().is_kinematic(std::size_t(i)) ? "kinematic" : "static") +
                "; only dynamic bodies take forces and impulses");
  return i;
}

bool World::is_valid(BodyId id) const {
  return simulation_ && id.index >= 0 && std::size_t(id.index) < generation_.size() &&
         generation_[std::size_t(id.index)] == id.generation &&
         !simulation_->model().is_removed(std::size_t(id.index));
}

BodyId World::body(std::string_view name) const {
  if (const std::optional<BodyId> id = find_body(name))
    return *id;
  throw Error("tumble::World::body: no body is named '" + std::string(name) + "'");
}

std::optional<BodyId> World::find_body(std::string_view name) const {
  if (name.empty())
    return std::nullopt;
  const int i = live().scene().find_body(name);
  if (i < 0 || live().model().is_removed(std::size_t(i)))
    return std::nullopt;
  return BodyId{i, generation_[std::size_t(i)]};
}

std::string World::name(BodyId id) const {
  return live().scene().bodies[std::size_t(checked(id))].name;
}

std::vector<BodyId> World::bodies() const {
  std::vector<BodyId> ids;
  for (std::size_t i = 0; i < generation_.size(); ++i) {
    if (!live().model().is_removed(i))
      ids.push_back({static_cast<std::int32_t>(i), generation_[i]});
  }
  return ids;
}

int World::body_count() const {
  return static_cast<int>(generation_.size() - live().model().removed_count());
}

BodyId World::add_body(const BodyDesc& desc) {
  // The last step's reports are kept as they were: the change drops cached impulses.
  refresh_reports();
  const Scene& scene = live().scene();
  std::size_t slot = scene.bodies.size();
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    if (live().model().is_removed(i)) {
      slot = i;
      break;
    }
  }
  check_body(scene, desc, slot);
  if (!desc.name.empty() && find_body(desc.name))
    throw SceneError(scene.source.empty() ? "scene" : scene.source, 0, 0,
                     "bodies[" + std::to_string(slot) + "].name",
                     "duplicate body name '" + desc.name + "'");
  const int added = live().add_body(desc);
  if (std::size_t(added) >= generation_.size())
    generation_.resize(std::size_t(added) + 1, 0);
  return {added, generation_[std::size_t(added)]};
}

void World::remove_body(BodyId id) {
  const std::int32_t i = checked(id);
  // The last step's reports are kept as they were: the change drops cached impulses.
  refresh_reports();
  live().remove_body(i);
  ++generation_[std::size_t(i)];
}

void World::add_force(BodyId id, const Vec3& force) {
  const std::int32_t i = checked_dynamic(id, "add_force");
  if (!(force.allFinite() && force.cwiseAbs().maxCoeff() <= kMaxLoad))
    throw Error("tumble::World::add_force: body '" + name(id) + "': force " + vector_text(force) +
                " N is not finite or beyond 1e15");
  live().add_force(i, force);
}

void World::add_torque(BodyId id, const Vec3& torque) {
  const std::int32_t i = checked_dynamic(id, "add_torque");
  if (!(torque.allFinite() && torque.cwiseAbs().maxCoeff() <= kMaxLoad))
    throw Error("tumble::World::add_torque: body '" + name(id) + "': torque " +
                vector_text(torque) + " N m is not finite or beyond 1e15");
  live().add_torque(i, torque);
}

void World::add_force_at(BodyId id, const Vec3& force, const Vec3& world_point) {
  const std::int32_t i = checked_dynamic(id, "add_force_at");
  if (!(force.allFinite() && force.cwiseAbs().maxCoeff() <= kMaxLoad))
    throw Error("tumble::World::add_force_at: body '" + name(id) + "': force " +
                vector_text(force) + " N is not finite or beyond 1e15");
  if (!(world_point.allFinite() && world_point.cwiseAbs().maxCoeff() <= kMaxCoordinate))
    throw Error("tumble::World::add_force_at: body '" + name(id) + "': point " +
                vector_text(world_point) + " m is not finite or beyond 1e9");
  const Vec3 lever = world_point - live().state().bodies[std::size_t(i)].position;
  live().add_force(i, force);
  live().add_torque(i, lever.cross(force));
}

void World::apply_impulse(BodyId id, const Vec3& impulse, const Vec3& world_point) {
  const std::int32_t i = checked_dynamic(id, "apply_impulse");
  if (!(impulse.allFinite() && impulse.cwiseAbs().maxCoeff() <= kMaxLoad))
    throw Error("tumble::World::apply_impulse: body '" + name(id) + "': impulse " +
                vector_text(impulse) + " N s is not finite or beyond 1e15");
  if (!(world_point.allFinite() && world_point.cwiseAbs().maxCoeff() <= kMaxCoordinate))
    throw Error("tumble::World::apply_impulse: body '" + name(id) + "': point " +
                vector_text(world_point) + " m is not finite or beyond 1e9");
  live().apply_impulse(i, impulse, world_point);
}

void World::set_velocity(BodyId id, const Vec3& linear, const Vec3& angular) {
  const std::int32_t i = checked(id);
  if (live().scene().bodies[std::size_t(i)].is_static)
    throw Error("tumble::World::set_velocity: body '" + name(id) +
                "' is static; make it kinematic to move it");
  if (!(linear.allFinite() && linear.cwiseAbs().maxCoeff() <= kMaxSpeed))
    throw Error("tumble::World::set_velocity: body '" + name(id) + "': velocity " +
                vector_text(linear) + " m/s is not finite or beyond 1e6");
  if (!(angular.allFinite() && angular.cwiseAbs().maxCoeff() <= kMaxSpeed))
    throw Error("tumble::World::set_velocity: body '" + name(id) + "': angular velocity " +
                vector_text(angular) + " rad/s is not finite or beyond 1e6");
  live().set_velocity(i, linear, angular);
}

void World::set_pose(BodyId id, const Vec3& position, const Quat& orientation) {
  // The last step's reports are kept as they were: the change drops cached impulses.
  refresh_reports();
  const std::int32_t i = checked(id);
  if (!(position.allFinite() && position.cwiseAbs().maxCoeff() <= kMaxCoordinate))
    throw Error("tumble::World::set_pose: body '" + name(id) + "': position " +
                vector_text(position) + " m is not finite or beyond 1e9");
  if (!(orientation.coeffs().allFinite() && orientation.norm() > 1e-9))
    throw Error("tumble::World::set_pose: body '" + name(id) +
                "': the orientation is not a finite, non-zero quaternion");
  live().teleport(i, position, orientation);
}

void World::set_kinematic_target(BodyId id, const Vec3& position, const Quat& orientation) {
  const std::int32_t i = checked(id);
  if (!live().model().is_kinematic(std::size_t(i)))
    throw Error("tumble::World::set_kinematic_target: body '" + name(id) + "' is " +
                (live().scene().bodies[std::size_t(i)].is_static ? "static" : "dynamic") +
                ", not kinematic (kinematic: true in the scene, or BodyDesc::kinematic)");
  const std::string problem = kinematic_target_problem(
      live().state().bodies[std::size_t(i)], position, orientation, live().scene().world.dt);
  if (!problem.empty())
    throw Error("tumble::World::set_kinematic_target: body '" + name(id) + "': " + problem);
  live().set_kinematic_target(i, position, orientation);
}

void World::step() {
  live().step();
}

void World::step(int n) {
  if (n < 0)
    throw Error("tumble::World::step: the step count " + std::to_string(n) + " is negative");
  for (int k = 0; k < n; ++k)
    live().step();
}

void World::reset() {
  live().reset();
  reports_step_ = -1;
}

void World::reset(std::shared_ptr<const Model> model) {
  live().reset(std::move(model));
  reports_step_ = -1;
}

void World::set_threads(int threads) {
  if (threads > 1024)
    throw Error("tumble::World::set_threads: " + std::to_string(threads) +
                " threads; at most 1024");
  live().set_threads(threads);
}

int World::threads() const {
  return live().threads();
}

BodyState World::body_state(BodyId id) const {
  return live().state().bodies[std::size_t(checked(id))];
}

Real World::time() const {
  return live().state().time;
}

std::int64_t World::step_count() const {
  return live().state().step;
}

// The reports of the last step, built on first request: each touching pair's manifold with the
// impulses the solver kept for it (both lists are sorted by pair).
void World::refresh_reports() const {
  const std::int64_t step = live().state().step;
  if (reports_step_ == step)
    return;
  reports_step_ = step;
  reports_.clear();
  const std::span<const PairContact> contacts = live().contacts();
  const std::vector<CachedManifold>& impulses = live().state().contacts;
  const Real scale = live().report_impulse_scale();
  std::size_t cursor = 0;
  for (const PairContact& pc : contacts) {
    ContactReport r;
    r.body_a = {pc.body_a, generation_[std::size_t(pc.body_a)]};
    r.body_b = {pc.body_b, generation_[std::size_t(pc.body_b)]};
    r.normal = pc.manifold.normal;
    r.point_count = pc.manifold.count;
    while (cursor < impulses.size() && std::pair{impulses[cursor].body_a, impulses[cursor].body_b} <
                                           std::pair{pc.body_a, pc.body_b})
      ++cursor;
    const CachedManifold* kept = cursor < impulses.size() && impulses[cursor].body_a == pc.body_a &&
                                         impulses[cursor].body_b == pc.body_b
                                     ? &impulses[cursor]
                                     : nullptr;
    for (int k = 0; k < pc.manifold.count; ++k) {
      ContactPointReport& p = r.points[std::size_t(k)];
      p.position = pc.manifold.points[std::size_t(k)].position;
      p.depth = pc.manifold.points[std::size_t(k)].depth;
      if (kept == nullptr)
        continue;
      // The solver keeps a manifold's points in its own order (by feature key); find this one's.
      const std::uint32_t key = pc.manifold.points[std::size_t(k)].feature.key();
      for (int j = 0; j < kept->count; ++j) {
        if (kept->points[std::size_t(j)].feature != key)
          continue;
        p.normal_impulse = kept->points[std::size_t(j)].normal_impulse * scale;
        p.friction_impulse = kept->points[std::size_t(j)].friction_impulse * scale;
        break;
      }
    }
    reports_.push_back(r);
  }
}

std::span<const ContactReport> World::contact_reports() const {
  refresh_reports();
  return reports_;
}

std::optional<RayHit> World::ray_cast(const Vec3& origin, const Vec3& direction,
                                      Real max_distance) const {
  if (!(origin.allFinite() && origin.cwiseAbs().maxCoeff() <= kMaxCoordinate))
    throw Error("tumble::World::ray_cast: origin " + vector_text(origin) +
                " m is not finite or beyond 1e9");
  const Real length = direction.norm();
  if (!(std::isfinite(length) && length > 0))
    throw Error("tumble::World::ray_cast: direction " + vector_text(direction) +
                " has no finite, non-zero length");
  if (!(max_distance >= 0 && max_distance <= 2 * kMaxCoordinate))
    throw Error("tumble::World::ray_cast: max_distance " + number_text(max_distance) +
                " m is not between 0 and 2e9");
  const Vec3 unit = direction / length;
  const Simulation::RayResult r = live().ray_cast(origin, unit, max_distance);
  if (r.body < 0)
    return std::nullopt;
  RayHit hit;
  hit.body = {r.body, generation_[std::size_t(r.body)]};
  hit.distance = r.distance;
  hit.point = origin + unit * r.distance;
  hit.normal = r.normal;
  return hit;
}

std::uint64_t World::state_hash() const {
  return live().state_hash();
}

}  // namespace tumble
