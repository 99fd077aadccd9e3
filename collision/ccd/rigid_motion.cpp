// Rigid motion over a step (docs/ccd.md). The SE(3) exponential and logarithm follow the closed
// forms of Murray, Li and Sastry, "A Mathematical Introduction to Robotic Manipulation", 1994,
// section 2.3 (Rodrigues' formula and the matrix V of the translational part), with Taylor
// series below a small angle where the closed forms lose digits.
#include "collision/ccd/rigid_motion.hpp"

#include <cmath>

namespace tumble {
namespace {

// Coefficients of V(phi) = I + b(theta) [phi]x + c(theta) [phi]x^2 for theta = |phi|:
// b = (1 - cos theta) / theta^2, c = (theta - sin theta) / theta^3.
void v_coefficients(Real theta, Real& b, Real& c) {
  if (theta < Real(1e-3)) {
    const Real t2 = theta * theta;
    b = Real(0.5) - t2 / 24 + t2 * t2 / 720;
    c = Real(1) / 6 - t2 / 120 + t2 * t2 / 5040;
    return;
  }
  const Real t2 = theta * theta;
  b = (1 - std::cos(theta)) / t2;
  c = (theta - std::sin(theta)) / (t2 * theta);
}

Mat3 v_matrix(const Vec3& phi) {
  Real b = 0;
  Real c = 0;
  v_coefficients(phi.norm(), b, c);
  const Mat3 k = skew(phi);
  return Mat3::Identity() + b * k + c * (k * k);
}

}  // namespace

Quat quaternion_from_rotation_vector(const Vec3& rotation_vector) {
  const Real angle = rotation_vector.norm();
  const Real half = Real(0.5) * angle;
  // sin(half) / angle, with its series near zero.
  const Real s = angle < Real(1e-4) ? Real(0.5) - angle * angle / 48 : std::sin(half) / angle;
  return Quat(std::cos(half), s * rotation_vector.x(), s * rotation_vector.y(),
              s * rotation_vector.z());
}

Vec3 rotation_vector_from_quaternion(const Quat& q_in) {
  Quat q = q_in.normalized();
  if (q.w() < 0)
    q.coeffs() = -q.coeffs();  // the shorter way round: angle in [0, pi]
  const Vec3 xyz = q.vec();
  const Real sin_half = xyz.norm();
  // atan2 keeps full precision for small and for near-pi angles alike.
  const Real angle = 2 * std::atan2(sin_half, q.w());
  if (sin_half < Real(1e-12))
    return 2 * xyz;  // angle ~ 2 sin_half
  return xyz * (angle / sin_half);
}

RigidMotion::RigidMotion(const Transform& start, const Transform& end, MotionKind kind)
    : start_(start), end_(end), kind_(kind) {
  start_.rotation.normalize();
  end_.rotation.normalize();
  const Quat relative = end_.rotation * start_.rotation.conjugate();
  rotation_vector_ = rotation_vector_from_quaternion(relative);
  if (kind_ == MotionKind::linear) {
    centre_speed_ = (end_.translation - start_.translation).norm();
    return;
  }
  // T1 T0^-1 = (R, d) with d = x1 - R x0. Its log is (phi, v) with d = V(phi) v.
  const Vec3 d = end_.translation - (relative * start_.translation);
  screw_velocity_ = v_matrix(rotation_vector_).lu().solve(d);
  // Velocity of the centre at s: omega x x(s) + v; its norm is constant along the helix, so
  // evaluating it at s = 0 is exact for every s.
  centre_speed_ = (rotation_vector_.cross(start_.translation) + screw_velocity_).norm();
}

RigidMotion RigidMotion::from_velocity(const Transform& start, const Vec3& velocity,
                                       const Vec3& angular_velocity) {
  Transform end;
  end.translation = start.translation + velocity;
  end.rotation = (quaternion_from_rotation_vector(angular_velocity) * start.rotation).normalized();
  RigidMotion m(start, end, MotionKind::linear);
  m.rotation_vector_ = angular_velocity;  // keeps turns beyond pi that the quaternion forgets
  return m;
}

Transform RigidMotion::at(Real s) const {
  if (s <= 0)
    return start_;
  if (s >= 1 && kind_ == MotionKind::linear && rotation_vector_.norm() <= Real(M_PI))
    return end_;
  Transform out;
  const Quat turn = quaternion_from_rotation_vector(s * rotation_vector_);
  out.rotation = (turn * start_.rotation).normalized();
  if (kind_ == MotionKind::linear) {
    out.translation = (1 - s) * start_.translation + s * end_.translation;
    return out;
  }
  // exp(s xi) = (R(s), V(s phi) s v), applied to T0.
  const Vec3 step_translation = v_matrix(s * rotation_vector_) * (s * screw_velocity_);
  out.translation = turn * start_.translation + step_translation;
  return out;
}

}  // namespace tumble
