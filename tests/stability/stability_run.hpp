// Runs a scene of scenes/stability/ under a chosen solver and records what the stability tests
// bound: non-finite values, the largest total energy above the initial one, the deepest
// penetration (measured independently of the solver, by running the narrow phase on every
// overlapping pair at sampled steps), and the largest drift of chosen bodies.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"
#include "tests/property_scale.hpp"
#include "tumble/load_scene.hpp"

namespace tumble::test {

inline std::shared_ptr<Scene> stability_scene(const std::string& name, SolverType solver) {
  auto scene = std::make_shared<Scene>(
      load_scene_file(std::string(TUMBLE_SOURCE_DIR) + "/scenes/stability/" + name));
  scene->world.solver = solver;
  return scene;
}

// A scene with sleeping on (asleep after 0.5 s below 5 cm/s), friction 0.6, a floor plane and
// `bodies`: YAML lines of the `bodies:` list, each ending in a newline.
inline std::shared_ptr<Scene> sleeping_scene(const std::string& bodies, SolverType solver) {
  const std::string yaml = R"(
world:
  dt: 0.0166666666666666667
  sleeping: true
  sleep_speed: 0.05
  sleep_time: 0.5
materials:
  default: {friction: 0.6, restitution: 0}
bodies:
  - {name: floor, shape: {type: plane}, static: true}
)" + bodies;
  auto scene = std::make_shared<Scene>(*load_scene_text(yaml, "sleeping.yaml"));
  scene->world.solver = solver;
  return scene;
}

inline const char* solver_label(SolverType s) {
  return s == SolverType::impulse ? "impulse" : "penalty";
}

struct StabilityRecord {
  bool finite = true;
  Real initial_energy = 0;
  Real max_energy_gain = 0;  // max over steps of E(t) - E(0) [J]
  Real max_penetration = 0;  // deepest overlap of any pair at the sampled steps [m]
  Real max_drift = 0;        // of the watched bodies from their start [m]
  Real final_drift = 0;      // same, at the end
  Real max_tilt = 0;         // largest angle of a watched body from its start [rad]
  std::int64_t steps = 0;
  double seconds_per_step = 0;  // wall time, for the docs only; never asserted
};

// Deepest penetration between any two bodies now.
inline Real deepest_penetration(const Simulation& world) {
  const Scene& scene = world.scene();
  const std::size_t n = scene.bodies.size();
  std::vector<Aabb> boxes(n);
  std::vector<Transform> poses(n);
  for (std::size_t i = 0; i < n; ++i) {
    poses[i] = {world.state().bodies[i].position, world.state().bodies[i].orientation};
    boxes[i] = world_aabb(scene.bodies[i].shape, poses[i]);
  }
  Real deepest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      if (scene.bodies[i].is_static && scene.bodies[j].is_static)
        continue;
      if (!boxes[i].overlaps(boxes[j]))
        continue;
      Manifold m;
      const int count =
          collide(scene.bodies[i].shape, poses[i], scene.bodies[j].shape, poses[j], 0, m);
      for (int k = 0; k < count; ++k)
        deepest = std::max(deepest, m.points[k].depth);
    }
  }
  return deepest;
}

// Steps `world` for `seconds`, watching the bodies `watched` (empty: all dynamic ones).
// `sample_every` steps the penetration is measured; `each_step` (optional) sees every step.
inline StabilityRecord run_and_record(
    Simulation& world, Real seconds, std::vector<int> watched, int sample_every,
    const std::function<void(const Simulation&)>& each_step = {}) {
  const Scene& scene = world.scene();
  if (watched.empty()) {
    for (std::size_t i = 0; i < scene.bodies.size(); ++i)
      if (!scene.bodies[i].is_static)
        watched.push_back(static_cast<int>(i));
  }
  StabilityRecord r;
  r.initial_energy = world.kinetic_energy() + world.potential_energy();
  std::vector<BodyState> start;
  for (int i : watched)
    start.push_back(world.state().bodies[i]);
  r.steps = std::llround(seconds / scene.world.dt);
  double wall = 0;
  for (std::int64_t k = 0; k < r.steps; ++k) {
    world.step();
    const StepStatistics& stats = world.last_step_statistics();
    for (double s : stats.seconds)
      wall += s;
    const Real energy = world.kinetic_energy() + world.potential_energy();
    if (!std::isfinite(energy)) {
      r.finite = false;
      break;
    }
    r.max_energy_gain = std::max(r.max_energy_gain, energy - r.initial_energy);
    for (std::size_t w = 0; w < watched.size(); ++w) {
      const BodyState& b = world.state().bodies[watched[w]];
      if (!b.position.allFinite() || !b.velocity.allFinite() || !b.angular_velocity.allFinite() ||
          !b.orientation.coeffs().allFinite()) {
        r.finite = false;
      }
      const Real drift = (b.position - start[w].position).norm();
      r.max_drift = std::max(r.max_drift, drift);
      if (k + 1 == r.steps)
        r.final_drift = std::max(r.final_drift, drift);
      r.max_tilt = std::max(r.max_tilt, b.orientation.angularDistance(start[w].orientation));
    }
    if (!r.finite)
      break;
    if (sample_every > 0 && ((k + 1) % sample_every == 0 || k + 1 == r.steps))
      r.max_penetration = std::max(r.max_penetration, deepest_penetration(world));
    if (each_step)
      each_step(world);
  }
  r.seconds_per_step = r.steps > 0 ? wall / static_cast<double>(r.steps) : 0;
  return r;
}

// One line per run, collected into docs/stability.md.
inline void report(const std::string& what, SolverType solver, const StabilityRecord& r) {
  std::printf(
      "[stability] %-28s %-8s steps %7lld  finite %d  energy gain %.3g J (E0 %.4g)  "
      "penetration %.3g m  drift max %.3g m final %.3g m  tilt %.3g rad  %.1f us/step\n",
      what.c_str(), solver_label(solver), static_cast<long long>(r.steps), r.finite ? 1 : 0,
      r.max_energy_gain, r.initial_energy, r.max_penetration, r.max_drift, r.final_drift,
      r.max_tilt, r.seconds_per_step * 1e6);
}

inline constexpr SolverType kBoth[] = {SolverType::impulse, SolverType::penalty};

// Every run: finite, and never more energy than at the start (to rounding of the total).
inline void expect_sane(const StabilityRecord& r) {
  EXPECT_TRUE(r.finite);
  EXPECT_LE(r.max_energy_gain, 1e-9 * std::max(Real(1), std::abs(r.initial_energy)));
}

}  // namespace tumble::test
