// Time integration of free rigid bodies over one step h.
//
// Linear motion is semi-implicit (symplectic) Euler: v += h g, then x += h v.
//
// Rotation uses the implicit midpoint rule on Euler's equations in the body frame,
//   I (w2 - w1) = -h wm x (I wm),   wm = (w1 + w2) / 2,
// followed by the orientation update q2 = q1 * cay(h wm), where cay is the Cayley rotation
// (quaternion (1, h wm / 2), normalised). The midpoint rule conserves the quadratic invariants
// |I w|^2 and w . I w, and the Cayley update rotates the body by exactly the inverse of the
// rotation that the midpoint rule applies to body-frame momentum, so a torque-free body keeps
// its world angular momentum and its kinetic energy to rounding. Backward Euler (Catto, GDC 2015
// "Numerical Methods") would be stable too but bleeds momentum; explicit Euler gains energy.
// Reference: Hairer, Lubich, Wanner, "Geometric Numerical Integration", IV.2 and VII.5.
#pragma once

#include <cstdint>

#include "dynamics/rigid_body.hpp"

namespace tumble {

// What velocity integration leaves for position integration: the half of the gyroscopic
// velocity change (body frame) that the midpoint rule does not apply to the pose.
struct GyroscopicCarry {
  Vec3 half_change_body = Vec3::Zero();
};

// Gravity and gyroscopic term. Leaves the angular velocity in the world frame of the current
// orientation; contact impulses are then added to both velocities by the solver.
void integrate_velocity(BodyState& state, const BodyMass& mass, const Vec3& gravity, Real h,
                        GyroscopicCarry& carry);

// Advances the pose with the solved velocities and rotates the world angular velocity with
// the body.
void integrate_position(BodyState& state, const GyroscopicCarry& carry, Real h);

// What velocity integration reads and writes, indexed by body.
struct VelocityIntegration {
  BodyState* states = nullptr;
  const BodyMass* masses = nullptr;
  GyroscopicCarry* carries = nullptr;
  Vec3 gravity = Vec3::Zero();
  // Bodies with loads: loaded[i] != 0 adds forces[i] / mass to gravity. Null for none.
  const std::uint8_t* loaded = nullptr;
  const Vec3* forces = nullptr;
  Real h = 0;
};

struct PositionIntegration {
  BodyState* states = nullptr;
  const GyroscopicCarry* carries = nullptr;
  Real h = 0;
};

// The same two updates for many bodies: bodies body[0..count), each listed once, in bundles as wide
// as the CPU's vector registers. A body gets the same bits as from the one-body functions above,
// whatever bodies share its bundle (dynamics/integrator_lanes.inc).
void integrate_velocities(const VelocityIntegration& in, const std::int32_t* body, int count);
void integrate_positions(const PositionIntegration& in, const std::int32_t* body, int count);

}  // namespace tumble
