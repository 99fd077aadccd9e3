// Whether a kinematic target can be reached: one rule for World::set_kinematic_target and for the
// batch's kinematic_targets, so a batch world refuses what a lone World refuses.
#pragma once

#include <string>

#include "engine/number_text.hpp"
#include "tumble/body_state.hpp"

namespace tumble {

// Why a body now at `now` cannot be sent to (position, orientation) in one step of `dt`, or an
// empty string: the target must be finite and within 1e9 m, the orientation a non-zero
// quaternion, and the motion no faster than 1e6 m/s and 1e6 rad/s (the engine's speed limits).
inline std::string kinematic_target_problem(const BodyState& now, const Vec3& position,
                                            const Quat& orientation, Real dt) {
  constexpr Real kMostCoordinate = 1e9;
  constexpr Real kMostSpeed = 1e6;
  if (!(position.allFinite() && position.cwiseAbs().maxCoeff() <= kMostCoordinate))
    return "position " + vector_text(position) + " m is not finite or beyond 1e9";
  if (!(orientation.coeffs().allFinite() && orientation.norm() > 1e-9))
    return "the orientation is not a finite, non-zero quaternion";
  const Real travel = (position - now.position).norm();
  if (!(travel / dt <= kMostSpeed))
    return "the target " + vector_text(position) + " is " + number_text(travel) +
           " m away, more than 1e6 m/s over one step";
  const Real turn = now.orientation.angularDistance(orientation.normalized());
  if (!(turn / dt <= kMostSpeed))
    return "turning " + number_text(turn) + " rad in one step is more than 1e6 rad/s";
  return {};
}

}  // namespace tumble
