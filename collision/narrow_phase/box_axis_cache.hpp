// A separating-axis cache for box pairs: the axis that separated two boxes last step is tried
// first this step, and when it still separates them by more than the margin the pair has no
// contact and the full test is skipped (temporal coherence: Gregorius, "The Separating Axis Test
// between Convex Polyhedra", GDC 2013, "caching the separating axis"; the 15 axes as in
// Gottschalk, Lin and Manocha, "OBBTree", SIGGRAPH 1996). Separated pairs are half of the candidate
// pairs of a settling pile (docs/narrow-phase.md, "The separating-axis cache").
//
// The answer never differs from the full test's: a pair is skipped only when one axis separates it
// by more than the margin, and then collide() finds no point either (every point is at least that
// far apart along that axis), with a relative safety band against rounding.
#pragma once

#include <cstdint>

#include "collision/math.hpp"

namespace tumble {

// An axis of the box-box test: 0-2 A's face normals, 3-5 B's, 6 + 3 i + j the cross product of A's
// axis i with B's axis j. kNoBoxAxis: none cached.
inline constexpr std::uint8_t kNoBoxAxis = 255;

// The separation of the boxes of half extents `half_a` at `pose_a` and `half_b` at `pose_b` along
// `axis` [m]: positive when the axis separates them. An edge axis of nearly parallel edges has no
// direction and gives -infinity.
Real box_axis_separation(const Vec3& half_a, const Transform& pose_a, const Vec3& half_b,
                         const Transform& pose_b, std::uint8_t axis);

// Whether `axis` separates the boxes by more than `margin`, beyond rounding.
bool box_axis_separates(const Vec3& half_a, const Transform& pose_a, const Vec3& half_b,
                        const Transform& pose_b, std::uint8_t axis, Real margin);

// The axis of largest separation among the 15, if it separates the boxes by more than `margin`
// (beyond rounding); otherwise kNoBoxAxis.
std::uint8_t best_separating_box_axis(const Vec3& half_a, const Transform& pose_a,
                                      const Vec3& half_b, const Transform& pose_b, Real margin);

// One cached axis, kept in the world's state (sorted by pair) so that replay stays bit-identical.
struct CachedBoxAxis {
  std::int32_t body_a = 0;  // body_a < body_b
  std::int32_t body_b = 0;
  std::uint8_t axis = kNoBoxAxis;
};

}  // namespace tumble
