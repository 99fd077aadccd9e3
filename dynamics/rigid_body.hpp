// Rigid body state and mass properties. The state is what a step changes; mass properties are
// fixed by the scene.
#pragma once

#include "collision/math.hpp"
#include "tumble/body_state.hpp"

namespace tumble {

// Inverse mass properties; static bodies have all zeros, so the solver treats every body alike.
struct BodyMass {
  Real inverse_mass = 0;                // 1/kg
  Mat3 inertia = Mat3::Zero();          // kg m^2, body frame, about the centre of mass
  Mat3 inverse_inertia = Mat3::Zero();  // body frame
  bool is_isotropic = true;             // inertia is a multiple of identity: no gyroscopic torque

  static BodyMass make(Real mass, const Mat3& inertia, bool is_static);
};

// Kinetic energy, translational plus rotational [J].
Real kinetic_energy(const BodyState& state, const BodyMass& mass);

// Simulation-frame angular momentum about the centre of mass [kg m^2/s].
Vec3 angular_momentum(const BodyState& state, const BodyMass& mass);

}  // namespace tumble
