// The box's row of the shape table (collision/shapes/shape_ops.hpp): half extents along the
// local axes.
#include <algorithm>
#include <cmath>

#include "collision/shapes/shape_rows.hpp"
#include "collision/shapes/surface_mesh.hpp"

namespace tumble {
namespace {

using shape_geometry::sign_or_plus;

Vec3 support(const Shape& s, const Vec3& d) {
  return {sign_or_plus(d.x()) * s.half_extents.x(), sign_or_plus(d.y()) * s.half_extents.y(),
          sign_or_plus(d.z()) * s.half_extents.z()};
}

Aabb world_aabb(const Shape& s, const Transform& pose) {
  // Extent along each world axis is |R| * h (Arvo, "Transforming Axis-Aligned Bounding Boxes",
  // Graphics Gems 1990).
  const Mat3 r = pose.rotation.toRotationMatrix().cwiseAbs();
  const Vec3 e = r * s.half_extents;
  return {pose.translation - e, pose.translation + e};
}

Real volume(const Shape& s) {
  return 8 * s.half_extents.prod();
}

Mat3 unit_inertia(const Shape& s) {
  const Vec3 h2 = s.half_extents.cwiseProduct(s.half_extents);
  return Vec3(h2.y() + h2.z(), h2.x() + h2.z(), h2.x() + h2.y()).asDiagonal() * (Real(1) / 3);
}

Real bounding_radius(const Shape& s) {
  return s.half_extents.norm();
}

// Slabs (Ericson, Real-Time Collision Detection, 2005, 5.3.3).
ShapeRayHit ray(const Shape& s, const Vec3& o, const Vec3& d) {
  ShapeRayHit out;
  Real enter = 0;
  Real exit = 1;
  int enter_axis = -1;
  Real enter_sign = 1;
  for (int k = 0; k < 3; ++k) {
    const Real h = s.half_extents[k];
    if (d[k] == 0) {
      if (std::abs(o[k]) > h)
        return out;
      continue;
    }
    Real t0 = (-h - o[k]) / d[k];
    Real t1 = (h - o[k]) / d[k];
    Real sign = -1;  // entering through the -h face when moving in +k
    if (t0 > t1) {
      std::swap(t0, t1);
      sign = 1;
    }
    if (t0 > enter) {
      enter = t0;
      enter_axis = k;
      enter_sign = sign;
    }
    exit = std::min(exit, t1);
    if (enter > exit)
      return out;
  }
  if (enter_axis < 0)
    return out;  // starts inside: handled by ray_cast()
  out.hit = true;
  out.fraction = enter;
  out.normal = Vec3::Zero();
  out.normal[enter_axis] = enter_sign;
  return out;
}

Real signed_distance(const Shape& s, const Vec3& p) {
  const Vec3 q = p.cwiseAbs() - s.half_extents;
  return q.cwiseMax(Real(0)).norm() + std::min(q.maxCoeff(), Real(0));
}

Real inner_radius(const Shape& s) {
  return s.half_extents.minCoeff();
}

SurfaceMesh surface_mesh(const Shape& s, const TessellationDetail&) {
  return tessellate_box(s.half_extents);
}

}  // namespace

const ShapeOps kBoxOps{"box",           support, world_aabb,      volume,       unit_inertia,
                       bounding_radius, ray,     signed_distance, inner_radius, surface_mesh};

}  // namespace tumble
