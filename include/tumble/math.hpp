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

// A rigid transform: p_world = rotation * p_local + translation. Beware `Transform{t, {}}`:
// Eigen's default quaternion constructor leaves it uninitialised; write Quat::Identity().
struct Transform {
  Vec3 translation = Vec3::Zero();
  Quat rotation = Quat::Identity();

  Vec3 apply(const Vec3& p) const { return rotation * p + translation; }
  Vec3 apply_inverse(const Vec3& p) const { return rotation.conjugate() * (p - translation); }
  Vec3 rotate(const Vec3& v) const { return rotation * v; }
  Vec3 rotate_inverse(const Vec3& v) const { return rotation.conjugate() * v; }
  // The transform undone: inverse().apply(apply(p)) is p.
  Transform inverse() const { return {rotate_inverse(-translation), rotation.conjugate()}; }
  // `pose` seen from this frame (a body's pose in another body's frame): inverse() then pose.
  Transform relative(const Transform& pose) const {
    return {rotate_inverse(pose.translation - translation), rotation.conjugate() * pose.rotation};
  }
};

}  // namespace tumble
