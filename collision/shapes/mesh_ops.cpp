// The triangle mesh's row of the shape table (collision/shapes/shape_ops.hpp): a static surface,
// one-sided (its triangles face the side bodies rest on).
#include <algorithm>
#include <limits>

#include "collision/closest_point_on_triangle.hpp"
#include "collision/shapes/shape_rows.hpp"
#include "collision/shapes/surface_mesh.hpp"
#include "collision/shapes/triangle_mesh.hpp"

namespace tumble {
namespace {

Vec3 support(const Shape& s, const Vec3& d) {
  return s.mesh->support(d);
}

Aabb world_aabb(const Shape& s, const Transform& pose) {
  return s.mesh->world_aabb(pose);
}

Real volume(const Shape& s) {
  return s.mesh->volume();  // 0 for an open mesh
}

Mat3 unit_inertia(const Shape& s) {
  return s.mesh->unit_inertia();  // about the mesh's centroid; zero when open
}

Real bounding_radius(const Shape& s) {
  return s.mesh->bounding_radius();
}

// Front faces only (Moller and Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection",
// JGT 1997), on the triangles whose boxes the segment's box meets.
ShapeRayHit ray(const Shape& s, const Vec3& o, const Vec3& d) {
  const TriangleMesh& mesh = *s.mesh;
  Aabb box;
  box.grow(o);
  box.grow(o + d);
  Real best = std::numeric_limits<Real>::infinity();
  Vec3 normal = Vec3::UnitZ();
  mesh.for_each_overlapping(box, [&](int tri) {
    const Vec3& n = mesh.normal(tri);
    if (n.dot(d) >= 0)
      return;
    const Vec3 a = mesh.corner(tri, 0);
    const Vec3 e1 = mesh.corner(tri, 1) - a;
    const Vec3 e2 = mesh.corner(tri, 2) - a;
    const Vec3 p = d.cross(e2);
    const Real det = e1.dot(p);
    if (det == 0)
      return;
    const Vec3 sa = o - a;
    const Real u = sa.dot(p) / det;
    if (u < 0 || u > 1)
      return;
    const Vec3 q = sa.cross(e1);
    const Real v = d.dot(q) / det;
    if (v < 0 || u + v > 1)
      return;
    const Real t = e2.dot(q) / det;
    if (t >= 0 && t < best) {
      best = t;
      normal = n;
    }
  });
  if (best <= 1)
    return {true, best, normal};
  return {};
}

// A surface: the distance to the nearest triangle, never negative (a scan: a query for tests
// and tools, not the step).
Real signed_distance(const Shape& s, const Vec3& p) {
  const TriangleMesh& mesh = *s.mesh;
  Real best = std::numeric_limits<Real>::infinity();
  for (int tri = 0; tri < mesh.triangle_count(); ++tri) {
    const Vec3 q =
        closest_point_on_triangle(p, mesh.corner(tri, 0), mesh.corner(tri, 1), mesh.corner(tri, 2));
    best = std::min(best, (p - q).norm());
  }
  return best;
}

// A surface without a solid, static only: never swept, never asked.
Real inner_radius(const Shape&) {
  return 0;
}

SurfaceMesh surface_mesh(const Shape& s, const TessellationDetail&) {
  return tessellate_triangle_mesh(*s.mesh);
}

}  // namespace

const ShapeOps kMeshOps{"mesh",          support, world_aabb,      volume,       unit_inertia,
                        bounding_radius, ray,     signed_distance, inner_radius, surface_mesh};

}  // namespace tumble
