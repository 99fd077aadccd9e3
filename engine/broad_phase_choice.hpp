// The automatic choice of broad-phase structure (`world.broadphase: auto`), from the scene's
// statistics. The rule and the measurements behind it are in docs/broad-phase.md.
#pragma once

#include "collision/broad_phase.hpp"
#include "engine/scene.hpp"

namespace tumble {

struct SceneStatistics {
  int dynamic_bodies = 0;
  int static_bodies = 0;
  int unbounded_bodies = 0;  // planes
  // Largest over median bounding radius of the bounded bodies: 1 when all are alike.
  Real size_spread = 1;
  // Fraction of the bounded bodies' bounding volume filled by the bodies themselves (boxes of
  // their bounding spheres): near 1 when packed, near 0 when sparse or clustered in a big box.
  Real fill = 0;
};

SceneStatistics scene_statistics(const Scene& scene);

// `requested` unless it is `automatic`; then the structure the rule picks for `scene`.
BroadPhaseType choose_broad_phase(BroadPhaseType requested, const Scene& scene);

}  // namespace tumble
