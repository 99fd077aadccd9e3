#include "collision/ccd/shape_distance.hpp"

#include <cmath>
#include <limits>

#include "collision/ccd/ray_cast.hpp"
#include "collision/closest_point_on_triangle.hpp"
#include "collision/narrow_phase/gjk_epa/epa.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/narrow_phase/pairs/field_separation.hpp"
#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/shape.hpp"
#include "collision/shapes/triangle_mesh.hpp"

namespace tumble {
namespace {

// A convex shape against a static triangle mesh: the exact signed distance to the nearest
// triangle within `max_distance` (GJK on the shape's core and the triangle's corners, EPA when
// they overlap), with the normal from the mesh to the shape. Not the narrow phase's contact
// depth: its internal-edge rule replaces some normals by a face normal, which is right for a
// contact but is not a distance (it can be larger than the true distance near a convex edge, and
// the advancement would then step past the contact). The query runs in a frame centred on the
// convex shape, for precision far from the origin.
//
// With `motion` (the convex shape's velocity relative to the mesh), also the least advance:
// each triangle is convex, so the gap along its own separating normal n_t bounds its distance
// from below and closes no faster than max(0, -v . n_t) plus the turning's part (Mirtich,
// "Impulse-based Dynamic Simulation of Rigid Body Systems", 1996, ch. 4, per triangle); the least
// of (d_t - target) / that rate over the triangles is how far the motion may advance. A shape
// sliding along a mesh close above it closes on none of its triangles, where the unprojected
// speed would advance it by its gap over its speed, a step at a time. A triangle whose distance
// bound from the shape's ball shows it can limit neither the distance nor, at the full speed, the
// advance is skipped.
DistanceBound convex_mesh_distance(const Shape& convex, const Transform& pose_c,
                                   const Shape& mesh_shape, const Transform& pose_m,
                                   Real max_distance, const ClosingMotion* motion) {
  const TriangleMesh& mesh = *mesh_shape.mesh;
  // The convex shape in the mesh's frame, for the BVH query.
  const Transform in_mesh = pose_m.relative(pose_c);
  const Aabb reach = world_aabb(convex, in_mesh).inflated(std::max(max_distance, Real(0)));
  const ConvexSupport shape_support = ConvexSupport::of(convex, {Vec3::Zero(), pose_c.rotation});
  // The normal found is the nearest triangle's, not a separating axis of the mesh:
  // separating_normal stays false.
  DistanceBound out;
  out.distance = max_distance;
  out.separating_normal = false;
  if (motion != nullptr)
    out.least_advance = std::numeric_limits<Real>::infinity();
  bool found = false;
  // The shape lies in a ball of this radius about its centre, so a triangle whose plane is
  // farther from the centre than the radius plus the nearest distance found cannot be nearer
  // (signed: the depth of an overlap is at most the radius less the plane's distance), and its
  // GJK query is skipped; the band keeps rounding from changing the answer.
  const Real radius = bounding_radius(convex);
  const Real band = Real(1e-9) * (radius + std::abs(max_distance) + mesh.bounding_radius());
  const Real full_speed =
      motion != nullptr ? motion->relative_velocity.norm() + motion->spin_bound : Real(0);
  // Whether a triangle at least `bound` from the shape could limit the advance found so far.
  const auto may_limit_advance = [&](Real bound) {
    return motion != nullptr &&
           !(bound - motion->target_distance >= out.least_advance * full_speed);
  };
  // Whether a triangle at least `bound` from the shape can change the answer: one farther than
  // `max_distance` is not measured at all, and one farther than the nearest found and too far
  // to limit the advance changes neither.
  const auto may_matter = [&](Real bound) {
    return !(bound > max_distance + band) &&
           (!(bound > out.distance + band) || may_limit_advance(bound));
  };
  mesh.for_each_overlapping(reach, [&](int t) {
    // Corners in the world frame, then relative to the shape's centre.
    std::array<Vec3, 3> corners;
    for (int k = 0; k < 3; ++k)
      corners[std::size_t(k)] = pose_m.apply(mesh.corner(t, k)) - pose_c.translation;
    const Vec3 plane_normal = pose_m.rotate(mesh.normal(t));
    const Real plane_offset = plane_normal.dot(corners[0]);
    if (!may_matter(std::abs(plane_offset) - radius))
      return;
    // The same bound from the triangle itself, tighter where the centre lies beside the
    // triangle rather than over it (a terrain's neighbouring triangles share its plane).
    const Real triangle_distance =
        closest_point_on_triangle(Vec3::Zero(), corners[0], corners[1], corners[2]).norm();
    if (!may_matter(triangle_distance - radius))
      return;
    // The shape's own extent towards the plane, tighter than its ball for a shape longer than
    // it is thick: its gap to the plane bounds its distance to the triangle from below. Half of
    // the triangles a swept body's reach takes in lie wholly beyond the distance asked for.
    const Vec3 towards_plane = plane_offset >= 0 ? plane_normal : Vec3(-plane_normal);
    int support_index = 0;
    const Real extent =
        towards_plane.dot(shape_support.core_support(towards_plane, support_index)) +
        shape_support.radius;
    if (!may_matter(std::abs(plane_offset) - extent))
      return;
    const ConvexSupport triangle = ConvexSupport::of_points(corners.data(), 3, {});
    const GjkResult g = gjk(shape_support, triangle);
    Real distance = g.distance;
    Vec3 normal = g.normal;
    if (g.status == GjkStatus::intersecting) {
      const EpaResult e = epa(shape_support, triangle, g);
      distance = -e.depth;
      normal = e.normal;
    }
    // Farther than asked counts as not measured; otherwise keep the nearest triangle.
    if (!(distance <= max_distance))
      return;
    if (motion != nullptr) {
      const Real rate =
          std::max(Real(0), -motion->relative_velocity.dot(normal)) + motion->spin_bound;
      const Real gap = distance - motion->target_distance;
      if (!(rate * out.least_advance <= gap))
        out.least_advance = rate > 0 ? std::max(gap, Real(0)) / rate : out.least_advance;
    }
    if (found && distance >= out.distance)
      return;
    out.distance = distance;
    out.normal = normal;
    found = true;
  });
  return out;
}

// A lower bound of the distance between a field and another shape from their bounding balls
// (centre c and radius r about each shape's origin), for the price of a sample or two; the
// largest of:
//   - |c_A - c_B| - r_A - r_B: the balls' gap;
//   - phi(c_O) - r_O for a 1-Lipschitz field of phi and another shape O: phi lies below the
//     distance to the field's solid outside it and changes by at most r_O over O's ball;
//   - d_O(c_F) - r_F for a field F and a shape O that is not a field, d_O the distance to O
//     (exact for the convex shapes and compounds of them, the distance to the surface for a mesh).
// `normal` runs from B to A along the gradient of the measure that gave the bound (the centres'
// line for the last, whose distance comes without one). Returned only when it exceeds both a
// quarter of the smaller radius (nearer, the bound is too loose to step by) and `floor`;
// otherwise the distance is -infinity (no bound).
DistanceBound field_ball_bound(const Shape& a, const Transform& pose_a, const Shape& b,
                               const Transform& pose_b, Real floor) {
  DistanceBound best;
  best.distance = -std::numeric_limits<Real>::infinity();
  best.separating_normal = false;
  const Real radius_a = bounding_radius(a);
  const Real radius_b = bounding_radius(b);
  if (!std::isfinite(radius_a) && !std::isfinite(radius_b))
    return best;
  const Vec3 centres = pose_a.translation - pose_b.translation;  // from B to A
  const Vec3 along_centres = centres.norm() > 0 ? Vec3(centres.normalized()) : Vec3::UnitZ();
  const auto consider = [&](Real bound, const Vec3& normal) {
    if (bound > best.distance) {
      best.distance = bound;
      best.normal = normal;
    }
  };
  // A hair less than each bound, for the rounding of the measures.
  const auto hair = [](Real r, Real d) { return Real(1e-9) * (r + std::abs(d)); };
  if (std::isfinite(radius_a) && std::isfinite(radius_b)) {
    const Real gap = centres.norm();
    consider(gap - radius_a - radius_b - hair(radius_a + radius_b, gap), along_centres);
  }
  const auto from_field = [&](const Shape& field, const Transform& pose_field, Real field_radius,
                              const Shape& other, const Transform& pose_other, Real other_radius,
                              Real sign) {
    if (field.type != ShapeType::sdf)
      return;
    if (field.sdf->is_one_lipschitz() && std::isfinite(other_radius)) {
      const sdf::Sample at =
          field.sdf->sample(pose_field.apply_inverse(pose_other.translation), field.field_time);
      const Vec3 outward = pose_field.rotate(at.gradient);
      consider(at.distance - other_radius - hair(other_radius, at.distance),
               outward.norm() > 0 ? Vec3(sign * outward.normalized()) : along_centres);
    }
    if (other.type != ShapeType::sdf && std::isfinite(field_radius)) {
      const Real d = signed_distance(other, pose_other, pose_field.translation);
      consider(d - field_radius - hair(field_radius, d), along_centres);
    }
  };
  from_field(b, pose_b, radius_b, a, pose_a, radius_a, Real(1));
  from_field(a, pose_a, radius_a, b, pose_b, radius_b, Real(-1));
  const Real smaller = std::min(radius_a, radius_b);
  if (!(best.distance > Real(0.25) * smaller) || !(best.distance > floor))
    best.distance = -std::numeric_limits<Real>::infinity();
  return best;
}

bool is_convex(const Shape& s) {
  return s.type != ShapeType::mesh && s.type != ShapeType::plane && s.type != ShapeType::compound;
}

}  // namespace

DistanceBound box_box_separation(const Vec3& half_a, const Transform& pose_a, const Vec3& half_b,
                                 const Transform& pose_b) {
  const Mat3 ra = pose_a.rotation.toRotationMatrix();
  const Mat3 rb = pose_b.rotation.toRotationMatrix();
  const Vec3 d = pose_a.translation - pose_b.translation;  // from B to A
  DistanceBound best;
  best.distance = -std::numeric_limits<Real>::infinity();
  auto try_axis = [&](Vec3 axis) {
    const Real length = axis.norm();
    if (length < Real(1e-9))
      return;  // parallel edges: the face axes cover this direction
    axis /= length;
    const Real extent_a = half_a.x() * std::abs(axis.dot(ra.col(0))) +
                          half_a.y() * std::abs(axis.dot(ra.col(1))) +
                          half_a.z() * std::abs(axis.dot(ra.col(2)));
    const Real extent_b = half_b.x() * std::abs(axis.dot(rb.col(0))) +
                          half_b.y() * std::abs(axis.dot(rb.col(1))) +
                          half_b.z() * std::abs(axis.dot(rb.col(2)));
    const Real centre = axis.dot(d);
    const Real gap = std::abs(centre) - extent_a - extent_b;
    if (gap > best.distance) {
      best.distance = gap;
      best.normal = centre >= 0 ? axis : Vec3(-axis);
    }
  };
  for (int i = 0; i < 3; ++i) {
    try_axis(ra.col(i));
    try_axis(rb.col(i));
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      try_axis(ra.col(i).cross(rb.col(j)));
  }
  return best;
}

DistanceBound shape_distance_bound(const Shape& a, const Transform& pose_a, const Shape& b,
                                   const Transform& pose_b, Real max_distance, Real stop_distance,
                                   const ClosingMotion* motion) {
  if (a.type == ShapeType::box && b.type == ShapeType::box)
    return box_box_separation(a.half_extents, pose_a, b.half_extents, pose_b);
  // Asked the other way round (B against A), B moves against A with the opposite velocity.
  ClosingMotion reversed;
  if (motion != nullptr) {
    reversed = *motion;
    reversed.relative_velocity = -motion->relative_velocity;
  }
  const ClosingMotion* motion_of_b = motion != nullptr ? &reversed : nullptr;
  if (b.type == ShapeType::mesh && is_convex(a))
    return convex_mesh_distance(a, pose_a, b, pose_b, max_distance, motion);
  if (a.type == ShapeType::mesh && is_convex(b)) {
    DistanceBound d = convex_mesh_distance(b, pose_b, a, pose_a, max_distance, motion_of_b);
    d.normal = -d.normal;
    return d;
  }
  // A compound against a mesh: its nearest part, and the least advance of any part (a part's
  // points move no faster along a triangle's normal than the compound's centre does plus the
  // compound's turning part, which `motion` bounds with the compound's own radius).
  if (a.type == ShapeType::compound && b.type == ShapeType::mesh) {
    DistanceBound best;
    best.distance = max_distance;
    best.separating_normal = false;
    if (motion != nullptr)
      best.least_advance = std::numeric_limits<Real>::infinity();
    for (const CompoundPart& part : a.compound->parts()) {
      const DistanceBound d = shape_distance_bound(part.shape, compose(pose_a, part.pose), b,
                                                   pose_b, max_distance, stop_distance, motion);
      if (d.distance < best.distance) {
        best.distance = d.distance;
        best.normal = d.normal;
      }
      if (motion != nullptr)
        best.least_advance = std::min(best.least_advance, d.least_advance);
    }
    return best;
  }
  if (a.type == ShapeType::mesh && b.type == ShapeType::compound) {
    DistanceBound d =
        shape_distance_bound(b, pose_b, a, pose_a, max_distance, stop_distance, motion_of_b);
    d.normal = -d.normal;
    return d;
  }
  // Far from a field, the balls that hold the shapes give a lower bound of their distance for
  // the price of a sample or two (field_ball_bound). Conservative advancement of a fast pair
  // spends most of its advances far apart, each of which asked the narrow phase about every
  // surface point within reach; it asks only once the bound falls to a quarter of the smaller
  // radius, where it is too loose to step by, or to where the advancement stops.
  if (a.type == ShapeType::sdf || b.type == ShapeType::sdf) {
    const DistanceBound ball_bound = field_ball_bound(a, pose_a, b, pose_b, stop_distance);
    if (ball_bound.distance > -std::numeric_limits<Real>::infinity())
      return ball_bound;
  }
  // Every other current pair of the narrow phase reports the exact signed distance of its
  // closest features as the deepest point's depth (sphere, capsule and plane pairs by closed
  // form, capsule-box by exact piecewise minimisation, box-plane by the lowest vertex).
  // Against a field whose phi is 1-Lipschitz, every point of the other shape lies within its
  // bounding radius r of its centre c, so phi <= phi(c) + r at each of them: the narrow phase
  // finds its deepest candidate within that margin, and skips the field's points farther from
  // the other shape. (With the motion's whole reach as the margin, every point of both fields
  // of a fast pair was measured at every advance.)
  Real margin = max_distance;
  const auto field_margin = [&](const Shape& field, const Transform& pose_field, const Shape& other,
                                const Transform& pose_other) {
    // The other may not be a field that is not 1-Lipschitz: its candidates' culling counts on
    // the margin to cover its interpolation's error.
    if (field.type != ShapeType::sdf || !field.sdf->is_one_lipschitz() ||
        (other.type == ShapeType::sdf && !other.sdf->is_one_lipschitz()))
      return;
    const Real r = bounding_radius(other);
    const Real phi =
        field.sdf->distance(pose_field.apply_inverse(pose_other.translation), field.field_time);
    // A hair more than the bound, for the rounding of the points' own phi.
    const Real bound = phi + r + Real(1e-9) * (r + std::abs(phi));
    if (bound < margin)
      margin = std::max(bound, Real(0));
  };
  field_margin(b, pose_b, a, pose_a);
  field_margin(a, pose_a, b, pose_b);
  DistanceBound out;
  // Against a field, the advancement steps by the deepest candidate's own separation
  // (field_least_separation: the narrow phase's candidates, a few of them refined instead of one
  // per region, no manifold) and stops with that candidate's normal, where the two shapes first
  // touch, not the manifold's mean of the normals within 60 degrees (which turns a hull's corner
  // poking into a curved field by up to 0.4 rad: docs/sdf.md). Touching fields, whose advancement
  // creeps by a fiftieth of the thinner body per advance, spent most of a short fuzzed scene's
  // time in the whole narrow phase.
  const auto plain = [](const Shape& s) {
    return s.type != ShapeType::mesh && s.type != ShapeType::compound;
  };
  if ((a.type == ShapeType::sdf || b.type == ShapeType::sdf) && plain(a) && plain(b)) {
    const FieldSeparation least = field_least_separation(a, pose_a, b, pose_b, margin);
    out.distance = least.distance;
    out.normal = least.normal;
    out.separating_normal = false;
    return out;
  }
  Manifold m;
  if (collide(a, pose_a, b, pose_b, margin, m) == 0) {
    out.distance = margin;
    out.separating_normal = false;
    return out;
  }
  Real deepest = m.points[0].depth;
  for (int i = 1; i < m.count; ++i)
    deepest = std::max(deepest, m.points[i].depth);
  out.distance = -deepest;
  out.normal = m.normal;
  // A compound's manifold normal is its nearest part's, not a separating axis of the whole; a
  // field's is the mean of its candidates' normals (sdf_pairs.cpp), and a field need not be
  // convex: conservative advancement may not take the approach speed along either, or it steps
  // past the contact (a 1 cm field ball at 1000 m/s went through a 1 cm wall in 126 of 300 tries).
  out.separating_normal = a.type != ShapeType::compound && b.type != ShapeType::compound &&
                          a.type != ShapeType::sdf && b.type != ShapeType::sdf;
  return out;
}

}  // namespace tumble
