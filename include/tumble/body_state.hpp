// The state of one body between steps.
#pragma once

#include "tumble/math.hpp"

namespace tumble {

// Pose and velocity of one body, world frame. `position` is the centre of mass.
struct BodyState {
  Vec3 position = Vec3::Zero();          // m
  Quat orientation = Quat::Identity();   // unit, body to world
  Vec3 velocity = Vec3::Zero();          // m/s
  Vec3 angular_velocity = Vec3::Zero();  // rad/s, world frame
};

}  // namespace tumble
