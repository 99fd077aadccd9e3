// Non-convex 1-Lipschitz fields about a metre across, for tests of what meets them: a bowl (a box
// with a ball carved out of its top), a torus, and a smooth union of a ball and a capsule.
#pragma once

#include <vector>

#include "collision/sdf/sdf_tree.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "tumble/shape.hpp"

namespace tumble::testing {

// The three fields at `cells` cells along their longest sides.
inline std::vector<Shape> csg_test_fields(int cells) {
  const SdfNode bowl = SdfNode::combine(
      SdfKind::difference_of, {SdfNode::box(Vec3(0.6, 0.6, 0.3)),
                               SdfNode::sphere(0.5).placed({Vec3(0, 0, 0.35), Quat::Identity()})});
  const SdfNode blob =
      SdfNode::combine(SdfKind::smooth_union_of,
                       {SdfNode::sphere(0.4),
                        SdfNode::capsule(0.15, 0.5).placed({Vec3(0.3, 0, 0), Quat::Identity()})},
                       8);
  return {sdf_shape(bowl, nullptr, cells), sdf_shape(SdfNode::torus(0.5, 0.15), nullptr, cells),
          sdf_shape(blob, nullptr, cells)};
}

}  // namespace tumble::testing
