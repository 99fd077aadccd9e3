// The separating-axis theorem extended over time (docs/ccd.md) for two boxes that translate
// without turning over s in [0, 1]. Along a fixed axis L the projections of the two boxes are
// intervals whose centres move linearly, so the set of times at which they overlap on L is one
// interval found by two divisions; the boxes overlap exactly when they overlap on all 15 axes
// (3 + 3 face normals, 9 edge cross products) at the same time, i.e. in the intersection of
// the 15 time intervals. The first time of contact is that intersection's start: exact up to
// rounding, with no iteration. (With rotation the axes turn and each interval becomes a root
// problem of trigonometric functions; the stepper then uses conservative advancement.)
#pragma once

#include "collision/ccd/conservative_advancement.hpp"

namespace tumble {

// Boxes A and B (half extents, start poses) translating by `translation_a` and `translation_b`.
// Returns hit (or overlapping at s = 0) with the time and the axis (from B to A) of the last
// axis to close, or separated.
ToiResult swept_box_sat(const Vec3& half_a, const Transform& pose_a, const Vec3& translation_a,
                        const Vec3& half_b, const Transform& pose_b, const Vec3& translation_b);

}  // namespace tumble
