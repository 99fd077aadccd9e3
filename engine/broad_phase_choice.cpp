#include "engine/broad_phase_choice.hpp"

#include "collision/shapes/shape.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace tumble {

SceneStatistics scene_statistics(const Scene& scene) {
  SceneStatistics s;
  std::vector<Real> radii;
  for (const BodyDesc& b : scene.bodies) {
    if (!b.shape.is_bounded()) {
      ++s.unbounded_bodies;
      ++s.static_bodies;
      continue;
    }
    (b.is_static ? s.static_bodies : s.dynamic_bodies) += 1;
    const Real r = bounding_radius(b.shape);
    radii.push_back(r);
  }
  if (radii.empty())
    return s;
  std::sort(radii.begin(), radii.end());
  const Real median = radii[radii.size() / 2];
  s.size_spread = median > 0 ? radii.back() / median : Real(1);
  return s;
}

BroadPhaseType choose_broad_phase(BroadPhaseType requested, const Scene& scene) {
  if (requested != BroadPhaseType::automatic)
    return requested;
  const SceneStatistics s = scene_statistics(scene);
  // Up to about 40 bodies all pairs is cheapest: no structure to maintain, and the n^2 box
  // tests stay in cache (measured crossover with the k-d tree: between 32 and 48 bodies). This
  // is the reinforcement-learning case: many small worlds.
  if (s.dynamic_bodies + s.static_bodies <= kBruteForceBodyLimit)
    return BroadPhaseType::brute;
  // Above that the k-d tree: in docs/broad-phase-benchmark.md it is within 1.3x of the fastest
  // structure on every layout (uniform, clustered, mixed sizes) and count (1k to 100k), which no
  // other structure is; size spread and clustering move the winner among structures that are all
  // within that margin, so they do not change the choice.
  return BroadPhaseType::kdtree;
}

}  // namespace tumble
