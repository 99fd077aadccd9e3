// Scalar and geometry aliases of tumble's public API, used by every part of the engine too. The
// whole engine computes in one scalar type, `Real`, so that a change of precision is a change of
// one line. Vectors and rotations are Eigen's (Eigen 3.4, header-only).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tumble {

using Real = double;
using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;
using Quat = Eigen::Quaternion<Real>;

// q * v, by the operations of Eigen's own (QuaternionBase::_transformVector: u = 2 (q_xyz x v),
// then v + w u + q_xyz x u) in the same order, so the same bits; written out because GCC keeps
// Eigen's out of line, a call for every point of the loops that move points between frames.
inline Vec3 rotate_vector(const Quat& q, const Vec3& v) {
  const Real x = q.x(), y = q.y(), z = q.z(), w = q.w();
  Real u0 = y * v.z() - z * v.y();
  Real u1 = z * v.x() - x * v.z();
  Real u2 = x * v.y() - y * v.x();
  u0 += u0;
  u1 += u1;
  u2 += u2;
  return Vec3(v.x() + w * u0 + (y * u2 - z * u1), v.y() + w * u1 + (z * u0 - x * u2),
              v.z() + w * u2 + (x * u1 - y * u0));
}

// A rigid transform: p_world = rotation * p_local + translation. Beware `Transform{t, {}}`:
// Eigen's default quaternion constructor leaves it uninitialised; write Quat::Identity().
struct Transform {
  Vec3 translation = Vec3::Zero();
  Quat rotation = Quat::Identity();

  Vec3 apply(const Vec3& p) const { return rotate_vector(rotation, p) + translation; }
  Vec3 apply_inverse(const Vec3& p) const {
    return rotate_vector(rotation.conjugate(), p - translation);
  }
  Vec3 rotate(const Vec3& v) const { return rotate_vector(rotation, v); }
  Vec3 rotate_inverse(const Vec3& v) const { return rotate_vector(rotation.conjugate(), v); }
  // The transform undone: inverse().apply(apply(p)) is p.
  Transform inverse() const { return {rotate_inverse(-translation), rotation.conjugate()}; }
  // `pose` seen from this frame (a body's pose in another body's frame): inverse() then pose.
  Transform relative(const Transform& pose) const {
    return {rotate_inverse(pose.translation - translation), rotation.conjugate() * pose.rotation};
  }
};

}  // namespace tumble
