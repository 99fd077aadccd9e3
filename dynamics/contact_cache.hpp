// Impulses carried from one step to the next for warm starting (Catto, "Iterative Dynamics with
// Temporal Coherence", GDC 2005): one record per touching pair, one entry per manifold point
// keyed by its feature id. Part of the world's State, so that a copied or restored state
// warm-starts exactly as the original would.
#pragma once

#include <array>
#include <cstdint>

#include "collision/contact.hpp"
#include "collision/math.hpp"

namespace tumble {

struct CachedContactPoint {
  std::uint32_t feature = 0;             // FeatureId::key()
  Vec3 local_point = Vec3::Zero();       // m, the contact point in body A's frame
  Real normal_impulse = 0;               // N s
  Vec3 friction_impulse = Vec3::Zero();  // N s, world frame, in the contact plane
};

struct CachedManifold {
  std::int32_t body_a = 0;  // body_a < body_b
  std::int32_t body_b = 0;
  std::int32_t count = 0;
  std::array<CachedContactPoint, kMaxManifoldPoints> points{};
};

}  // namespace tumble
