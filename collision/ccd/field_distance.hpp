// The signed distance of a signed distance field from a plane's half-space or from another field,
// with its derivatives with respect to both poses (include/tumble/distance.hpp; docs/sdf.md,
// "Gradients").
#pragma once

#include "collision/shapes/sdf_shape.hpp"
#include "tumble/distance.hpp"

namespace tumble {

// A is the plane (its solid is below z = 0 of its frame), B the field: the least phi_B over the
// half-space. Apart, that is how far B's solid is from the plane; overlapping, minus the depth
// of B's point deepest below it.
ShapeDistance plane_and_field(const Transform& plane_pose, const SdfShape& field, Real time,
                              const Transform& field_pose);

// Two fields: the least of phi_A + phi_B over space. For exact fields apart this is their
// distance (phi_A(x) + phi_B(x) is at least the distance of the two solids by the triangle
// inequality, and equals it along the segment between their closest points); overlapping, it is
// minus the depth along the line through the point where the two fields sum lowest (for two
// balls, exactly their penetration depth).
ShapeDistance field_and_field(const SdfShape& a, Real time_a, const Transform& pose_a,
                              const SdfShape& b, Real time_b, const Transform& pose_b);

}  // namespace tumble
