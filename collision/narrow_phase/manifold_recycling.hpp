// Contact recycling: a pair whose relative pose has barely changed since its manifold was
// computed reuses that manifold instead of colliding again. The manifold is kept in the two
// bodies' own frames (each point as the point on A in A's frame and the point on B in B's frame),
// so that moving both bodies moves the points with them; the depth is then measured again from
// the two points, exactly, and only which features make the manifold is taken from the past.
//
// Source: Jolt Physics' body pair cache (ContactConstraintManager,
// "mBodyPairCacheMaxDeltaPositionSq" and "mBodyPairCacheCosMaxDeltaRotationDiv2" in
// PhysicsSettings.h) and Box2D's persistent contacts; the tolerances here are relative to the
// bodies' size (docs/narrow-phase.md, "Recycling").
#pragma once

#include <array>
#include <cstdint>

#include "collision/contact.hpp"
#include "collision/math.hpp"

namespace tumble {

struct RecyclableManifold {
  std::int32_t body_a = 0;  // body_a < body_b
  std::int32_t body_b = 0;
  // B's pose in A's frame when the manifold was computed.
  Vec3 relative_position = Vec3::Zero();
  Quat relative_orientation = Quat::Identity();
  Vec3 normal = Vec3::UnitZ();  // from B to A, in A's frame
  std::int32_t count = 0;
  std::array<Vec3, kMaxManifoldPoints> point_a{};  // on A's surface, A's frame
  std::array<Vec3, kMaxManifoldPoints> point_b{};  // on B's surface, B's frame
  std::array<FeatureId, kMaxManifoldPoints> feature{};
  // A manifold of one point is not reused: its normal may be the direction between two edges'
  // closest points, which turns as the edges slide along each other, not only with the
  // relative rotation, so the recycling angle would not bound it.
  bool reusable = true;
};

// The manifold `m` of bodies at poses `a` and `b`, in their frames.
RecyclableManifold make_recyclable(std::int32_t body_a, std::int32_t body_b, const Manifold& m,
                                   const Transform& a, const Transform& b);

// When B's pose relative to A is within `max_distance` [m] and `max_angle` [rad] of the pose
// `kept` was computed at, writes the kept manifold at poses `a` and `b` (its depths measured
// again) into `out` and returns true; otherwise returns false and leaves `out` alone.
bool recycle(const RecyclableManifold& kept, const Transform& a, const Transform& b,
             Real max_distance, Real max_angle, Manifold& out);

// The same with the angle given as sin(max_angle / 2), for a caller that asks with one angle
// every step (a sine per pair was a tenth of the recycling's time).
bool recycle_within_half_sine(const RecyclableManifold& kept, const Transform& a,
                              const Transform& b, Real max_distance, Real max_half_sine,
                              Manifold& out);

}  // namespace tumble
