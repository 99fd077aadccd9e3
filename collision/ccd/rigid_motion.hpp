// Rigid motion of a body over one step, parameterised by s in [0, 1] (docs/ccd.md, "Rigid motion").
//
// Two interpolations between the poses T0 (s = 0) and T1 (s = 1):
//   linear: the centre of mass moves on the straight line x(s) = (1 - s) x0 + s x1 and the
//           orientation turns about a fixed world axis at a constant rate (slerp). This is the
//           motion the integrator makes in one step (constant velocity, constant angular
//           velocity), so it is what the stepper sweeps.
//   screw:  T(s) = exp(s log(T1 T0^-1)) T0, the one-parameter subgroup of SE(3) through the
//           relative transform; every point moves on a helix at a constant speed.
// Both are exact at s = 0 and s = 1 and both turn the body by the same rotation.
#pragma once

#include <cstdint>

#include "collision/math.hpp"

namespace tumble {

enum class MotionKind : std::uint8_t { linear, screw };

class RigidMotion {
 public:
  RigidMotion() = default;
  RigidMotion(const Transform& start, const Transform& end, MotionKind kind = MotionKind::linear);
  // A body at `start` moving with constant velocity [m per unit s] and angular velocity
  // [rad per unit s, world frame] (the linear kind).
  static RigidMotion from_velocity(const Transform& start, const Vec3& velocity,
                                   const Vec3& angular_velocity);
  static RigidMotion stationary(const Transform& pose) { return RigidMotion(pose, pose); }

  Transform at(Real s) const;

  const Transform& start() const { return start_; }
  const Transform& end() const { return end_; }
  MotionKind kind() const { return kind_; }

  // Rotation vector of the whole motion (axis times angle, world frame) [rad per unit s].
  const Vec3& angular_velocity() const { return rotation_vector_; }
  // An upper bound of the speed of the centre of mass over s in [0, 1] [m per unit s]: exact
  // for both kinds (the speed is constant along the line and along the helix).
  Real centre_speed() const { return centre_speed_; }
  // Velocity of the centre of mass of the linear kind (constant) [m per unit s].
  Vec3 linear_velocity() const { return end_.translation - start_.translation; }

 private:
  Transform start_;
  Transform end_;
  MotionKind kind_ = MotionKind::linear;
  Vec3 rotation_vector_ = Vec3::Zero();  // log of end.rotation * start.rotation^-1
  Vec3 screw_velocity_ =
      Vec3::Zero();  // translational part of log(T1 T0^-1) (the "v" of the twist)
  Real centre_speed_ = 0;
};

// exp of a rotation vector (axis * angle) as a unit quaternion; exact near zero.
Quat quaternion_from_rotation_vector(const Vec3& rotation_vector);
// log of a unit quaternion: the rotation vector with angle in [0, pi].
Vec3 rotation_vector_from_quaternion(const Quat& q);

}  // namespace tumble
