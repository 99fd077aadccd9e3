// Sphere against sphere, capsule, box and plane: closed forms. A sphere is a point with a radius,
// so each pair is "closest point of the other shape's core to the centre", then offset by the
// radii (Ericson, Real-Time Collision Detection, 2005: 5.1.2 point-segment, 5.1.4 point-OBB).
#include <cmath>

#include "collision/pairs/pairs.hpp"

namespace tumble::detail {

int sphere_sphere(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                  Real margin, Manifold& out) {
  const Vec3 between = pose_a.translation - pose_b.translation;
  // Coincident centres have no preferred direction: push A up the world z axis (a ball dropped
  // exactly into another pops up, the least surprising choice under gravity). Of two spheres,
  // A here is the one that runs first in narrow_phase.cpp's order: the smaller.
  const Vec3 normal = normalized_or(between, Vec3::UnitZ());
  const Real depth = a.radius + b.radius - between.dot(normal);
  out.normal = normal;
  add_contact(out, pose_a.translation - normal * a.radius, normal, depth, margin,
              {feature::kSphere, feature::kSphere});
  return out.count;
}

int sphere_capsule(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                   Real margin, Manifold& out) {
  const Segment core = capsule_segment(b, pose_b);
  const Real t = closest_parameter_on_segment(pose_a.translation, core.start, core.end);
  const Vec3 closest = core.start + (core.end - core.start) * t;
  const Vec3 between = pose_a.translation - closest;
  // A centre on the core segment (closer than 1e-12 of the pair's size, where the offset is
  // rounding and could point along the axis): any direction across the axis is a minimum
  // translation; take the capsule's local x axis so the choice is deterministic.
  const Real scale = a.radius + b.radius + b.half_length;
  const Vec3 normal = between.norm() > Real(1e-12) * scale ? Vec3(between.normalized())
                                                           : Vec3(pose_b.rotate(Vec3::UnitX()));
  const Real depth = a.radius + b.radius - between.dot(normal);
  out.normal = normal;
  add_contact(out, pose_a.translation - normal * a.radius, normal, depth, margin,
              {feature::kSphere, feature::capsule_feature_at(t)});
  return out.count;
}

int sphere_box(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
               Real margin, Manifold& out) {
  const Vec3& half = b.half_extents;
  const Vec3 centre = pose_b.apply_inverse(pose_a.translation);  // in the box's frame
  const Vec3 clamped = centre.cwiseMax(-half).cwiseMin(half);
  const Vec3 outward = centre - clamped;
  const Real outside_distance = outward.norm();

  Vec3 local_normal;
  Real depth = 0;
  std::uint16_t box_feature = 0;
  // Outside by less than 1e-12 of the pair's size is on the surface: there the offset is
  // rounding, and the face rule below gives the well-defined normal.
  if (outside_distance > Real(1e-12) * (a.radius + half.norm())) {
    // Centre outside: the clamped point is the closest point of the box (Ericson 5.1.4.1).
    local_normal = outward / outside_distance;
    depth = a.radius - outside_distance;
    box_feature = box_feature_of_outside_point(centre, half);
  } else {
    // Centre inside or on the surface: leave through the face with the least penetration. Ties
    // (the exact centre, a point on an edge) take the lowest axis and its positive side, so
    // the normal is deterministic and finite.
    int axis = 0;
    Real room = half[0] - std::abs(centre[0]);
    for (int k = 1; k < 3; ++k) {
      const Real room_k = half[k] - std::abs(centre[k]);
      if (room_k < room) {
        room = room_k;
        axis = k;
      }
    }
    const bool positive = centre[axis] >= 0;
    local_normal = Vec3::Unit(axis) * (positive ? Real(1) : Real(-1));
    depth = a.radius + room;
    box_feature = feature::box_face(axis, positive);
  }
  const Vec3 normal = pose_b.rotate(local_normal);
  out.normal = normal;
  add_contact(out, pose_a.translation - normal * a.radius, normal, depth, margin,
              {feature::kSphere, box_feature});
  return out.count;
}

int sphere_plane(const Shape& a, const Transform& pose_a, const Shape& /*plane*/,
                 const Transform& pose_b, Real margin, Manifold& out) {
  const Vec3 normal = pose_b.rotate(Vec3::UnitZ());
  const Real height = normal.dot(pose_a.translation - pose_b.translation);
  out.normal = normal;
  add_contact(out, pose_a.translation - normal * a.radius, normal, a.radius - height, margin,
              {feature::kSphere, feature::kPlane});
  return out.count;
}

}  // namespace tumble::detail
