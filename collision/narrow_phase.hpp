// Narrow phase entry point (seed 4.1.4): one function per pair of shape types, looked up in a
// table indexed by the two types (the way MuJoCo's collision table reads).
#pragma once

#include "collision/contact.hpp"
#include "collision/shape.hpp"

namespace tumble {

// Fills `out` with up to four contact points between `a` at pose `pose_a` and `b` at `pose_b`
// whose signed depth is at least -margin (they are closer than `margin` or penetrate), and
// returns out.count. The normal points from B to A; calling with A and B swapped flips the
// normal and swaps feature ids and changes nothing else (bit for bit: both orders run the same
// arithmetic). The query runs in a frame centred on one of the two shapes (the first in the
// pair function's own order), so that bodies far from the origin keep their precision. Planes
// never collide with planes.
int collide(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out);

}  // namespace tumble
