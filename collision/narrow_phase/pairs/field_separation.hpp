// The least separation of a pair with a signed distance field, for conservative advancement.
#pragma once

#include "collision/math.hpp"
#include "tumble/shape.hpp"

namespace tumble {

// For a pair with a signed distance field (either shape or both; the other neither a mesh nor a
// compound): the separation of the deepest candidate collide() would measure (minus its depth
// along its own normal; the narrow phase reports each point along the manifold's common normal, at
// least half as deep), or `margin` when there is none within it, and that candidate's own normal
// (from B to A), without building the manifold: its candidates are refined only where they lie
// deepest (collision/narrow_phase/pairs/sdf_pairs.cpp). Conservative advancement steps by it
// (collision/ccd/shape_distance.cpp).
struct FieldSeparation {
  Real distance = 0;
  Vec3 normal = Vec3::UnitZ();
};
FieldSeparation field_least_separation(const Shape& a, const Transform& pose_a, const Shape& b,
                                       const Transform& pose_b, Real margin);

}  // namespace tumble
