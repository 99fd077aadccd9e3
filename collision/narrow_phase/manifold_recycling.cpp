#include "collision/narrow_phase/manifold_recycling.hpp"

#include <cmath>

namespace tumble {

RecyclableManifold make_recyclable(std::int32_t body_a, std::int32_t body_b, const Manifold& m,
                                   const Transform& a, const Transform& b) {
  RecyclableManifold r;
  r.body_a = body_a;
  r.body_b = body_b;
  r.relative_position = a.rotate_inverse(b.translation - a.translation);
  r.relative_orientation = (a.rotation.conjugate() * b.rotation).normalized();
  r.normal = a.rotate_inverse(m.normal);
  r.count = m.count;
  r.reusable = m.count > 1;
  for (int k = 0; k < m.count; ++k) {
    const ContactPoint& p = m.points[std::size_t(k)];
    // Differences first, so that bodies far from the origin keep their digits.
    const Vec3 to_a = (p.position - a.translation) - m.normal * (p.depth * Real(0.5));
    const Vec3 to_b = (p.position - b.translation) + m.normal * (p.depth * Real(0.5));
    r.point_a[std::size_t(k)] = a.rotate_inverse(to_a);
    r.point_b[std::size_t(k)] = b.rotate_inverse(to_b);
    r.feature[std::size_t(k)] = p.feature;
  }
  return r;
}

bool recycle(const RecyclableManifold& kept, const Transform& a, const Transform& b,
             Real max_distance, Real max_angle, Manifold& out) {
  return recycle_within_half_sine(kept, a, b, max_distance, std::sin(Real(0.5) * max_angle), out);
}

bool recycle_within_half_sine(const RecyclableManifold& kept, const Transform& a,
                              const Transform& b, Real max_distance, Real max_half_sine,
                              Manifold& out) {
  if (!kept.reusable)
    return false;
  const Vec3 offset = b.translation - a.translation;
  const Vec3 relative_position = a.rotate_inverse(offset);
  if (!((relative_position - kept.relative_position).squaredNorm() <= max_distance * max_distance))
    return false;
  // The angle of the rotation from the kept relative orientation to the current one:
  // 2 asin(|vector part|) of q_kept^-1 q_now, compared through its half-angle sine.
  const Quat relative_orientation = a.rotation.conjugate() * b.rotation;
  const Quat change = kept.relative_orientation.conjugate() * relative_orientation;
  const Real half_sine = change.vec().norm();
  if (!(half_sine <= max_half_sine))
    return false;
  out.normal = a.rotate(kept.normal);
  out.count = kept.count;
  for (int k = 0; k < kept.count; ++k) {
    const Vec3 on_a = a.rotate(kept.point_a[std::size_t(k)]);           // from A's origin
    const Vec3 on_b = offset + b.rotate(kept.point_b[std::size_t(k)]);  // from A's origin
    const Real depth = (on_b - on_a).dot(out.normal);
    ContactPoint& p = out.points[std::size_t(k)];
    p.depth = depth;
    p.position = a.translation + Real(0.5) * (on_a + on_b);
    p.feature = kept.feature[std::size_t(k)];
  }
  return true;
}

}  // namespace tumble
