// Narrow phase entry point (docs/narrow-phase.md): one function per pair of shape types, looked up
// in a table indexed by the two types (the way MuJoCo's collision table reads).
#pragma once

#include "collision/contact.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/shapes/shape.hpp"

namespace tumble {

// Fills `out` with up to four contact points between `a` at pose `pose_a` and `b` at `pose_b`
// whose signed depth is at least -margin (they are closer than `margin` or penetrate), and
// returns out.count. The normal points from B to A; calling with A and B swapped flips the
// normal and swaps feature ids and changes nothing else (bit for bit: both orders run the same
// arithmetic), but for twins, the same shape at the same pose (for spheres, at the same
// centre), where nothing tells A from B and the normal is the same either way. The query runs in a
// frame centred on one of the two shapes (the first in the pair function's own order), so that
// bodies far from the origin keep their precision. Planes never collide with planes.
int collide(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out);

// Whether `a` at `pose_a` and `b` at `pose_b` are twins: shapes of equal content (dimensions,
// vertices, parts and their poses, a field's surface points; not the same object necessarily) at
// equal poses, or spheres of one radius at one centre. Nothing tells A from B then.
bool twins(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b);

// Whether collide() answers shapes of these types, in this order, by GJK/EPA (a cylinder or a hull
// against another convex shape; hull-hull has its own separating-axis test, and two cylinders no
// fixed order), so that a GJK warm start can serve it.
bool collides_by_gjk(ShapeType a, ShapeType b);

// collide() with GJK warm-started (docs/narrow-phase.md, "GJK"): for a pair collides_by_gjk
// names, GJK starts from `cache` (last step's separating axis in the first shape's frame, and its
// support vertices) and leaves its final axis there when the shapes are apart; other pairs leave
// `cache` alone. The answer is collide()'s up to GJK's tolerance (1e-10 of the distance).
int collide(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out, GjkCache& cache);

}  // namespace tumble
