// Capsule against box. There is no neat closed form, so the pair is split by whether the
// capsule's core segment reaches the box.
//
// Core outside the box: the distance from a point to a convex set is convex, so along the core
// s(t) = sdf_box(p0 + t (p1 - p0)) is a convex function of t. It is also piecewise simple: between
// the parameters where the segment crosses a slab plane x_k = +-h_k, the set of clamped
// coordinates does not change and s(t)^2 is a quadratic in t. Minimising that quadratic on each
// piece and keeping the best piece is an exact minimisation (no iteration, no tolerance); the
// normal is the gradient of the box's signed distance there, i.e. the direction from the
// closest box point to the core point (Ericson, Real-Time Collision Detection, 2005, 5.1.4;
// Quilez, "Distance functions" for the box SDF). This "exact piecewise analysis" replaces a
// golden-section search: same convexity argument, exact answer and ties broken deterministically.
//
// Core touching or inside the box: the Minkowski difference of capsule and box is the
// difference of core segment and box, rounded by the radius, and for a point inside a convex
// set the depth in the rounded set is the depth in the core set plus the radius with the same
// direction. So the minimum translation is a separating-axis test of segment against box (its 3
// face normals and the 3 cross products of the segment with the box edges; Gottschalk, Lin and
// Manocha, "OBBTree", SIGGRAPH 1996; Ericson 5.2.1) plus the radius. Unlike box-box, the axis
// is chosen exactly (up to rounding): this branch only runs for penetrations deeper than the
// radius, where the true minimum translation matters more than feature stability.
//
// Points: when the normal is a box face normal, the core is clipped to the prism over that face
// and both ends of the clipped core become points (depth measured along the normal), so a capsule
// lying flat on a box, or across its edge, gets two points; otherwise one point.
#include <algorithm>
#include <array>
#include <cmath>

#include "collision/narrow_phase/pairs/pairs.hpp"

namespace tumble::detail {
namespace {

// The core counts as reaching the box when its distance is below 1e-9 of the pair's size:
// closer than that, the gradient direction is rounding noise and the separating-axis normal is
// the better answer (the two agree on the depth to that tolerance).
constexpr Real kCoreTouchTolerance = Real(1e-9);
// Cross products of the core with a box edge shorter than this (sine of the angle) are left
// out of the separating-axis test; the face axes cover those directions.
constexpr Real kMinCrossSine = Real(1e-6);
// Separations that differ by less than this fraction of the pair's size are equal.
constexpr Real kAxisRoundingTolerance = Real(1e-12);

struct CapsuleInBox {
  Vec3 start;  // core segment start, box frame
  Vec3 axis;   // end - start, box frame
  Real radius;
  Vec3 half;  // box half extents
  Real tiny;  // lengths below this are zero
  const Transform* box_pose;

  Vec3 at(Real t) const { return start + axis * t; }
};

// The minimum over t in [0, 1] of the box's signed distance along the core (see the file
// comment). Returns the distance and writes the parameter; ties keep the smallest t.
Real minimize_distance_along_core(const CapsuleInBox& c, Real& best_t) {
  std::array<Real, 8> knots{};
  int knot_count = 0;
  knots[knot_count++] = 0;
  knots[knot_count++] = 1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(c.axis[k]) <= c.tiny)
      continue;
    for (const Real bound : {-c.half[k], c.half[k]}) {
      const Real t = (bound - c.start[k]) / c.axis[k];
      if (t > 0 && t < 1)
        knots[knot_count++] = t;
    }
  }
  // Insertion sort: at most 8 values, and no std::sort false positive from -Warray-bounds.
  for (int i = 1; i < knot_count; ++i) {
    for (int j = i; j > 0 && knots[j] < knots[j - 1]; --j)
      std::swap(knots[j], knots[j - 1]);
  }

  best_t = 0;
  Real best = box_signed_distance(c.at(0), c.half);
  const auto consider = [&](Real t) {
    const Real value = box_signed_distance(c.at(t), c.half);
    if (value < best) {
      best = value;
      best_t = t;
    }
  };
  for (int i = 1; i < knot_count; ++i)
    consider(knots[i]);
  // Inside each piece the clamped coordinates are fixed: minimise their squared distance.
  for (int i = 0; i + 1 < knot_count; ++i) {
    const Real low = knots[i];
    const Real high = knots[i + 1];
    if (!(high > low))
      continue;
    const Vec3 middle = c.at((low + high) * Real(0.5));
    Real slope = 0;      // sum over clamped k of (start_k - bound_k) * axis_k
    Real curvature = 0;  // sum over clamped k of axis_k^2
    for (int k = 0; k < 3; ++k) {
      if (std::abs(middle[k]) <= c.half[k])
        continue;
      const Real bound = middle[k] > 0 ? c.half[k] : -c.half[k];
      slope += (c.start[k] - bound) * c.axis[k];
      curvature += c.axis[k] * c.axis[k];
    }
    if (curvature > c.tiny * c.tiny)
      consider(std::clamp(-slope / curvature, low, high));
  }
  return best;
}

// Contacts for a normal along the box face (axis, sign): the core clipped to the prism over the
// face (Liang-Barsky against the four side slabs), both ends as points. `t_keep` is the core
// parameter that must be in the manifold (the closest point); when the clip comes out empty
// through rounding it is used alone, and with `extend` the clipped range is widened to hold it.
void add_face_contacts(const CapsuleInBox& c, int axis, bool positive, Real t_keep, bool extend,
                       Real margin, Manifold& out) {
  const Real sign = positive ? Real(1) : Real(-1);
  Real t_low = 0;
  Real t_high = 1;
  std::uint16_t low_feature = feature::box_face(axis, positive);
  std::uint16_t high_feature = low_feature;
  bool empty = false;
  for (int m = 0; m < 3 && !empty; ++m) {
    if (m == axis)
      continue;
    if (std::abs(c.axis[m]) <= c.tiny) {
      empty = std::abs(c.start[m]) > c.half[m];
      continue;
    }
    Real t_minus = (-c.half[m] - c.start[m]) / c.axis[m];
    Real t_plus = (c.half[m] - c.start[m]) / c.axis[m];
    bool enter_minus = true;  // the side slab the core enters through
    if (t_minus > t_plus) {
      std::swap(t_minus, t_plus);
      enter_minus = false;
    }
    // The edge shared by the face and the side slab (m, side).
    const auto edge_on_side = [&](bool side_positive) {
      const int third = 3 - axis - m;
      const int bits = (positive ? 1 << axis : 0) | (side_positive ? 1 << m : 0);
      return feature::box_edge(third, bits);
    };
    if (t_minus > t_low) {
      t_low = t_minus;
      low_feature = edge_on_side(!enter_minus);
    }
    if (t_plus < t_high) {
      t_high = t_plus;
      high_feature = edge_on_side(enter_minus);
    }
  }
  if (empty || t_low > t_high) {
    t_low = t_high = t_keep;
    low_feature = high_feature = feature::box_face(axis, positive);
  } else if (extend) {
    if (t_keep < t_low) {
      t_low = t_keep;
      low_feature = feature::box_face(axis, positive);
    }
    if (t_keep > t_high) {
      t_high = t_keep;
      high_feature = feature::box_face(axis, positive);
    }
  }

  const Vec3 local_normal = Vec3::Unit(axis) * sign;
  const Vec3 normal = c.box_pose->rotate(local_normal);
  out.normal = normal;
  const auto add_at = [&](Real t, std::uint16_t box_feature) {
    const Vec3 core_point = c.at(t);
    const Real height = sign * core_point[axis] - c.half[axis];
    add_contact(out, c.box_pose->apply(core_point - local_normal * c.radius), normal,
                c.radius - height, margin, {feature::capsule_feature_at(t), box_feature});
  };
  add_at(t_low, low_feature);
  // A second point only when the clipped core has length (not for a zero-length capsule).
  if ((t_high - t_low) * c.axis.norm() > c.tiny)
    add_at(t_high, high_feature);
}

// Core outside the box: the closest point and its gradient normal.
void collide_core_outside(const CapsuleInBox& c, Real t, Real margin, Manifold& out) {
  const Vec3 core_point = c.at(t);
  int outside_count = 0;
  int outside_axis = 0;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(core_point[k]) > c.half[k]) {
      ++outside_count;
      outside_axis = k;
    }
  }
  if (outside_count == 1) {
    add_face_contacts(c, outside_axis, core_point[outside_axis] > 0, t, true, margin, out);
    return;
  }
  // Nearest to an edge or a vertex: one point.
  const Vec3 box_point = core_point.cwiseMax(-c.half).cwiseMin(c.half);
  const Vec3 offset = core_point - box_point;
  const Vec3 local_normal = normalized_or(offset, Vec3::UnitZ());
  const Vec3 normal = c.box_pose->rotate(local_normal);
  out.normal = normal;
  add_contact(out, c.box_pose->apply(core_point - local_normal * c.radius), normal,
              c.radius - offset.dot(local_normal), margin,
              {feature::capsule_feature_at(t), box_feature_of_outside_point(core_point, c.half)});
}

// Core touching or inside the box: separating-axis test of the core segment against the box.
void collide_core_inside(const CapsuleInBox& c, Real scale, Real margin, Manifold& out) {
  const Vec3 centre = c.start + c.axis * Real(0.5);
  const Vec3 half_axis = c.axis * Real(0.5);

  int face_axis = 0;
  bool face_positive = true;
  Real face_separation = -std::numeric_limits<Real>::infinity();
  for (int k = 0; k < 3; ++k) {
    const Real separation = std::abs(centre[k]) - c.half[k] - std::abs(half_axis[k]);
    if (separation > face_separation) {
      face_separation = separation;
      face_axis = k;
      face_positive = centre[k] >= 0;
    }
  }

  int edge_axis = -1;
  Vec3 edge_normal = Vec3::Zero();
  Real edge_separation = -std::numeric_limits<Real>::infinity();
  const Real axis_length = c.axis.norm();
  for (int k = 0; k < 3; ++k) {
    const Vec3 cross = c.axis.cross(Vec3::Unit(k));
    const Real length = cross.norm();
    if (!(length > kMinCrossSine * axis_length))
      continue;
    Vec3 direction = cross / length;
    if (direction.dot(centre) < 0)
      direction = -direction;
    // The core projects to a point on this axis (it is perpendicular to the core).
    const Real separation = direction.dot(centre) - c.half.dot(direction.cwiseAbs());
    if (separation > edge_separation) {
      edge_separation = separation;
      edge_axis = k;
      edge_normal = direction;
    }
  }

  // Exact choice, up to rounding: this branch only runs when the core itself reaches the box
  // (a penetration deeper than the radius), where the true minimum translation matters more
  // than feature stability. An edge axis equal to a face axis (a core parallel to a box axis)
  // differs from it by rounding only, and the face, with its two points, keeps it.
  if (edge_axis < 0 || !(edge_separation > face_separation + kAxisRoundingTolerance * scale)) {
    // The deepest end of the core along the face normal, kept if the clip loses everything.
    const Real sign = face_positive ? Real(1) : Real(-1);
    const Real t_deepest = sign * c.axis[face_axis] >= 0 ? Real(0) : Real(1);
    add_face_contacts(c, face_axis, face_positive, t_deepest, false, margin, out);
    return;
  }

  // Edge axis: the box edge parallel to `edge_axis` that is extreme along the normal, against
  // the core; one point at their closest points.
  int bits = 0;
  for (int m = 0; m < 3; ++m) {
    if (m != edge_axis && edge_normal[m] >= 0)
      bits |= 1 << m;
  }
  Vec3 edge_start;
  for (int m = 0; m < 3; ++m)
    edge_start[m] = (bits >> m) & 1 ? c.half[m] : -c.half[m];
  edge_start[edge_axis] = -c.half[edge_axis];
  Vec3 edge_end = edge_start;
  edge_end[edge_axis] = c.half[edge_axis];
  Real s = 0;
  Real t = 0;
  closest_parameters_between_segments(c.start, c.start + c.axis, edge_start, edge_end, s, t);
  const Vec3 core_point = c.at(s);
  const Vec3 edge_point = edge_start + (edge_end - edge_start) * t;
  const Vec3 normal = c.box_pose->rotate(edge_normal);
  out.normal = normal;
  add_contact(out, c.box_pose->apply(core_point - edge_normal * c.radius), normal,
              c.radius - (core_point - edge_point).dot(edge_normal), margin,
              {feature::capsule_feature_at(s), feature::box_edge(edge_axis, bits)});
}

}  // namespace

int capsule_box(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                Real margin, Manifold& out) {
  const Segment core = capsule_segment(a, pose_a);
  CapsuleInBox c;
  c.start = pose_b.apply_inverse(core.start);
  c.axis = pose_b.apply_inverse(core.end) - c.start;
  c.radius = a.radius;
  c.half = b.half_extents;
  c.box_pose = &pose_b;
  const Real scale = c.half.norm() + c.axis.norm() + c.radius;
  // Directions shorter than 1e-15 of the pair's size do not clip or cross anything.
  c.tiny = Real(1e-15) * scale;

  Real t = 0;
  const Real core_distance = minimize_distance_along_core(c, t);
  // Quick reject: the closest point of the capsule is farther than the margin.
  if (c.radius - core_distance < -margin)
    return 0;
  if (core_distance > kCoreTouchTolerance * scale) {
    collide_core_outside(c, t, margin, out);
  } else {
    collide_core_inside(c, scale, margin, out);
  }
  return out.count;
}

}  // namespace tumble::detail
