// The automatic choice of broad-phase structure (`world.broadphase: auto`), from the scene's
// statistics. The rule and the measurements behind it are in docs/broad-phase.md.
#pragma once

#include "collision/broad_phase/broad_phase.hpp"
#include "tumble/scene.hpp"

namespace tumble {

struct SceneStatistics {
  int dynamic_bodies = 0;
  int static_bodies = 0;
  int unbounded_bodies = 0;  // planes
  // Largest over median bounding radius of the bounded bodies: 1 when all are alike.
  Real size_spread = 1;
};

// At or below this many bodies (static ones included) `auto` is brute force.
inline constexpr int kBruteForceBodyLimit = 40;

SceneStatistics scene_statistics(const Scene& scene);

// `requested` unless it is `automatic`; then the structure the rule picks for `scene`.
BroadPhaseType choose_broad_phase(BroadPhaseType requested, const Scene& scene);

}  // namespace tumble
