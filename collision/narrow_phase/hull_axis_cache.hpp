// A separating-axis cache for hull pairs, the counterpart of
// collision/narrow_phase/box_axis_cache.hpp: the direction that separated two hulls last step (a
// face normal or an edge cross product of the separating-axis test, Gregorius, "The Separating Axis
// Test between Convex Polyhedra", GDC 2013, which also proposes caching it) is measured first this
// step, by one support query per hull climbed from last step's support vertices. While it separates
// the hulls by more than the margin, the pair has no contact and its query is skipped.
//
// Any direction proves what it separates: the hulls are at least that far apart, so collide()
// finds no point within the margin either (up to a rounding band of 1e-9 of the pair's size), and
// the answer never differs from the full query's.
#pragma once

#include <cstdint>

#include "collision/math.hpp"
#include "collision/shapes/convex_hull.hpp"

namespace tumble {

struct HullAxis {
  Vec3 direction_in_a = Vec3::Zero();  // unit, in A's frame, from A towards B; zero: none
  std::int32_t support_a = 0;          // last supports (climb starts)
  std::int32_t support_b = 0;
};

// The separation of hull `b` at `pose_b` from hull `a` at `pose_a` along `axis` (min over B minus
// max over A) [m]; updates the axis's support vertices.
Real hull_axis_separation(const ConvexHull& a, const Transform& pose_a, const ConvexHull& b,
                          const Transform& pose_b, HullAxis& axis);

// Whether `axis` separates the hulls by more than `margin`, beyond rounding.
bool hull_axis_separates(const ConvexHull& a, const Transform& pose_a, const ConvexHull& b,
                         const Transform& pose_b, HullAxis& axis, Real margin);

// An axis of the separating-axis test that separates the hulls by more than `margin` (beyond
// rounding), or one with a zero direction when none does (they touch, or lie within the margin).
HullAxis separating_hull_axis(const ConvexHull& a, const Transform& pose_a, const ConvexHull& b,
                              const Transform& pose_b, Real margin);

// One cached axis, kept in the world's state (sorted by pair) so that replay stays bit-identical.
struct CachedHullAxis {
  std::int32_t body_a = 0;  // body_a < body_b
  std::int32_t body_b = 0;
  HullAxis axis;
};

}  // namespace tumble
