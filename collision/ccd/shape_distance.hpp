// A lower bound of the distance between two posed shapes, with the axis it is measured along:
// the query conservative advancement needs (collision/ccd/conservative_advancement.hpp). Today
// it uses the exact closest-feature pairs of the narrow phase and, for box against box, the
// separating-axis bound; GJK replaces the latter when it lands.
#pragma once

#include "collision/shapes/shape.hpp"

namespace tumble {

struct DistanceBound {
  // A lower bound of the distance [m]: the shapes are at least this far apart along `normal`
  // (the support of A along -normal lies at least this far beyond the support of B along
  // normal). Negative when they overlap (then minus a penetration depth).
  Real distance = 0;
  Vec3 normal = Vec3::UnitZ();  // unit, from B to A
  // True when `normal` separates the whole shapes (convex pairs): the gap along it then closes
  // no faster than the relative velocity's component along it, and conservative advancement may
  // use that component. False when the shapes are farther than asked and no axis was measured
  // (`normal` means nothing), and when one shape is a mesh or compound (`normal` is the nearest
  // triangle's or part's, and another may be approached faster from another direction): then
  // only the unprojected speed bounds the approach.
  bool separating_normal = true;
  // How far (in the motion's parameter) the pair may advance before the gap can have closed to
  // the target, measured along each nearby part's own separating axis: a convex shape against a
  // mesh, asked with a ClosingMotion, where no one axis separates the whole mesh but each
  // triangle has its own; infinity when no triangle closes. Negative when not measured
  // (conservative advancement then steps by `distance` over the unprojected speed alone).
  Real least_advance = -1;
};

// What conservative advancement knows of the motions of a pair whose centres move on straight
// lines (both of the linear kind): A's velocity less B's [m per unit of the motion's parameter],
// the most the turning of both adds to the closing speed, and the gap it advances to.
struct ClosingMotion {
  Vec3 relative_velocity = Vec3::Zero();
  Real spin_bound = 0;
  Real target_distance = 0;
};

// `max_distance`: beyond it the answer may be any bound >= max_distance [m]. When nothing is
// found within the margin the narrow phase was asked with, that margin is the bound: at most
// max_distance (less against a 1-Lipschitz field, shape_distance.cpp). Where a field is one of
// the two, a cheaper and looser bound from the shapes' bounding balls is returned while it
// exceeds `stop_distance` (conservative advancement's target plus tolerance, where it stops: a
// loose bound there would stop it early) and a quarter of the smaller bounding radius.
// `motion`, when given, lets a convex shape against a mesh also answer `least_advance`.
DistanceBound shape_distance_bound(const Shape& a, const Transform& pose_a, const Shape& b,
                                   const Transform& pose_b, Real max_distance,
                                   Real stop_distance = 0, const ClosingMotion* motion = nullptr);

// Separating-axis lower bound of the distance between two boxes: the largest gap along the 15
// axes of the box-box test (3 + 3 face normals, 9 edge cross products). It equals the distance
// when a face or an edge pair is closest and is below it otherwise (Gottschalk, Lin and
// Manocha, "OBBTree", SIGGRAPH 1996; Ericson, Real-Time Collision Detection, 4.4.1).
DistanceBound box_box_separation(const Vec3& half_a, const Transform& pose_a, const Vec3& half_b,
                                 const Transform& pose_b);

}  // namespace tumble
