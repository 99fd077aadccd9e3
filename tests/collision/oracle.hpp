// Independent truth for the collision tests: random poses with fixed seeds, signed distance
// functions of each shape, and a brute-force signed distance between two shapes that shares no
// code with the narrow phase.
//
// The brute force writes each shape as a finite "core" point set swept by a ball (a sphere is
// one point, a capsule two, a box eight with radius 0). The Minkowski difference A - B is then
// the convex hull of all core differences, swept by rA + rB, and the signed distance of the
// origin to the hull is found by enumerating every triple of points: triples whose plane has all
// points on one side are facets. The origin is inside when it is on the inner side of every
// facet (depth = distance to the nearest facet plane); otherwise its distance is the smallest
// distance to a facet (when it projects inside it), an edge between two points, or a point.
// This is O(n^4) and slow on purpose: it is simple enough to trust.
#pragma once

#include <random>
#include <vector>

#include "collision/contact.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/shape.hpp"

namespace tumble::testing {

using Rng = std::mt19937_64;

Real uniform(Rng& rng, Real low, Real high);
Vec3 random_unit_vector(Rng& rng);
Quat random_rotation(Rng& rng);
Vec3 random_vector_in_box(Rng& rng, Real half_width);

// A random shape of the given type with dimensions in a moderate range (plane has none).
Shape random_shape(Rng& rng, ShapeType type);

// Signed distance from a point in the shape's own frame to its surface (negative inside).
// Written from the definitions, not from the narrow phase's helpers.
Real local_signed_distance(const Shape& shape, const Vec3& local_point);
Real signed_distance_to_shape(const Shape& shape, const Transform& pose, const Vec3& world_point);

// Uniformly-ish distributed points on the shape's surface (local frame).
Vec3 random_surface_point(Rng& rng, const Shape& shape);

// max over the shape of direction . x in the world, through the support map. A plane's support
// is finite only along its own normal; elsewhere it is +infinity.
Real support_value(const Shape& shape, const Transform& pose, const Vec3& direction);

// min over A of n . x minus max over B of n . x: positive when n separates the shapes, and then
// it is a certificate that they are at least that far apart along n. For a penetrating pair the
// negative of it is how far A must move along n to separate.
Real separation_along(const Shape& a, const Transform& pose_a, const Shape& b,
                      const Transform& pose_b, const Vec3& n);

// Brute-force signed distance between two bounded shapes (negative = penetration depth), or
// between a bounded shape and a plane (from the support map, which is exact there).
Real brute_force_signed_distance(const Shape& a, const Transform& pose_a, const Shape& b,
                                 const Transform& pose_b);

// Signed distance of the origin to the convex hull of `points` (negative inside). Exposed for
// its own test.
Real hull_signed_distance_of_origin(const std::vector<Vec3>& points);

// Distance between two segments by checking the unconstrained minimiser of |P(s) - Q(t)|^2 and
// the minimum on each of the four edges of the parameter square: a different route from the
// narrow phase's Ericson clamping.
Real segment_segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);
Real point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b);

// Signed distance of a local point to a convex hull: the largest face-plane distance inside,
// the nearest face triangle (fan of each face) outside.
Real hull_local_signed_distance(const ConvexHull& hull, const Vec3& local_point);

// Deepest point of a manifold (index), or -1 when empty.
int deepest_point(const Manifold& m);

}  // namespace tumble::testing
