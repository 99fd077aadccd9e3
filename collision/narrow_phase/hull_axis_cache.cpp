#include "collision/narrow_phase/hull_axis_cache.hpp"

#include <cmath>

#include "collision/narrow_phase/pairs/hull_hull_sat.hpp"

namespace tumble {

namespace {

// Separations are trusted beyond rounding only when they exceed the margin by this share of the
// pair's size (as in box_axis_cache.cpp).
constexpr Real kRelativeBand = Real(1e-9);

Real band(const ConvexHull& a, const ConvexHull& b, const Vec3& b_centre_in_a, Real margin) {
  return kRelativeBand *
         (b_centre_in_a.norm() + a.bounding_radius() + b.bounding_radius() + std::abs(margin));
}

Transform b_in_a_of(const Transform& pose_a, const Transform& pose_b) {
  return {pose_a.apply_inverse(pose_b.translation), pose_a.rotation.conjugate() * pose_b.rotation};
}

}  // namespace

Real hull_axis_separation(const ConvexHull& a, const Transform& pose_a, const ConvexHull& b,
                          const Transform& pose_b, HullAxis& axis) {
  const Transform b_in_a = b_in_a_of(pose_a, pose_b);
  const Vec3& d = axis.direction_in_a;
  // Climbed from last step's supports: the poses moved a little, so the answer is a step or two
  // away. (Climbing, not scanning, whatever the size: the climb ends at the exact support.)
  axis.support_a = a.climb_support_index(d, axis.support_a);
  const Vec3 d_in_b = b_in_a.rotate_inverse(d);
  axis.support_b = b.climb_support_index(-d_in_b, axis.support_b);
  const Real highest_a = d.dot(a.vertex(axis.support_a));
  const Real lowest_b = d.dot(b_in_a.apply(b.vertex(axis.support_b)));
  return lowest_b - highest_a;
}

bool hull_axis_separates(const ConvexHull& a, const Transform& pose_a, const ConvexHull& b,
                         const Transform& pose_b, HullAxis& axis, Real margin) {
  if (!(axis.direction_in_a.squaredNorm() > 0))
    return false;
  const Real separation = hull_axis_separation(a, pose_a, b, pose_b, axis);
  const Vec3 b_centre = pose_a.apply_inverse(pose_b.translation);
  return separation > margin + band(a, b, b_centre, margin);
}

HullAxis separating_hull_axis(const ConvexHull& a, const Transform& pose_a, const ConvexHull& b,
                              const Transform& pose_b, Real margin) {
  const Transform b_in_a = b_in_a_of(pose_a, pose_b);
  const Real stop = margin + band(a, b, b_in_a.translation, margin);
  const detail::SatResult sat = detail::hull_sat_query(a, b, b_in_a, stop);
  HullAxis axis;
  if (sat.status != detail::SatStatus::separated)
    return axis;
  // The query stopped at the first axis beyond `stop`: A's face, B's face or an edge pair. Every
  // direction points from A to B.
  if (sat.face_a.separation > stop) {
    axis.direction_in_a = a.faces()[std::size_t(sat.face_a.face)].normal;
  } else if (sat.face_b.separation > stop) {
    axis.direction_in_a = -b_in_a.rotate(b.faces()[std::size_t(sat.face_b.face)].normal);
  } else {
    axis.direction_in_a = sat.edges.axis;
  }
  // Its supports now, for next step's climb; and the separation measured the cache's way must
  // clear the margin too, or the axis is not kept.
  if (!hull_axis_separates(a, pose_a, b, pose_b, axis, margin))
    return HullAxis{};
  return axis;
}

}  // namespace tumble
