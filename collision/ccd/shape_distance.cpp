#include "collision/ccd/shape_distance.hpp"

#include <cmath>

#include "collision/narrow_phase.hpp"

namespace tumble {

DistanceBound box_box_separation(const Vec3& half_a, const Transform& pose_a, const Vec3& half_b,
                                 const Transform& pose_b) {
  const Mat3 ra = pose_a.rotation.toRotationMatrix();
  const Mat3 rb = pose_b.rotation.toRotationMatrix();
  const Vec3 d = pose_a.translation - pose_b.translation;  // from B to A
  DistanceBound best;
  best.distance = -std::numeric_limits<Real>::infinity();
  auto try_axis = [&](Vec3 axis) {
    const Real length = axis.norm();
    if (length < Real(1e-9))
      return;  // parallel edges: the face axes cover this direction
    axis /= length;
    const Real extent_a = half_a.x() * std::abs(axis.dot(ra.col(0))) +
                          half_a.y() * std::abs(axis.dot(ra.col(1))) +
                          half_a.z() * std::abs(axis.dot(ra.col(2)));
    const Real extent_b = half_b.x() * std::abs(axis.dot(rb.col(0))) +
                          half_b.y() * std::abs(axis.dot(rb.col(1))) +
                          half_b.z() * std::abs(axis.dot(rb.col(2)));
    const Real centre = axis.dot(d);
    const Real gap = std::abs(centre) - extent_a - extent_b;
    if (gap > best.distance) {
      best.distance = gap;
      best.normal = centre >= 0 ? axis : Vec3(-axis);
    }
  };
  for (int i = 0; i < 3; ++i) {
    try_axis(ra.col(i));
    try_axis(rb.col(i));
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      try_axis(ra.col(i).cross(rb.col(j)));
  }
  return best;
}

DistanceBound shape_distance_bound(const Shape& a, const Transform& pose_a, const Shape& b,
                                   const Transform& pose_b, Real max_distance) {
  if (a.type == ShapeType::box && b.type == ShapeType::box)
    return box_box_separation(a.half_extents, pose_a, b.half_extents, pose_b);
  // Every other current pair of the narrow phase reports the exact signed distance of its
  // closest features as the deepest point's depth (sphere, capsule and plane pairs by closed
  // form, capsule-box by exact piecewise minimisation, box-plane by the lowest vertex).
  Manifold m;
  DistanceBound out;
  if (collide(a, pose_a, b, pose_b, max_distance, m) == 0) {
    out.distance = max_distance;
    out.has_normal = false;
    return out;
  }
  Real deepest = m.points[0].depth;
  for (int i = 1; i < m.count; ++i)
    deepest = std::max(deepest, m.points[i].depth);
  out.distance = -deepest;
  out.normal = m.normal;
  return out;
}

}  // namespace tumble
