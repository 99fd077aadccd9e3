// Cylinder and hull against one triangle of a mesh (convex_triangle.hpp: the shape at the origin,
// unrotated; the normal from the triangle to the shape). The closest features come from GJK on
// the shape and the triangle's three corners (collision/narrow_phase/gjk_epa/gjk.hpp), or from EPA
// when they overlap (collision/narrow_phase/gjk_epa/epa.hpp). Where on the triangle the witness
// lies decides, with the internal-edge rules of region_use, whether that normal is trusted or
// replaced by the face normal; a normal pointing behind the one-sided triangle gives no contact
// when apart and is replaced when the shapes overlap. With the face normal the points are the
// shape's vertices (hull) or cap-rim samples (cylinder) within the margin of the triangle's plane
// that project inside the triangle, the shape's deepest point (support map) first, so a hull
// resting on a mesh gets a supporting polygon, not one point, and the depth is exact.
#include <cmath>
#include <numbers>

#include "collision/narrow_phase/gjk_epa/epa.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/pairs/convex_triangle.hpp"
#include "collision/shapes/convex_hull.hpp"

namespace tumble::detail {
namespace {

constexpr int kRimSamples = 8;  // per cap of a cylinder

bool projects_inside(const Vec3& p, const TriangleView& tri) {
  for (int k = 0; k < 3; ++k) {
    const Vec3& a = tri.corner[k];
    const Vec3& b = tri.corner[(k + 1) % 3];
    if ((b - a).cross(p - a).dot(tri.normal) < 0)
      return false;
  }
  return true;
}

// Depth of a point of the shape below the triangle's plane (positive = penetration).
Real depth_below(const Vec3& p, const TriangleView& tri) {
  return tri.normal.dot(tri.corner[0] - p);
}

void add_face_points(const Shape& shape, const TriangleView& tri, Real margin,
                     TriangleContact& contact) {
  const auto consider = [&](const Vec3& p, std::uint16_t feature) {
    const Real d = depth_below(p, tri);
    if (d >= -margin && projects_inside(p, tri))
      contact.add(p, d, feature, TriangleRegion::face, margin);
  };
  // The shape's deepest point first: the points are capped at kMaxPoints, and a tilted
  // cylinder's deepest rim point is in general none of the samples, so without it the depth
  // would be short by up to r (1 - cos(pi / kRimSamples)).
  const Vec3 deepest = support(shape, -tri.normal);
  if (shape.type == ShapeType::hull) {
    const ConvexHull& hull = *shape.hull;
    const int count = static_cast<int>(hull.vertices().size());
    int deepest_index = 0;
    for (int i = 1; i < count; ++i) {
      if (depth_below(hull.vertex(i), tri) > depth_below(hull.vertex(deepest_index), tri))
        deepest_index = i;
    }
    consider(hull.vertex(deepest_index), std::uint16_t(deepest_index));
    for (int i = 0; i < count && contact.count < TriangleContact::kMaxPoints; ++i) {
      if (i != deepest_index)
        consider(hull.vertex(i), std::uint16_t(i));
    }
    return;
  }
  // Cylinder: the deepest rim point, then its two cap rims, sampled.
  consider(deepest, std::uint16_t(2 * kRimSamples));
  for (int cap = 0; cap < 2; ++cap) {
    const Real z = cap == 0 ? -shape.half_length : shape.half_length;
    for (int s = 0; s < kRimSamples; ++s) {
      const Real angle = 2 * std::numbers::pi_v<Real> * s / kRimSamples;
      const Vec3 p(shape.radius * std::cos(angle), shape.radius * std::sin(angle), z);
      if (p != deepest)
        consider(p, std::uint16_t(cap * kRimSamples + s));
    }
  }
}

}  // namespace

int generic_triangle(const Shape& shape, const TriangleView& tri, Real margin,
                     TriangleContact& contact) {
  // The shape's gap to the triangle's plane, from its support along the normal, bounds its
  // distance to the triangle from below: a shape wholly in front of the plane, or wholly behind
  // it, by more than the margin gives no contact, and GJK is not needed to say so (most of the
  // triangles a mesh pair's box takes in, on a terrain).
  const Real plane = tri.normal.dot(tri.corner[0]);
  if (tri.normal.dot(support(shape, -tri.normal)) - plane > margin ||
      plane - tri.normal.dot(support(shape, tri.normal)) > margin)
    return 0;
  const ConvexSupport a = ConvexSupport::of(shape, Transform{});
  const ConvexSupport b = ConvexSupport::of_points(tri.corner.data(), 3, Transform{});
  const GjkResult g = gjk(a, b);
  Vec3 normal = g.normal;
  Vec3 on_shape = g.point_a;
  Vec3 on_triangle = g.point_b;
  Real depth = -g.distance;
  if (g.status == GjkStatus::intersecting) {
    const EpaResult e = epa(a, b, g);
    normal = e.normal;
    on_shape = e.point_a;
    on_triangle = e.point_b;
    depth = e.depth;
  } else if (g.distance > margin) {
    return 0;
  }
  // Apart, and reached from behind the face or from behind a boundary or convex feature: the
  // shape is beside or behind the one-sided triangle, so no contact from it, as for the sphere (a
  // neighbour, if any, gives the contact). Taken with the face normal, a hull just behind the
  // face got its vertices under the face pushed through to the front (0.39 m for a hull 1.8 cm
  // from it). Overlapping, such a normal is replaced by the face's below.
  if (normal.dot(tri.normal) <= 0 && g.status != GjkStatus::intersecting)
    return 0;
  TriangleRegion region;
  closest_point_on_triangle(on_triangle, tri.corner, region);
  const RegionUse use = region_use(tri, region);
  if (use == RegionUse::drop)
    return 0;
  // An edge or corner normal is kept only when it leans to the triangle's front; the witness of
  // a face contact has the face normal anyway (up to rounding), and is given it exactly.
  if (use == RegionUse::keep && region != TriangleRegion::face) {
    if (normal.dot(tri.normal) > 0) {
      contact.normal = normal;
      contact.add(on_shape, depth, std::uint16_t(0), region, margin);
      return contact.count;
    }
  }
  contact.normal = tri.normal;
  // A face witness carries the exact distance or depth along the face normal: the vertices over
  // the triangle alone can miss it when the shape overhangs an edge.
  // Overlapping with an edge or corner witness, the vertices over the triangle can all be in
  // front of its plane while the shape crosses it: the shape's lowest point under the plane
  // gives a depth that pushes it wholly in front (never less than the true depth).
  if (region == TriangleRegion::face) {
    contact.add(on_shape, depth, std::uint16_t(0xfe), TriangleRegion::face, margin);
  } else if (g.status == GjkStatus::intersecting) {
    const Vec3 lowest = support(shape, -tri.normal);
    contact.add(lowest, depth_below(lowest, tri), std::uint16_t(0xfd), TriangleRegion::face,
                margin);
  }
  add_face_points(shape, tri, margin, contact);
  if (contact.count == 0) {
    // No vertex or rim sample over the triangle: the deepest point of the shape below the plane.
    const Vec3 deepest = support(shape, -tri.normal);
    contact.add(deepest, depth_below(deepest, tri), std::uint16_t(0xff), TriangleRegion::face,
                margin);
  }
  return contact.count;
}

}  // namespace tumble::detail
