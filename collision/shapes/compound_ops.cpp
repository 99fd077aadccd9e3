// The compound's row of the shape table (collision/shapes/shape_ops.hpp): convex parts placed in
// the compound's frame, each answered by its own row.
#include <algorithm>
#include <limits>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/shape_rows.hpp"
#include "collision/shapes/surface_mesh.hpp"

namespace tumble {
namespace {

Vec3 support(const Shape& s, const Vec3& d) {
  return s.compound->support(d);
}

Aabb world_aabb(const Shape& s, const Transform& pose) {
  return s.compound->world_aabb(pose);
}

Real volume(const Shape& s) {
  return s.compound->volume();
}

Mat3 unit_inertia(const Shape& s) {
  return s.compound->unit_inertia();
}

Real bounding_radius(const Shape& s) {
  return s.compound->bounding_radius();
}

// The nearest part's hit.
ShapeRayHit ray(const Shape& s, const Vec3& o, const Vec3& d) {
  ShapeRayHit out;
  for (const CompoundPart& part : s.compound->parts()) {
    ShapeRayHit h = shape_ops(part.shape.type)
                        .ray(part.shape, part.pose.apply_inverse(o), part.pose.rotate_inverse(d));
    if (h.hit && (!out.hit || h.fraction < out.fraction)) {
      h.normal = part.pose.rotate(h.normal);
      out = h;
    }
  }
  return out;
}

// The union's distance outside; inside, the deepest part's (a bound on the union's).
Real signed_distance(const Shape& s, const Vec3& p) {
  Real best = std::numeric_limits<Real>::infinity();
  for (const CompoundPart& part : s.compound->parts())
    best = std::min(
        best, shape_ops(part.shape.type).signed_distance(part.shape, part.pose.apply_inverse(p)));
  return best;
}

// The thinnest part's (a body is swept as soon as any part could pass through something).
Real inner_radius(const Shape& s) {
  Real thinnest = std::numeric_limits<Real>::infinity();
  for (const CompoundPart& part : s.compound->parts())
    thinnest = std::min(thinnest, shape_ops(part.shape.type).inner_radius(part.shape));
  return thinnest;
}

SurfaceMesh surface_mesh(const Shape& s, const TessellationDetail& detail) {
  return tessellate_compound(*s.compound, detail);
}

}  // namespace

const ShapeOps kCompoundOps{"compound",      support, world_aabb,      volume,       unit_inertia,
                            bounding_radius, ray,     signed_distance, inner_radius, surface_mesh};

}  // namespace tumble
