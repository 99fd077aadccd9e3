// Sphere against sphere, capsule, box and plane: closed forms. A sphere is a point with a radius,
// so each pair is "closest point of the other shape's core to the centre", then offset by the
// radii (Ericson, Real-Time Collision Detection, 2005: 5.1.2 point-segment, 5.1.4 point-OBB).
#include <cmath>
#include <limits>

#include "collision/narrow_phase/pairs/pairs.hpp"

namespace tumble::detail {

namespace {

// Of two spheres with coincident centres, whether A is pushed up (+z) rather than down.
bool sphere_goes_up(Real radius_a, const Vec3& centre_a, Real radius_b, const Vec3& centre_b) {
  if (radius_a != radius_b)
    return radius_a < radius_b;
  const auto& p = centre_a;
  const auto& q = centre_b;
  return p.x() < q.x() || (p.x() == q.x() && (p.y() < q.y() || (p.y() == q.y() && p.z() <= q.z())));
}

}  // namespace

int sphere_sphere(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                  Real margin, Manifold& out) {
  // Written symmetric in A and B, so the table calls it as it is (no ordering rule, no pair
  // frame): with A and B swapped, `between` and the normal change sign exactly, the length and
  // depth do not change, and the position adds the same centres in the other order and the same
  // offset (both factors change sign). One division for the normal, not three. It works
  // on the world translations directly; their difference is as precise as in a pair frame.
  const Vec3 between = pose_a.translation - pose_b.translation;
  const Real length = between.norm();
  Vec3 normal;
  if (length > 0 && length <= std::numeric_limits<Real>::max()) {
    normal = between * (Real(1) / length);
  } else {
    // Coincident centres (or a NaN/inf offset) have no preferred direction: push the smaller
    // sphere (of equal ones, the lexicographically lower centre) up the world z axis - a ball
    // dropped exactly into another pops up, the least surprising choice under gravity.
    normal =
        Vec3(0, 0,
             sphere_goes_up(a.radius, pose_a.translation, b.radius, pose_b.translation) ? Real(1)
                                                                                        : Real(-1));
  }
  const Real depth = a.radius + b.radius - length;
  if (!(depth >= -margin))
    return 0;
  out.normal = normal;
  // Midway between the surface points a - n r_a and b + n r_b.
  const Real shift = (b.radius - a.radius) * Real(0.5);
  out.add((pose_a.translation + pose_b.translation) * Real(0.5) + normal * shift, depth,
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
