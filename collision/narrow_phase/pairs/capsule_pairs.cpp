// Capsule against capsule and against a plane.
//
// Capsule-capsule: closest points of the two core segments (Ericson, Real-Time Collision
// Detection, 2005, 5.1.9), offset by the radii. When the cores are nearly parallel and their
// projections overlap, one closest point would let a capsule lying on another rock about it, so
// the manifold takes the two ends of the overlap instead, the way Jolt treats a capsule's core as
// a "face" when it is within a small slop of perpendicular to the normal (JoltPhysics,
// CapsuleShape::GetSupportingFace and cCapsuleProjectionSlop = 0.02).
//
// Capsule-plane: each end of the core is a sphere against the plane.
#include <algorithm>
#include <array>
#include <cmath>

#include "collision/narrow_phase/pairs/pairs.hpp"

namespace tumble::detail {
namespace {

// Sine of the largest angle between two cores that still counts as parallel for the two-point
// manifold. Above it one closest point describes the contact well; below it the depth at the
// far end of the overlap differs from the closest depth by at most 2% of the overlap length.
constexpr Real kParallelSine = Real(0.02);

// A normal for cores that touch or cross, where the closest points coincide. Crossing cores:
// the common perpendicular, which is the minimum translation of the two infinite lines.
// Parallel or point-like cores: any direction across them, preferring the one from B's centre
// to A's; +z when even that is undefined (two coincident point cores, as for spheres).
Vec3 normal_for_touching_cores(const Vec3& axis_a, const Vec3& axis_b, const Vec3& centre_offset) {
  const Real length_a = axis_a.norm();
  const Real length_b = axis_b.norm();
  const Vec3 cross = axis_a.cross(axis_b);
  // The cross product of nearly parallel axes is mostly rounding; 1e-6 (sine of the angle)
  // keeps its direction good to about 1e-10 rad.
  if (cross.norm() > Real(1e-6) * length_a * length_b) {
    const Vec3 n = cross.normalized();
    return n.dot(centre_offset) < 0 ? Vec3(-n) : n;
  }
  const Vec3& axis = length_a >= length_b ? axis_a : axis_b;
  const Vec3 unit_axis = normalized_or(axis, Vec3::Zero());
  if (unit_axis.isZero())
    return normalized_or(centre_offset, Vec3::UnitZ());
  const Vec3 across = centre_offset - unit_axis * unit_axis.dot(centre_offset);
  Vec3 t1;
  Vec3 t2;
  orthonormal_basis(unit_axis, t1, t2);
  // An offset shorter than 1e-12 of the axis is rounding, not a direction.
  if (across.norm() > Real(1e-12) * axis.norm())
    return across.normalized();
  return t1;
}

struct CandidatePoint {
  Vec3 position;
  Real depth;
  FeatureId feature;
};

}  // namespace

int capsule_capsule(const Shape& a, const Transform& pose_a, const Shape& b,
                    const Transform& pose_b, Real margin, Manifold& out) {
  const Segment core_a = capsule_segment(a, pose_a);
  const Segment core_b = capsule_segment(b, pose_b);
  const Vec3 axis_a = core_a.end - core_a.start;
  const Vec3 axis_b = core_b.end - core_b.start;
  const Real radii = a.radius + b.radius;
  const Real scale = axis_a.norm() + axis_b.norm() + radii;

  Real s = 0;
  Real t = 0;
  closest_parameters_between_segments(core_a.start, core_a.end, core_b.start, core_b.end, s, t);
  const Vec3 closest_a = core_a.start + axis_a * s;
  const Vec3 closest_b = core_b.start + axis_b * t;
  const Vec3 between = closest_a - closest_b;

  // Closer than 1e-12 of the configuration's size the difference of the closest points is
  // rounding noise, so the touching-core normal takes over.
  const Vec3 normal =
      between.norm() > Real(1e-12) * scale
          ? Vec3(between.normalized())
          : normal_for_touching_cores(axis_a, axis_b, pose_a.translation - pose_b.translation);
  out.normal = normal;
  const Real closest_depth = radii - between.dot(normal);

  // Two points at the ends of the overlap of nearly parallel cores.
  const Real length_a = axis_a.norm();
  const Real length_b = axis_b.norm();
  const Real tiny_length = Real(1e-12) * scale;
  if (length_a > tiny_length && length_b > tiny_length &&
      axis_a.cross(axis_b).norm() <= kParallelSine * length_a * length_b) {
    const Vec3 unit_a = axis_a / length_a;
    const Real b_start_along_a = (core_b.start - core_a.start).dot(unit_a);
    const Real b_end_along_a = (core_b.end - core_a.start).dot(unit_a);
    const Real overlap_low = std::max(Real(0), std::min(b_start_along_a, b_end_along_a));
    const Real overlap_high = std::min(length_a, std::max(b_start_along_a, b_end_along_a));
    if (overlap_high - overlap_low > tiny_length) {
      std::array<CandidatePoint, 2> ends;
      Real deepest = -std::numeric_limits<Real>::infinity();
      const std::array<Real, 2> along = {overlap_low, overlap_high};
      for (int i = 0; i < 2; ++i) {
        const Real s_end = along[i] / length_a;
        const Vec3 on_core_a = core_a.start + axis_a * s_end;
        const Real t_end = closest_parameter_on_segment(on_core_a, core_b.start, core_b.end);
        const Vec3 on_core_b = core_b.start + axis_b * t_end;
        // Depth along the shared normal, as for a face contact, and the position midway between
        // the two surface points. Unless the cores are exactly parallel, the end's own closest
        // points are not exactly along the shared normal; the midpoint splits that sideways
        // offset between the two shapes.
        const Real depth = radii - (on_core_a - on_core_b).dot(normal);
        const Vec3 position =
            ((on_core_a - normal * a.radius) + (on_core_b + normal * b.radius)) * Real(0.5);
        ends[i] = {position,
                   depth,
                   {feature::capsule_feature_at(s_end), feature::capsule_feature_at(t_end)}};
        deepest = std::max(deepest, depth);
      }
      // The pair must still report the true depth; if rounding at a near-parallel limit made
      // both ends shallower than the closest points, the single closest point is the better
      // description.
      if (deepest >= closest_depth - Real(1e-9) * scale) {
        for (const CandidatePoint& end : ends) {
          if (end.depth >= -margin)
            out.add(end.position, end.depth, end.feature);
        }
        return out.count;
      }
    }
  }

  add_contact(out, closest_a - normal * a.radius, normal, closest_depth, margin,
              {feature::capsule_feature_at(s), feature::capsule_feature_at(t)});
  return out.count;
}

int capsule_plane(const Shape& a, const Transform& pose_a, const Shape& /*plane*/,
                  const Transform& pose_b, Real margin, Manifold& out) {
  const Segment core = capsule_segment(a, pose_a);
  const Vec3 normal = pose_b.rotate(Vec3::UnitZ());
  out.normal = normal;
  const std::array<Vec3, 2> ends = {core.start, core.end};
  // A capsule of zero length has one end, not two coincident ones.
  const int end_count = core.start == core.end ? 1 : 2;
  for (int i = 0; i < end_count; ++i) {
    const Real height = normal.dot(ends[i] - pose_b.translation);
    add_contact(out, ends[i] - normal * a.radius, normal, a.radius - height, margin,
                {std::uint16_t(i), feature::kPlane});
  }
  return out.count;
}

}  // namespace tumble::detail
