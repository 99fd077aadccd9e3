// What the engine asks of a shape (include/tumble/shape.hpp describes the shapes): its support
// point, bounding box, volume, inertia, bounding radius and inner radius.
#pragma once

#include "collision/aabb.hpp"
#include "collision/math.hpp"
#include "tumble/shape.hpp"

namespace tumble {

// Farthest point of the shape along `direction` (local frame; direction need not be unit).
// For a plane the support is unbounded in most directions; it is never asked for.
Vec3 support(const Shape& shape, const Vec3& direction);

// Simulation-space bounding box of the shape under `pose`. A plane's box is infinite except along a
// world axis that is exactly its normal.
Aabb world_aabb(const Shape& shape, const Transform& pose);

// Volume [m^3]; infinite for a plane.
Real volume(const Shape& shape);

// Inertia tensor per unit mass about the centre of mass, in the local frame [m^2].
// Multiply by the body's mass to get kg m^2.
Mat3 unit_inertia(const Shape& shape);

// Radius of the smallest origin-centred sphere that holds the shape [m]; used to bound the
// speed of surface points from linear and angular velocity.
Real bounding_radius(const Shape& shape);

// Radius of a ball about the centre of mass inside the shape [m] (0 for planes and meshes, which
// are static); continuous collision sweeps a body that moves farther than it in a step.
Real inner_radius(const Shape& shape);

}  // namespace tumble
