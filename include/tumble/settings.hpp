// The settings of a world: time step, solver, collision and sleeping. Every setting has a unit
// and a default; docs/scene-format.md states them and what breaks when they are wrong.
#pragma once

#include <cstdint>
#include <optional>

#include "tumble/math.hpp"

namespace tumble {

// The structures tumble has (docs/broad-phase.md, "The structures"). `automatic` lets the engine
// choose from the scene's statistics.
enum class BroadPhaseType : std::uint8_t {
  automatic,
  brute,   // all pairs, O(n^2)
  sap,     // incremental sweep and prune on three axes
  hash,    // spatial hash
  bvh,     // dynamic AABB tree
  lbvh,    // linear BVH from Morton codes, rebuilt every step
  octree,  // loose octree
  kdtree,  // k-d tree with SAH splits
  grid,    // uniform grid
  hgrid,   // hierarchical grid
};

enum class SolverType : std::uint8_t { impulse, penalty };
enum class CcdMode : std::uint8_t { automatic, on, off };
// Which collision shape a body with a training shape (BodyDesc::train_shape) uses.
enum class Geometry : std::uint8_t { deploy, train };

struct WorldSettings {
  Vec3 gravity{0, 0, Real(-9.81)};  // m/s^2
  Real dt = Real(1) / 60;           // s, one step
  // How long `tumble run` simulates unless the command line says otherwise: `steps` wins when
  // set, else ceil(duration / dt) steps.
  Real duration = 5;  // s
  std::optional<std::int64_t> steps;
  // The solver runs at least `substeps` substeps of dt / substeps per step; collision runs once
  // per step. Each substep: gravity, warm start, `iterations` soft passes, positions,
  // `relax_iterations` rigid passes (design: docs/architecture.md). An island whose contacts
  // carry a load that would sag them deeper than `sag_tolerance` (all but one in a hundred, and
  // every one a body's weight loads) takes more substeps, doubling up to `max_substeps`
  // ("Substeps per island" there).
  int substeps = 4;
  int max_substeps = 64;
  SolverType solver = SolverType::impulse;
  int iterations = 1;        // soft velocity passes per substep
  int relax_iterations = 1;  // rigid velocity passes per substep
  BroadPhaseType broadphase = BroadPhaseType::automatic;
  CcdMode ccd = CcdMode::automatic;
  // Contact recycling: a pair whose relative pose barely moved since its manifold was computed
  // reuses it (collision/narrow_phase/manifold_recycling.hpp). Off collides every candidate pair
  // every step.
  bool contact_recycling = true;
  // Contacts are created this far before the surfaces touch, plus the distance the bodies can
  // close in one step (speculative contacts), so that resting contacts never flicker. [m]
  Real contact_margin = Real(0.005);
  // Penetration left alone, so that resting contacts stay in touch. Each joint of a stack sinks
  // up to this much: 0.1 mm keeps a 12-box tower within 1.2 mm of its height. [m]
  Real penetration_slop = Real(0.0001);
  // Stiffness of the spring that pushes penetrating bodies apart. Unset (`auto`, the default):
  // an eighth of the substep rate between moving bodies and a quarter against a static body
  // (Box2D v3's ratios: the stiffest a one-pass Gauss-Seidel substep keeps stable), so the spring
  // stiffens with the substeps. Set: that frequency, capped at a quarter of the substep rate,
  // twice that against static bodies. [Hz]
  std::optional<Real> contact_hertz;
  // The static deflection of a soft contact under its load that an island tolerates, as a
  // fraction of the smaller body's bounding radius; beyond it the island takes more substeps
  // (only with `contact_hertz` auto). 0.002 keeps a 0.5 m cube's joints within 0.9 mm. [1]
  Real sag_tolerance = Real(0.002);
  // Damping ratio of that spring; well above 1 so pushing out never overshoots. [1]
  Real contact_damping_ratio = 10;
  // The fastest the spring pushes bodies apart. [m/s]
  Real max_push_velocity = 3;
  // Approach speeds below this bounce with no restitution, so resting bodies do not jitter. [m/s]
  Real restitution_threshold = Real(0.2);
  // Sleeping: an island (bodies connected by contacts) whose bodies have all moved slower than
  // `sleep_speed` (|v| + |w| r, r the bounding radius) for `sleep_time` stops being solved and
  // integrated until an awake body touches it. Off by default: results then never depend on
  // it, and benchmarks measure the full work (docs/stability.md).
  bool sleeping = false;
  Real sleep_speed = Real(0.05);  // m/s
  Real sleep_time = Real(0.5);    // s
  // Threads a step may use (`auto`, stored as 0: the machine's cores). The results are the same
  // bits on any count (docs/architecture.md, "Threads").
  int threads = 0;
  // `train`: bodies with a train_shape collide with it (their mass stays their shape's); `deploy`
  // (the default): every body collides with its detailed shape.
  Geometry geometry = Geometry::deploy;
};

}  // namespace tumble
