// Geometric helpers shared by the pair functions: capsule core segments, closest points on and
// between segments (Ericson, Real-Time Collision Detection, 2005, 5.1.2 and 5.1.9), the signed
// distance to a box and the box feature of a point.
#include <algorithm>
#include <cmath>

#include "collision/narrow_phase/pairs/pairs.hpp"

namespace tumble::detail {

Segment capsule_segment(const Shape& capsule, const Transform& pose) {
  const Vec3 half_axis = pose.rotate(Vec3(0, 0, capsule.half_length));
  return {pose.translation - half_axis, pose.translation + half_axis};
}

Real closest_parameter_on_segment(const Vec3& point, const Vec3& start, const Vec3& end) {
  const Vec3 direction = end - start;
  const Real length_squared = direction.squaredNorm();
  // Compared with the squared size of the whole configuration: a segment this short has no
  // usable direction, and t = 0 names its start feature deterministically.
  const Real tiny = Real(1e-30) * (length_squared + (point - start).squaredNorm());
  if (!(length_squared > tiny))
    return 0;
  return std::clamp((point - start).dot(direction) / length_squared, Real(0), Real(1));
}

void closest_parameters_between_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                         const Vec3& q1, Real& s, Real& t) {
  const Vec3 d1 = p1 - p0;
  const Vec3 d2 = q1 - q0;
  const Vec3 r = p0 - q0;
  const Real a = d1.squaredNorm();
  const Real e = d2.squaredNorm();
  const Real f = d2.dot(r);
  // Segments shorter than 1e-15 of the configuration's size are points (Ericson's EPSILON, made
  // relative so that the test means the same at every scale).
  const Real tiny = Real(1e-30) * (a + e + r.squaredNorm());
  const bool p_is_point = !(a > tiny);
  const bool q_is_point = !(e > tiny);
  if (p_is_point && q_is_point) {
    s = t = 0;
    return;
  }
  if (p_is_point) {
    s = 0;
    t = std::clamp(f / e, Real(0), Real(1));
    return;
  }
  const Real c = d1.dot(r);
  if (q_is_point) {
    t = 0;
    s = std::clamp(-c / a, Real(0), Real(1));
    return;
  }
  const Real b = d1.dot(d2);
  const Real denominator = a * e - b * b;  // = |d1 x d2|^2 >= 0, up to rounding
  // Parallel (or nearly, sin^2 of the angle below 1e-20): any s works; take s = 0 so the choice
  // is deterministic, as Ericson does.
  s = denominator > Real(1e-20) * a * e
          ? std::clamp((b * f - c * e) / denominator, Real(0), Real(1))
          : Real(0);
  t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, Real(0), Real(1));
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, Real(0), Real(1));
  }
}

Real box_signed_distance(const Vec3& point, const Vec3& half_extents) {
  const Vec3 q = point.cwiseAbs() - half_extents;
  return q.cwiseMax(Real(0)).norm() + std::min(q.maxCoeff(), Real(0));
}

std::uint16_t box_feature_of_outside_point(const Vec3& point, const Vec3& half_extents) {
  int outside_count = 0;
  int outside_axis = 0;
  int inside_axis = 0;
  int sign_bits = 0;
  for (int k = 0; k < 3; ++k) {
    if (point[k] >= 0)
      sign_bits |= 1 << k;
    if (std::abs(point[k]) > half_extents[k]) {
      ++outside_count;
      outside_axis = k;
    } else {
      inside_axis = k;
    }
  }
  switch (outside_count) {
    case 1:
      return feature::box_face(outside_axis, point[outside_axis] >= 0);
    case 2:
      return feature::box_edge(inside_axis, sign_bits);
    case 3:
      return feature::box_vertex(sign_bits);
    default:
      break;
  }
  // Inside or on the surface: the face whose slab the point is closest to leaving (the first
  // axis on ties, so the answer is deterministic).
  int face_axis = 0;
  Real best = half_extents[0] - std::abs(point[0]);
  for (int k = 1; k < 3; ++k) {
    const Real room = half_extents[k] - std::abs(point[k]);
    if (room < best) {
      best = room;
      face_axis = k;
    }
  }
  return feature::box_face(face_axis, point[face_axis] >= 0);
}

Vec3 normalized_or(const Vec3& v, const Vec3& fallback) {
  const Real length = v.norm();
  // norm() underflows to 0 for vectors shorter than about 1e-154; anything longer divides
  // safely and gives a unit vector.
  if (!(length > 0) || !std::isfinite(length))
    return fallback;
  return v / length;
}

bool add_contact(Manifold& out, const Vec3& point_on_a, const Vec3& normal, Real depth, Real margin,
                 FeatureId feature) {
  if (!(depth >= -margin))
    return false;
  out.add(point_on_a + normal * (depth * Real(0.5)), depth, feature);
  return true;
}

}  // namespace tumble::detail
