// Ray casts against every shape, in world space (each shape type's method is in its row of the
// shape table, collision/shapes/<type>_ops.cpp: Ericson, Real-Time Collision Detection, 2005,
// 5.3.2 ray-sphere, 5.3.3 ray-box slabs, 5.3.7 ray-cylinder; a capsule is its side plus two
// spheres; a hull by Cyrus-Beck clipping against its face planes; a mesh by Moller-Trumbore on
// the triangles its BVH returns, front faces only; a compound by its nearest part).
#pragma once

#include "collision/shapes/shape.hpp"
#include "collision/shapes/shape_ops.hpp"

namespace tumble {

// The segment from `origin` to `origin + delta` (world) against `shape` at `pose`.
ShapeRayHit ray_cast(const Shape& shape, const Transform& pose, const Vec3& origin,
                     const Vec3& delta);

// Signed distance of a world point to the shape's surface (negative inside) [m]; exact for the
// convex shapes, unsigned for a mesh (a surface), the nearest part's for a compound. The
// brute-force check of the ray casts and a helper for tests.
Real signed_distance(const Shape& shape, const Transform& pose, const Vec3& point);

}  // namespace tumble
