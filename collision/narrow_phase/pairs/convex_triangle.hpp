// Internal to the narrow phase: contacts between one convex primitive and one triangle of a
// mesh, with the triangle already expressed in the convex shape's local frame (so the sphere's
// centre, the capsule's segment and the box are at the origin, axis aligned, and the arithmetic
// is as precise as it is for a shape at the origin).
//
// Triangles are one-sided: the front is the side the counter-clockwise normal points to, and a
// contact normal (from the triangle to the convex shape) never points behind it.
//
// Internal edges (Gregorius, "Robust Contact Creation for Physics Simulations", GDC 2015, and
// the Voronoi-region argument of Bullet's btInternalEdgeUtility, learnt from, not copied): a
// contact normal that comes from an edge or a corner of the triangle is only trusted when that
// feature can be touched from outside the surface: a boundary or convex edge, a corner on one.
// From a flat edge (coplanar neighbour) the contact is rebuilt with the face normal, which is
// what the neighbour reports too; from a concave edge (a valley) it is dropped, since the
// neighbouring face gives the real contact. A box sliding over a flat grid then sees only +z.
#pragma once

#include <array>
#include <cstdint>

#include "collision/contact.hpp"
#include "collision/shapes/shape.hpp"
#include "collision/shapes/triangle_mesh.hpp"

namespace tumble::detail {

// Where on the triangle a contact normal came from: 0 = face, 1 + k = edge k (corner k to
// corner k+1), 4 + k = corner k.
enum class TriangleRegion : std::uint8_t {
  face = 0,
  edge0,
  edge1,
  edge2,
  corner0,
  corner1,
  corner2
};

struct TriangleView {
  std::array<Vec3, 3> corner;  // in the convex shape's frame
  Vec3 normal;                 // unit, front side
  std::array<EdgeKind, 3> edge;
  std::array<bool, 3> corner_active;
};

// Contacts of one triangle: a normal from the triangle to the convex shape and up to eight
// points given by the point on the convex shape and the depth (positive = penetration). A box
// face clipped by a triangle has up to 7 corners; the caller reduces.
struct TriangleContact {
  static constexpr int kMaxPoints = 8;
  Vec3 normal = Vec3::UnitZ();
  int count = 0;
  std::array<Vec3, kMaxPoints> point_on_convex{};
  std::array<Real, kMaxPoints> depth{};
  std::array<std::uint16_t, kMaxPoints> convex_feature{};
  std::array<TriangleRegion, kMaxPoints> region{};

  void add(const Vec3& p, Real d, std::uint16_t feature, TriangleRegion r, Real margin) {
    if (count < kMaxPoints && d >= -margin) {
      point_on_convex[count] = p;
      depth[count] = d;
      convex_feature[count] = feature;
      region[count] = r;
      ++count;
    }
  }
};

// What to do with a contact whose normal came from `region` (see the header comment).
enum class RegionUse : std::uint8_t { keep, use_face, drop };
RegionUse region_use(const TriangleView& tri, TriangleRegion region);

// Closest point of triangle `tri` to `p` and the region it lies in (Ericson, Real-Time
// Collision Detection, 2005, 5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const std::array<Vec3, 3>& tri,
                               TriangleRegion& region);

// The shape sits at the origin of the frame, unrotated. Each returns contact.count.
int sphere_triangle(const Shape& sphere, const TriangleView& tri, Real margin,
                    TriangleContact& contact);
int capsule_triangle(const Shape& capsule, const TriangleView& tri, Real margin,
                     TriangleContact& contact);
int box_triangle(const Shape& box, const TriangleView& tri, Real margin, TriangleContact& contact);
// Cylinder and hull, through GJK/EPA (convex_triangle_generic.cpp).
int generic_triangle(const Shape& shape, const TriangleView& tri, Real margin,
                     TriangleContact& contact);

}  // namespace tumble::detail
