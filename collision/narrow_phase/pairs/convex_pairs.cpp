// Generic convex pairs (cylinder and hull against anything convex) and the analytic plane pairs
// of the new shapes.
//
// convex_convex: GJK on the cores (collision/narrow_phase/gjk_epa/gjk.hpp) gives distance, normal
// and witnesses when the shapes are apart; EPA (collision/narrow_phase/gjk_epa/epa.hpp) gives
// depth, normal and witnesses when the cores overlap. The manifold is then built from features
// (Catto, "Contact Manifolds", GDC 2007; Gregorius, "Robust Contact Creation for Physics
// Simulations", GDC 2015): each shape offers the feature it presents along the normal (a face
// polygon, a cylinder's cap as a 16-gon of exact rim points or its side line, a capsule's core
// segment, a point). When one of them is a face well aligned with the normal it becomes the
// reference: the other feature is clipped against its side planes (Sutherland-Hodgman) and every
// clipped point within the margin is kept, its depth measured along the face normal. Otherwise the
// single GJK/EPA point is the manifold. More than four points are reduced by manifold_reduction
// (deepest first, then area).
//
// cylinder_plane: the rim points of both caps in four directions, the first one being the
// deepest rim point (exact), kept when within the margin, reduced to four.
// hull_plane: every hull vertex within the margin, reduced to four.
#include <algorithm>
#include <array>
#include <cmath>

#include "collision/narrow_phase/gjk_epa/epa.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/gjk_epa/gjk_internal.hpp"
#include "collision/narrow_phase/pairs/manifold_reduction.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"
#include "collision/shapes/convex_hull.hpp"

namespace tumble::detail {

namespace {

// A face becomes the reference only when its normal is within about 18 degrees of the contact
// normal; a more tilted face touches with an edge or a vertex, and one point is the honest
// answer.
constexpr Real kFaceAlignment = Real(0.95);
// A cylinder's side or a capsule's core segment lies flat against a face when its axis is
// within this sine of perpendicular to the normal.
constexpr Real kSegmentAlignment = Real(0.05);
constexpr int kCylinderRimPoints = 16;
constexpr int kMaxFeaturePoints = 64;
constexpr int kMaxClipPoints = 2 * kMaxFeaturePoints + 8;

// Feature ids of the cylinder: its caps, its side and its rim sample points.
constexpr std::uint16_t kCylinderCap0 = 0;
constexpr std::uint16_t kCylinderSide = 2;
constexpr std::uint16_t cylinder_rim(int cap, int k) {
  return std::uint16_t(3 + kCylinderRimPoints * cap + k);
}
// Hull feature ids: vertices by index, faces and edge crossings flagged in the high bits.
constexpr std::uint16_t kFaceFlag = 0x8000;
constexpr std::uint16_t kEdgeFlag = 0x4000;

struct FeaturePolygon {
  std::array<Vec3, kMaxFeaturePoints> point{};
  std::array<std::uint16_t, kMaxFeaturePoints> id{};
  int count = 0;
  bool is_face = false;        // a planar face with `normal`
  Vec3 normal = Vec3::Zero();  // outward face normal (pair frame)
  Real alignment = -1;         // normal . (direction towards the other shape)
  std::uint16_t face_id = 0;
  Real radius = 0;  // rounding of the points (capsule core)
};

// The feature of `shape` that faces `direction` (unit, pair frame).
void feature_towards(const Shape& shape, const Transform& pose, const Vec3& direction,
                     FeaturePolygon& f) {
  const Vec3 u = pose.rotate_inverse(direction);
  f.count = 0;
  f.is_face = false;
  switch (shape.type) {
    case ShapeType::box: {
      int axis = 0;
      u.cwiseAbs().maxCoeff(&axis);
      const bool positive = u[axis] >= 0;
      f.is_face = true;
      f.normal = pose.rotate(Vec3::Unit(axis) * (positive ? 1 : -1));
      f.alignment = std::abs(u[axis]);
      f.face_id = feature::box_face(axis, positive);
      const int a1 = (axis + 1) % 3;
      const int a2 = (axis + 2) % 3;
      // Counter-clockwise about the outward normal.
      constexpr int kSigns[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (int k = 0; k < 4; ++k) {
        Vec3 local;
        local[axis] = positive ? shape.half_extents[axis] : -shape.half_extents[axis];
        const int s1 = positive ? kSigns[k][0] : kSigns[k][1];
        const int s2 = positive ? kSigns[k][1] : kSigns[k][0];
        local[a1] = s1 * shape.half_extents[a1];
        local[a2] = s2 * shape.half_extents[a2];
        int bits = 0;
        for (int c = 0; c < 3; ++c)
          bits |= local[c] > 0 ? (1 << c) : 0;
        f.point[std::size_t(k)] = pose.apply(local);
        f.id[std::size_t(k)] = feature::box_vertex(bits);
      }
      f.count = 4;
      return;
    }
    case ShapeType::hull: {
      const ConvexHull& hull = *shape.hull;
      const int face_index = hull.best_face(u);
      const HullFace& face = hull.faces()[std::size_t(face_index)];
      if (face.count <= kMaxFeaturePoints) {
        f.is_face = true;
        f.normal = pose.rotate(face.normal);
        f.alignment = face.normal.dot(u);
        f.face_id = std::uint16_t(kFaceFlag | (face_index & 0x3fff));
        for (int k = 0; k < face.count; ++k) {
          const int v = hull.face_vertices()[std::size_t(face.first_index + k)];
          f.point[std::size_t(k)] = pose.apply(hull.vertex(v));
          f.id[std::size_t(k)] = std::uint16_t(v & 0x3fff);
        }
        f.count = face.count;
        return;
      }
      int index = 0;
      f.point[0] = pose.apply(hull.vertex(hull.support_index(u, index)));
      f.count = 1;
      return;
    }
    case ShapeType::cylinder: {
      const Real r = shape.radius;
      const Real h = shape.half_length;
      if (std::abs(u.z()) >= kFaceAlignment) {
        const bool top = u.z() > 0;
        f.is_face = true;
        f.normal = pose.rotate(Vec3(0, 0, top ? 1 : -1));
        f.alignment = std::abs(u.z());
        f.face_id = top ? std::uint16_t(kCylinderCap0 + 1) : kCylinderCap0;
        for (int k = 0; k < kCylinderRimPoints; ++k) {
          // Counter-clockwise about the outward normal (reversed on the bottom cap).
          const Real angle = Real(2) * std::numbers::pi_v<Real> * Real(k) / kCylinderRimPoints;
          const Real y = top ? std::sin(angle) : -std::sin(angle);
          f.point[std::size_t(k)] = pose.apply(Vec3(r * std::cos(angle), r * y, top ? h : -h));
          f.id[std::size_t(k)] = cylinder_rim(top ? 1 : 0, k);
        }
        f.count = kCylinderRimPoints;
        return;
      }
      const Real radial = std::hypot(u.x(), u.y());
      const Vec3 rim = radial > 0 ? Vec3(u.x() / radial * r, u.y() / radial * r, 0) : Vec3::Zero();
      if (std::abs(u.z()) <= kSegmentAlignment) {
        f.point[0] = pose.apply(rim + Vec3(0, 0, -h));
        f.point[1] = pose.apply(rim + Vec3(0, 0, h));
        f.id[0] = cylinder_rim(0, 0);
        f.id[1] = cylinder_rim(1, 0);
        f.count = 2;
        return;
      }
      f.point[0] = pose.apply(rim + Vec3(0, 0, u.z() < 0 ? -h : h));
      f.id[0] = kCylinderSide;
      f.count = 1;
      return;
    }
    case ShapeType::capsule: {
      f.radius = shape.radius;
      if (shape.half_length > 0 && std::abs(u.z()) <= kSegmentAlignment) {
        f.point[0] = pose.apply(Vec3(0, 0, -shape.half_length));
        f.point[1] = pose.apply(Vec3(0, 0, shape.half_length));
        f.id[0] = feature::kCapsuleEnd0;
        f.id[1] = feature::kCapsuleEnd1;
        f.count = 2;
        return;
      }
      f.count = 0;  // a point: the GJK/EPA point is exact
      return;
    }
    default:
      f.count = 0;
      return;
  }
}

// Clips `incident` against the side planes of `reference` (a face) and appends the kept points
// as contacts. `reference_is_a` says which shape the reference face belongs to.
// Depths are measured along the manifold normal `normal` (B to A, from GJK/EPA) down to the
// reference face's plane; points deeper than `max_depth` (the exact depth) by more than
// `depth_slack` come from a face tilted from the normal and are dropped, so no point reports
// more than the true penetration and every point lies in both shapes.
int clip_features(const FeaturePolygon& reference, const FeaturePolygon& incident,
                  bool reference_is_a, const Vec3& normal, Real max_depth, Real depth_slack,
                  Real margin, std::array<ContactPoint, kMaxClipPoints>& out) {
  struct ClipPoint {
    Vec3 p;
    std::uint16_t incident_id;
    std::uint16_t reference_id;
  };
  std::array<ClipPoint, kMaxClipPoints> buffer_a{};
  std::array<ClipPoint, kMaxClipPoints> buffer_b{};
  int count = incident.count;
  for (int k = 0; k < count; ++k)
    buffer_a[std::size_t(k)] = {incident.point[std::size_t(k)], incident.id[std::size_t(k)],
                                reference.face_id};
  auto* input = &buffer_a;
  auto* output = &buffer_b;
  Vec3 centre = Vec3::Zero();
  for (int k = 0; k < reference.count; ++k)
    centre += reference.point[std::size_t(k)];
  centre /= Real(reference.count);
  for (int e = 0; e < reference.count && count > 0; ++e) {
    const Vec3& r0 = reference.point[std::size_t(e)];
    const Vec3& r1 = reference.point[std::size_t((e + 1) % reference.count)];
    // The side plane holds the edge and the manifold normal, so a kept point moved along the
    // normal onto the face plane lands inside the face.
    Vec3 side = (r1 - r0).cross(normal);
    if (side.dot(centre - r0) > 0)
      side = -side;  // outward from the face's interior
    const std::uint16_t side_id =
        std::uint16_t(kEdgeFlag | (reference.id[std::size_t(e)] & 0x3fff));
    int n = 0;
    const int edges = count == 2 ? 1 : count;  // a segment is clipped once, not as a loop
    if (count == 1) {
      if (side.dot((*input)[0].p - r0) <= 0)
        (*output)[std::size_t(n++)] = (*input)[0];
      std::swap(input, output);
      count = n;
      continue;
    }
    for (int k = 0; k < edges; ++k) {
      const ClipPoint& p = (*input)[std::size_t(k)];
      const ClipPoint& q = (*input)[std::size_t((k + 1) % count)];
      const Real dp = side.dot(p.p - r0);
      const Real dq = side.dot(q.p - r0);
      if (dp <= 0 && n < kMaxClipPoints)
        (*output)[std::size_t(n++)] = p;
      if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) {
        const Real t = dp / (dp - dq);
        if (n < kMaxClipPoints)
          (*output)[std::size_t(n++)] = {
              p.p + t * (q.p - p.p), std::uint16_t(kEdgeFlag | (p.incident_id & 0x3fff)), side_id};
      }
      if (count == 2 && dq <= 0 && n < kMaxClipPoints)
        (*output)[std::size_t(n++)] = q;
    }
    std::swap(input, output);
    count = n;
  }
  const Vec3& plane_point = reference.point[0];
  // The incident shape's surface faces the reference along -normal when the incident is A,
  // along +normal when it is B.
  const Vec3 towards_reference = reference_is_a ? normal : Vec3(-normal);
  const Real cosine = std::abs(reference.normal.dot(normal));
  int kept = 0;
  for (int k = 0; k < count; ++k) {
    const ClipPoint& c = (*input)[std::size_t(k)];
    const Vec3 surface = c.p + towards_reference * incident.radius;
    // Height above the reference plane along its normal, converted to a length along `normal`.
    const Real separation = reference.normal.dot(surface - plane_point) / cosine;
    // Deeper than the exact depth (beyond rounding): the face is tilted from the normal and the
    // point is not a true contact; drop it.
    if (-separation > max_depth + depth_slack)
      continue;
    const Real depth = std::min(-separation, max_depth);
    if (!(depth >= -margin))
      continue;
    // point_on_a - point_on_b = -depth * normal; the incident point is exact.
    const Vec3 position = surface - towards_reference * (depth * Real(0.5));
    const FeatureId feature = reference_is_a ? FeatureId{c.reference_id, c.incident_id}
                                             : FeatureId{c.incident_id, c.reference_id};
    out[std::size_t(kept++)] = {position, depth, feature};
  }
  return kept;
}

}  // namespace

int convex_convex(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                  Real margin, Manifold& out) {
  return convex_convex_cached(a, pose_a, b, pose_b, margin, out, nullptr);
}

int convex_convex_cached(const Shape& a, const Transform& pose_a, const Shape& b,
                         const Transform& pose_b, Real margin, Manifold& out, GjkCache* cache) {
  const ConvexSupport sa = ConvexSupport::of(a, pose_a);
  const ConvexSupport sb = ConvexSupport::of(b, pose_b);
  const GjkResult g = gjk(sa, sb, cache);
  Vec3 normal;
  Real depth;
  Vec3 point_a;
  Vec3 point_b;
  if (g.status == GjkStatus::intersecting) {
    const EpaResult e = epa(sa, sb, g);
    normal = e.normal;
    depth = e.depth;
    point_a = e.point_a;
    point_b = e.point_b;
  } else {
    if (!(g.distance <= margin))
      return 0;
    normal = g.normal;
    depth = -g.distance;
    point_a = g.point_a;
    point_b = g.point_b;
  }

  // Features: A's towards B is along -normal, B's towards A along +normal.
  FeaturePolygon fa;
  FeaturePolygon fb;
  feature_towards(a, pose_a, -normal, fa);
  feature_towards(b, pose_b, normal, fb);
  const bool a_face = fa.is_face && fa.alignment >= kFaceAlignment;
  const bool b_face = fb.is_face && fb.alignment >= kFaceAlignment;
  if ((a_face && fb.count >= 1) || (b_face && fa.count >= 1)) {
    // The better aligned face is the reference; ties go to A.
    const bool reference_is_a = a_face && (!b_face || fa.alignment >= fb.alignment);
    const FeaturePolygon& reference = reference_is_a ? fa : fb;
    const FeaturePolygon& incident = reference_is_a ? fb : fa;
    if (incident.count >= 2) {
      std::array<ContactPoint, kMaxClipPoints> candidates;
      // The exact GJK/EPA point goes first, so it is the deepest point (ties go to the lower
      // index in the reduction), and the clipped points join it.
      int index_a = 0;
      int index_b = 0;
      sa.core_support(-normal, index_a);
      sb.core_support(normal, index_b);
      candidates[0] = {point_a + normal * (depth * Real(0.5)),
                       depth,
                       {std::uint16_t(index_a & 0x3fff), std::uint16_t(index_b & 0x3fff)}};
      std::array<ContactPoint, kMaxClipPoints> clipped;
      const Real slack = Real(1e-9) * (bounding_radius(a) + bounding_radius(b));
      const int clipped_count =
          clip_features(reference, incident, reference_is_a, normal, depth, slack, margin, clipped);
      int count = 1;
      for (int k = 0; k < clipped_count && count < kMaxClipPoints; ++k)
        candidates[std::size_t(count++)] = clipped[std::size_t(k)];
      if (count > 1 && depth >= -margin) {
        return write_reduced_manifold(normal, std::span(candidates.data(), std::size_t(count)),
                                      out);
      }
    }
  }
  // One point: the exact closest (or deepest) pair.
  int index_a = 0;
  int index_b = 0;
  sa.core_support(-normal, index_a);
  sb.core_support(normal, index_b);
  out.normal = normal;
  add_contact(out, point_a, normal, depth, margin,
              {std::uint16_t(index_a & 0x3fff), std::uint16_t(index_b & 0x3fff)});
  return out.count;
}

int sphere_cylinder(const Shape& a, const Transform& pose_a, const Shape& b,
                    const Transform& pose_b, Real margin, Manifold& out) {
  // In the cylinder's frame: the closest point of the solid cylinder to the centre by clamping
  // (outside), or the nearest of the side and the two caps (inside).
  const Vec3 c = pose_b.apply_inverse(pose_a.translation);
  const Real r = b.radius;
  const Real h = b.half_length;
  const Real radial = std::hypot(c.x(), c.y());
  const Vec3 radial_direction =
      radial > 0 ? Vec3(c.x() / radial, c.y() / radial, 0) : Vec3::UnitX();
  Vec3 local_normal;
  Real depth;
  std::uint16_t feature_b;
  if (radial > r || std::abs(c.z()) > h) {
    const Vec3 closest(radial > r ? radial_direction.x() * r : c.x(),
                       radial > r ? radial_direction.y() * r : c.y(), std::clamp(c.z(), -h, h));
    const Vec3 gap = c - closest;
    const Real distance = gap.norm();
    local_normal =
        normalized_or(gap, radial > r ? radial_direction : Vec3(0, 0, c.z() < 0 ? -1 : 1));
    depth = a.radius - distance;
    feature_b = std::abs(c.z()) > h
                    ? (radial > r ? kCylinderSide : std::uint16_t(c.z() > 0 ? 1 : 0))
                    : kCylinderSide;
  } else {
    const Real to_side = r - radial;
    const Real to_cap = h - std::abs(c.z());
    if (to_side < to_cap) {
      local_normal = radial_direction;
      depth = a.radius + to_side;
      feature_b = kCylinderSide;
    } else {
      local_normal = Vec3(0, 0, c.z() < 0 ? -1 : 1);
      depth = a.radius + to_cap;
      feature_b = std::uint16_t(c.z() < 0 ? 0 : 1);
    }
  }
  const Vec3 normal = pose_b.rotate(local_normal);
  out.normal = normal;
  add_contact(out, pose_a.translation - normal * a.radius, normal, depth, margin,
              {feature::kSphere, feature_b});
  return out.count;
}

int capsule_cylinder(const Shape& a, const Transform& pose_a, const Shape& b,
                     const Transform& pose_b, Real margin, Manifold& out) {
  // A capsule of zero length is a sphere, and gets the exact sphere pair.
  if (a.half_length == 0)
    return sphere_cylinder(Shape::sphere(a.radius), pose_a, b, pose_b, margin, out);
  return convex_convex(a, pose_a, b, pose_b, margin, out);
}

int cylinder_plane(const Shape& a, const Transform& pose_a, const Shape& /*plane*/,
                   const Transform& pose_b, Real margin, Manifold& out) {
  const Vec3 normal = pose_b.rotate(Vec3::UnitZ());
  const Vec3 local_normal = pose_a.rotate_inverse(normal);
  const Real centre_height = normal.dot(pose_a.translation - pose_b.translation);
  // The deepest rim direction: the component of -n perpendicular to the axis.
  Vec3 radial(-local_normal.x(), -local_normal.y(), 0);
  const Real radial_length = radial.norm();
  Vec3 t1;
  Vec3 t2;
  if (radial_length > Real(1e-12)) {
    t1 = radial / radial_length;
    t2 = Vec3::UnitZ().cross(t1);
  } else {
    t1 = Vec3::UnitX();
    t2 = Vec3::UnitY();
  }
  std::array<ContactPoint, 8> candidates;
  int count = 0;
  for (int cap = 0; cap < 2; ++cap) {
    const Real z = cap == 0 ? -a.half_length : a.half_length;
    for (int k = 0; k < 4; ++k) {
      const Vec3 direction = k == 0 ? t1 : k == 1 ? t2 : k == 2 ? Vec3(-t1) : Vec3(-t2);
      const Vec3 local = direction * a.radius + Vec3(0, 0, z);
      const Real depth = -(centre_height + local_normal.dot(local));
      if (!(depth >= -margin))
        continue;
      const Vec3 on_cylinder = pose_a.apply(local);
      candidates[std::size_t(count++)] = {on_cylinder + normal * (depth * Real(0.5)),
                                          depth,
                                          {cylinder_rim(cap, k * 4), feature::kPlane}};
    }
  }
  return write_reduced_manifold(normal, std::span(candidates.data(), std::size_t(count)), out);
}

int hull_plane(const Shape& a, const Transform& pose_a, const Shape& /*plane*/,
               const Transform& pose_b, Real margin, Manifold& out) {
  const Vec3 normal = pose_b.rotate(Vec3::UnitZ());
  const Vec3 local_normal = pose_a.rotate_inverse(normal);
  const Real centre_height = normal.dot(pose_a.translation - pose_b.translation);
  const ConvexHull& hull = *a.hull;
  // Candidates: the vertices within the margin. Keep the deepest and a bounded set; the hull is
  // scanned without allocation by keeping the candidates in a fixed buffer and reducing it
  // whenever it fills.
  constexpr int kBuffer = 64;
  std::array<ContactPoint, kBuffer> candidates;
  int count = 0;
  const int n = int(hull.vertices().size());
  for (int v = 0; v < n; ++v) {
    const Real depth = -(centre_height + local_normal.dot(hull.vertex(v)));
    if (!(depth >= -margin))
      continue;
    if (count == kBuffer) {
      std::array<int, kMaxManifoldPoints> kept{};
      const int kept_count =
          reduce_manifold(normal, std::span(candidates.data(), std::size_t(count)), kept);
      std::array<ContactPoint, kMaxManifoldPoints> best{};
      for (int i = 0; i < kept_count; ++i)
        best[std::size_t(i)] = candidates[std::size_t(kept[std::size_t(i)])];
      for (int i = 0; i < kept_count; ++i)
        candidates[std::size_t(i)] = best[std::size_t(i)];
      count = kept_count;
    }
    const Vec3 on_hull = pose_a.apply(hull.vertex(v));
    candidates[std::size_t(count++)] = {on_hull + normal * (depth * Real(0.5)),
                                        depth,
                                        {std::uint16_t(v & 0x3fff), feature::kPlane}};
  }
  return write_reduced_manifold(normal, std::span(candidates.data(), std::size_t(count)), out);
}

}  // namespace tumble::detail
