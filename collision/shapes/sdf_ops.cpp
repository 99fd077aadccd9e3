// The signed distance field's row of the shape table (collision/shapes/shape_ops.hpp): a solid
// known by its field (collision/shapes/sdf_shape.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/shape_rows.hpp"
#include "collision/shapes/surface_mesh.hpp"

namespace tumble {
namespace {

// The farthest surface point: exact to the points' spacing (a fraction of a cell on curved
// parts), which is all the callers (shape fitting, bounds) need.
Vec3 support(const Shape& s, const Vec3& d) {
  const SdfShape& f = *s.sdf;
  Vec3 best = Vec3::Zero();
  Real best_dot = -std::numeric_limits<Real>::infinity();
  for (const Vec3& p : f.surface_points()) {
    const Real v = p.dot(d);
    if (v > best_dot) {
      best_dot = v;
      best = p;
    }
  }
  return best;
}

Aabb world_aabb(const Shape& s, const Transform& pose) {
  return s.sdf->local_bounds().placed(pose);
}

Real volume(const Shape& s) {
  return s.sdf->volume();
}

Mat3 unit_inertia(const Shape& s) {
  return s.sdf->unit_inertia();
}

Real bounding_radius(const Shape& s) {
  return s.sdf->bounding_radius();
}

// Sphere tracing (Hart, "Sphere tracing", The Visual Computer 12, 1996): steps of phi along the
// ray, safe because |phi| never exceeds the distance to the surface (docs/sdf.md), from where the
// segment enters the bounds; a hit when phi falls below a millionth of the solid's size.
ShapeRayHit ray(const Shape& s, const Vec3& o, const Vec3& d) {
  const SdfShape& f = *s.sdf;
  const Aabb& box = f.local_bounds();
  Real enter = 0;
  Real exit = 1;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) {
      if (o[k] < box.min[k] || o[k] > box.max[k])
        return {};
      continue;
    }
    Real t0 = (box.min[k] - o[k]) / d[k];
    Real t1 = (box.max[k] - o[k]) / d[k];
    if (t0 > t1)
      std::swap(t0, t1);
    enter = std::max(enter, t0);
    exit = std::min(exit, t1);
  }
  if (enter > exit)
    return {};
  const Real length = d.norm();
  if (!(length > 0))
    return {};
  const Real tolerance = f.bounding_radius() * Real(1e-6);
  Real t = enter;
  for (int step = 0; step < 512 && t <= exit; ++step) {
    const sdf::Sample sample = f.sample(o + t * d, s.field_time);
    if (sample.distance <= tolerance) {
      const Real g = sample.gradient.norm();
      return {true, t, g > 0 ? Vec3(sample.gradient / g) : Vec3(-d / length)};
    }
    t += std::max(sample.distance, tolerance) / length;
  }
  return {};
}

Real signed_distance(const Shape& s, const Vec3& p) {
  return s.sdf->distance(p, s.field_time);
}

// The largest ball inside, from the field's grid.
Real inner_radius(const Shape& s) {
  return s.sdf->inner_radius();
}

SurfaceMesh surface_mesh(const Shape& s, const TessellationDetail& detail) {
  return tessellate_sdf(*s.sdf, 16 * detail.subdivision + 16);
}

}  // namespace

const ShapeOps kSdfOps{"sdf",           support, world_aabb,      volume,       unit_inertia,
                       bounding_radius, ray,     signed_distance, inner_radius, surface_mesh};

}  // namespace tumble
