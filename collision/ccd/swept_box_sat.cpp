#include "collision/ccd/swept_box_sat.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tumble {

ToiResult swept_box_sat(const Vec3& half_a, const Transform& pose_a, const Vec3& translation_a,
                        const Vec3& half_b, const Transform& pose_b, const Vec3& translation_b) {
  ToiResult out;
  out.iterations = 1;
  const Mat3 ra = pose_a.rotation.toRotationMatrix();
  const Mat3 rb = pose_b.rotation.toRotationMatrix();
  const Vec3 d = pose_a.translation - pose_b.translation;  // from B to A at s = 0
  const Vec3 v = translation_a - translation_b;            // its change over the motion
  if (!d.allFinite() || !v.allFinite()) {
    out.status = ToiStatus::invalid_input;
    out.time_of_impact = 0;
    return out;
  }
  Real enter = -1;  // overlap on every axis tested so far for s in [enter, exit]
  Real exit = 1;
  Vec3 enter_axis = Vec3::UnitZ();
  auto clip = [&](Vec3 axis) {
    const Real length = axis.norm();
    if (length < Real(1e-9))
      return true;  // parallel edges: the face axes decide this direction
    axis /= length;
    const Real radius =
        half_a.x() * std::abs(axis.dot(ra.col(0))) + half_a.y() * std::abs(axis.dot(ra.col(1))) +
        half_a.z() * std::abs(axis.dot(ra.col(2))) + half_b.x() * std::abs(axis.dot(rb.col(0))) +
        half_b.y() * std::abs(axis.dot(rb.col(1))) + half_b.z() * std::abs(axis.dot(rb.col(2)));
    const Real c0 = axis.dot(d);
    const Real cv = axis.dot(v);
    // Overlap on this axis while -radius <= c0 + s cv <= radius.
    Real lo = -std::numeric_limits<Real>::infinity();
    Real hi = std::numeric_limits<Real>::infinity();
    if (cv == 0) {
      if (std::abs(c0) > radius)
        return false;
    } else {
      const Real s1 = (-radius - c0) / cv;
      const Real s2 = (radius - c0) / cv;
      lo = std::min(s1, s2);
      hi = std::max(s1, s2);
    }
    if (lo > enter) {
      enter = lo;
      // The side A comes from: the sign of the centre offset when the axis closes.
      enter_axis = (c0 + std::max(lo, Real(0)) * cv) >= 0 ? axis : Vec3(-axis);
    }
    exit = std::min(exit, hi);
    return enter <= exit;
  };
  bool overlap = true;
  for (int i = 0; i < 3 && overlap; ++i)
    overlap = clip(ra.col(i)) && clip(rb.col(i));
  for (int i = 0; i < 3 && overlap; ++i) {
    for (int j = 0; j < 3 && overlap; ++j)
      overlap = clip(ra.col(i).cross(rb.col(j)));
  }
  if (!overlap || exit < 0 || enter > 1) {
    out.status = ToiStatus::separated;
    out.time_of_impact = 1;
    return out;
  }
  out.status = enter <= 0 ? ToiStatus::overlapping : ToiStatus::hit;
  out.time_of_impact = std::max(enter, Real(0));
  out.normal = enter_axis;
  out.distance = 0;
  return out;
}

}  // namespace tumble
