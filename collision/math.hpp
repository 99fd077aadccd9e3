// Scalar and geometry aliases used by every part of tumble. The whole engine computes in one
// scalar type, `Real`, so that a change of precision is a change of one line.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tumble {

using Real = double;
using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;
using Quat = Eigen::Quaternion<Real>;

// A rigid transform: p_world = rotation * p_local + translation. Beware `Transform{t, {}}`:
// Eigen's default quaternion constructor leaves it uninitialised; write Quat::Identity().
struct Transform {
  Vec3 translation = Vec3::Zero();
  Quat rotation = Quat::Identity();

  Vec3 apply(const Vec3& p) const { return rotation * p + translation; }
  Vec3 apply_inverse(const Vec3& p) const { return rotation.conjugate() * (p - translation); }
  Vec3 rotate(const Vec3& v) const { return rotation * v; }
  Vec3 rotate_inverse(const Vec3& v) const { return rotation.conjugate() * v; }
};

inline Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Two unit vectors completing `n` to a right-handed orthonormal basis. Branch-free choice from
// Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017.
inline void orthonormal_basis(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Real sign = n.z() >= 0 ? Real(1) : Real(-1);
  const Real a = Real(-1) / (sign + n.z());
  const Real b = n.x() * n.y() * a;
  t1 = Vec3(Real(1) + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  t2 = Vec3(b, sign + n.y() * n.y() * a, -n.y());
}

}  // namespace tumble
