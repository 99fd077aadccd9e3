// A compound against any shape, through the narrow phase's own dispatch for each part
// (compound_collide.cpp): above the pair functions of pairs/, beside the dispatch table.
#pragma once

#include "collision/contact.hpp"
#include "collision/shapes/shape.hpp"

namespace tumble::detail {

// Each part near `b` through collide(), the parts' points merged into one manifold.
int compound_any(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                 Real margin, Manifold& out);

}  // namespace tumble::detail
