// The one-body integrator runs the same kernel as the stepper's bundles of bodies
// (dynamics/integrator_lanes.inc), so a body integrated alone and in a bundle gets the same bits.
#include "dynamics/integrator.hpp"

#include <cstdint>

#include "dynamics/integrator_wide.hpp"

namespace tumble {

void integrate_velocity(BodyState& s, const BodyMass& m, const Vec3& gravity, Real h,
                        GyroscopicCarry& carry) {
  VelocityIntegration in;
  in.states = &s;
  in.masses = &m;
  in.carries = &carry;
  in.gravity = gravity;
  in.h = h;
  const std::int32_t only = 0;
  integrate_velocities(in, &only, 1);
}

void integrate_position(BodyState& s, const GyroscopicCarry& carry, Real h) {
  PositionIntegration in;
  in.states = &s;
  in.carries = &carry;
  in.h = h;
  const std::int32_t only = 0;
  integrate_positions(in, &only, 1);
}

void integrate_velocities(const VelocityIntegration& in, const std::int32_t* body, int count) {
  detail::integrator_kernels().integrate_velocities(in, body, count);
}

void integrate_positions(const PositionIntegration& in, const std::int32_t* body, int count) {
  detail::integrator_kernels().integrate_positions(in, body, count);
}

}  // namespace tumble
