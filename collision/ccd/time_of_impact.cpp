#include <algorithm>
#include <limits>

#include "collision/ccd/conservative_advancement.hpp"

namespace tumble {

std::string_view toi_status_name(ToiStatus status) {
  switch (status) {
    case ToiStatus::separated:
      return "separated";
    case ToiStatus::hit:
      return "hit";
    case ToiStatus::overlapping:
      return "overlapping";
    case ToiStatus::max_iterations:
      return "max_iterations";
    case ToiStatus::invalid_input:
      return "invalid_input";
  }
  return "unknown";
}

ToiResult time_of_impact(const Shape& a, const RigidMotion& motion_a, const Shape& b,
                         const RigidMotion& motion_b, const ToiSettings& settings) {
  const Real radius_a = bounding_radius(a);
  const Real radius_b = bounding_radius(b);
  // Beyond this gap the shapes cannot meet within the motion; asking the narrow phase about
  // larger gaps only costs time.
  Real reach = motion_a.centre_speed() + motion_b.centre_speed();
  if (motion_a.angular_velocity().norm() > 0)
    reach += motion_a.angular_velocity().norm() * radius_a;
  if (motion_b.angular_velocity().norm() > 0)
    reach += motion_b.angular_velocity().norm() * radius_b;
  const Real max_distance =
      reach + std::max(settings.target_distance, Real(0)) + settings.tolerance + Real(1e-9);
  const Real stop = stop_distance(settings);
  // Centres on straight lines: the mesh pairs may measure their advance along each triangle's
  // own axis (shape_distance.hpp).
  ClosingMotion closing;
  const bool straight =
      motion_a.kind() == MotionKind::linear && motion_b.kind() == MotionKind::linear;
  if (straight) {
    closing.relative_velocity = motion_a.linear_velocity() - motion_b.linear_velocity();
    closing.spin_bound = turning_closing_speed(motion_a, radius_a, motion_b, radius_b);
    closing.target_distance = settings.target_distance;
  }
  auto distance = [&](const Transform& pa, const Transform& pb) {
    return shape_distance_bound(a, pa, b, pb, max_distance, stop, straight ? &closing : nullptr);
  };
  return conservative_advancement(motion_a, radius_a, motion_b, radius_b, distance, settings);
}

ToiResult shape_cast(const Shape& moving, const Transform& pose, const Vec3& translation,
                     const Shape& target, const Transform& target_pose,
                     const ToiSettings& settings) {
  Transform end = pose;
  end.translation += translation;
  return time_of_impact(moving, RigidMotion(pose, end), target,
                        RigidMotion::stationary(target_pose), settings);
}

}  // namespace tumble
