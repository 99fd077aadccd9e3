// The box of a tree node: an Aabb as six plain numbers, shared by the dynamic tree, the linear
// BVH and the binned SAH build.
#pragma once

#include <algorithm>
#include <cmath>

#include "collision/aabb.hpp"

namespace tumble {

// A box as six plain numbers: trivially copyable, no Eigen expression templates in hot loops.
// Same closed-interval semantics as Aabb::overlaps (touching boxes overlap), and the same
// comparisons in the same order, so both answer identically.
struct TreeBox {
  Real min[3];
  Real max[3];

  static TreeBox from(const Aabb& b) {
    return {{b.min.x(), b.min.y(), b.min.z()}, {b.max.x(), b.max.y(), b.max.z()}};
  }
  Aabb to_aabb() const { return {Vec3(min[0], min[1], min[2]), Vec3(max[0], max[1], max[2])}; }

  // Bitwise & rather than &&: six compares and no branches, which pays off where the answer is
  // unpredictable (pair scans, traversals). The result is the same as Aabb::overlaps.
  bool overlaps(const TreeBox& o) const {
    return (min[0] <= o.max[0]) & (o.min[0] <= max[0]) & (min[1] <= o.max[1]) &
           (o.min[1] <= max[1]) & (min[2] <= o.max[2]) & (o.min[2] <= max[2]);
  }
  bool contains(const TreeBox& o) const {
    return min[0] <= o.min[0] && min[1] <= o.min[1] && min[2] <= o.min[2] && o.max[0] <= max[0] &&
           o.max[1] <= max[1] && o.max[2] <= max[2];
  }
  // All six numbers finite (an inverted default Aabb or a plane's box is not).
  bool is_finite() const {
    return std::isfinite(min[0]) && std::isfinite(min[1]) && std::isfinite(min[2]) &&
           std::isfinite(max[0]) && std::isfinite(max[1]) && std::isfinite(max[2]);
  }
  // Half the surface area. Every use is a ratio or a comparison, so the factor 2 is dropped.
  Real half_area() const {
    const Real dx = max[0] - min[0];
    const Real dy = max[1] - min[1];
    const Real dz = max[2] - min[2];
    return dx * dy + dy * dz + dz * dx;
  }
  static TreeBox merge(const TreeBox& a, const TreeBox& b) {
    return {
        {std::min(a.min[0], b.min[0]), std::min(a.min[1], b.min[1]), std::min(a.min[2], b.min[2])},
        {std::max(a.max[0], b.max[0]), std::max(a.max[1], b.max[1]), std::max(a.max[2], b.max[2])}};
  }
};

}  // namespace tumble
