// The convex hull's row of the shape table (collision/shapes/shape_ops.hpp): vertices re-centred
// on the centre of mass, faces as counter-clockwise loops with outward planes.
#include <algorithm>
#include <limits>

#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/shape_rows.hpp"
#include "collision/shapes/surface_mesh.hpp"

namespace tumble {
namespace {

Vec3 support(const Shape& s, const Vec3& d) {
  return s.hull->vertex(s.hull->support_index(d));
}

Aabb world_aabb(const Shape& s, const Transform& pose) {
  const Mat3 r = pose.rotation.toRotationMatrix();
  const Vec3& c = pose.translation;
  Aabb box;
  for (int k = 0; k < 3; ++k) {
    const Vec3 axis_local = r.row(k).transpose();
    box.max[k] = c[k] + s.hull->vertex(s.hull->support_index(axis_local)).dot(axis_local);
    box.min[k] = c[k] + s.hull->vertex(s.hull->support_index(-axis_local)).dot(axis_local);
  }
  return box;
}

Real volume(const Shape& s) {
  return s.hull->volume();
}

Mat3 unit_inertia(const Shape& s) {
  return s.hull->unit_inertia();
}

Real bounding_radius(const Shape& s) {
  return s.hull->bounding_radius();
}

// Cyrus and Beck, "Generalized two- and three-dimensional clipping", Computers & Graphics 3,
// 1978: the segment clipped by every face's half-space.
ShapeRayHit ray(const Shape& s, const Vec3& o, const Vec3& d) {
  ShapeRayHit out;
  Real enter = 0;
  Real exit = 1;
  Vec3 normal = Vec3::UnitZ();
  bool entered = false;
  for (const HullFace& f : s.hull->faces()) {
    const Real dn = f.normal.dot(d);
    const Real gap = f.offset - f.normal.dot(o);  // >= 0 inside this face's half-space
    if (dn == 0) {
      if (gap < 0)
        return out;
      continue;
    }
    const Real t = gap / dn;
    if (dn < 0) {
      if (t > enter) {
        enter = t;
        normal = f.normal;
        entered = true;
      }
    } else {
      exit = std::min(exit, t);
    }
    if (enter > exit)
      return out;
  }
  if (entered)
    out = {true, enter, normal};
  return out;
}

Real segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const Real t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), Real(0), Real(1));
  return (p - (a + t * ab)).norm();
}

// Inside, the nearest face plane (exact: the deepest point's nearest face). Outside, the
// nearest point of the surface, found face by face: the point's projection on the face's
// plane when it falls inside the face's loop, else the nearest point of the loop's edges.
Real signed_distance(const Shape& s, const Vec3& p) {
  const ConvexHull& hull = *s.hull;
  Real inside = -std::numeric_limits<Real>::infinity();
  for (const HullFace& f : hull.faces())
    inside = std::max(inside, f.normal.dot(p) - f.offset);
  if (inside <= 0)
    return inside;
  Real best = std::numeric_limits<Real>::infinity();
  const auto loop = hull.face_vertices();
  for (const HullFace& f : hull.faces()) {
    const Real height = f.normal.dot(p) - f.offset;
    const Vec3 q = p - height * f.normal;
    bool within = true;
    Real edge = std::numeric_limits<Real>::infinity();
    for (int k = 0; k < f.count; ++k) {
      const Vec3& a = hull.vertex(loop[std::size_t(f.first_index + k)]);
      const Vec3& b = hull.vertex(loop[std::size_t(f.first_index + (k + 1) % f.count)]);
      if ((b - a).cross(q - a).dot(f.normal) < 0)
        within = false;
      edge = std::min(edge, segment_distance(p, a, b));
    }
    best = std::min(best, within ? std::abs(height) : edge);
  }
  return best;
}

// The centre of mass is inside: its distance to the nearest face plane.
Real inner_radius(const Shape& s) {
  Real inner = std::numeric_limits<Real>::infinity();
  for (const HullFace& f : s.hull->faces())
    inner = std::min(inner, f.offset);
  return inner;
}

// Drawn from its support map: its vertices, joined by the icosphere's connectivity.
SurfaceMesh surface_mesh(const Shape& s, const TessellationDetail& detail) {
  return tessellate_convex_support(s, detail);
}

}  // namespace

const ShapeOps kHullOps{"hull",          support, world_aabb,      volume,       unit_inertia,
                        bounding_radius, ray,     signed_distance, inner_radius, surface_mesh};

}  // namespace tumble
