#include "engine/broad_phase_choice.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace tumble {

SceneStatistics scene_statistics(const Scene& scene) {
  SceneStatistics s;
  std::vector<Real> radii;
  Aabb bounds;
  Real body_volume = 0;
  for (const BodyDesc& b : scene.bodies) {
    if (!b.shape.is_bounded()) {
      ++s.unbounded_bodies;
      ++s.static_bodies;
      continue;
    }
    (b.is_static ? s.static_bodies : s.dynamic_bodies) += 1;
    const Real r = bounding_radius(b.shape);
    radii.push_back(r);
    bounds.grow(b.position - Vec3::Constant(r));
    bounds.grow(b.position + Vec3::Constant(r));
    body_volume += 8 * r * r * r;
  }
  if (radii.empty())
    return s;
  std::sort(radii.begin(), radii.end());
  const Real median = radii[radii.size() / 2];
  s.size_spread = median > 0 ? radii.back() / median : Real(1);
  const Real bounds_volume = (bounds.max - bounds.min).prod();
  s.fill = bounds_volume > 0 ? std::min(Real(1), body_volume / bounds_volume) : Real(1);
  return s;
}

BroadPhaseType choose_broad_phase(BroadPhaseType requested, const Scene& scene) {
  if (requested != BroadPhaseType::automatic)
    return requested;
  const SceneStatistics s = scene_statistics(scene);
  const int bodies = s.dynamic_bodies + s.static_bodies;
  // Below a few dozen bodies, all pairs is cheapest: no structure to update, and the n^2 box
  // tests fit in cache (the RL case: many small worlds).
  if (bodies <= 48)
    return BroadPhaseType::brute;
  // Sizes spread over orders of magnitude defeat single-resolution structures.
  if (s.size_spread > 16)
    return BroadPhaseType::bvh;
  return BroadPhaseType::sap;
}

}  // namespace tumble
