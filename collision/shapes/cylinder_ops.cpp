// The cylinder's row of the shape table (collision/shapes/shape_ops.hpp): axis z, from
// -half_length to half_length.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "collision/shapes/shape_rows.hpp"
#include "collision/shapes/surface_mesh.hpp"

namespace tumble {
namespace {

using shape_geometry::sign_or_plus;

Vec3 support(const Shape& s, const Vec3& d) {
  // The rim point in the direction's projection on the cap plane; a direction along the axis
  // has a whole cap as support, and the cap's centre is returned.
  const Real radial = std::sqrt(d.x() * d.x() + d.y() * d.y());
  const Real z = sign_or_plus(d.z()) * s.half_length;
  if (radial > 0)
    return {d.x() / radial * s.radius, d.y() / radial * s.radius, z};
  return {0, 0, z};
}

Aabb world_aabb(const Shape& s, const Transform& pose) {
  // Exact box of a disc pair: a cap disc of radius r with unit normal u extends
  // r sqrt(1 - u_k^2) = r sqrt(u_i^2 + u_j^2) along world axis k. The second form: the first
  // cancels when u is near axis k and then loses up to 1e-8 r (the box came out too small).
  const Vec3 u = pose.rotation * Vec3::UnitZ();
  Vec3 e;
  for (int k = 0; k < 3; ++k) {
    const Real i = u[(k + 1) % 3];
    const Real j = u[(k + 2) % 3];
    e[k] = std::abs(u[k]) * s.half_length + s.radius * std::sqrt(i * i + j * j);
  }
  return {pose.translation - e, pose.translation + e};
}

Real volume(const Shape& s) {
  return std::numbers::pi_v<Real> * s.radius * s.radius * (2 * s.half_length);
}

Mat3 unit_inertia(const Shape& s) {
  const Real r = s.radius;
  const Real h = 2 * s.half_length;
  const Real transverse = (3 * r * r + h * h) / 12;
  return Vec3(transverse, transverse, r * r / 2).asDiagonal();
}

Real bounding_radius(const Shape& s) {
  return std::sqrt(s.half_length * s.half_length + s.radius * s.radius);
}

// Ericson, Real-Time Collision Detection, 2005, 5.3.7: the side, then the caps.
ShapeRayHit ray(const Shape& s, const Vec3& o, const Vec3& d) {
  const Real r = s.radius;
  const Real hl = s.half_length;
  Vec3 normal;
  Real best = shape_geometry::disc_side_hit(o, d, r, hl, normal);
  // Caps: entering through z = +hl moving down, or z = -hl moving up.
  for (const Real side : {Real(-1), Real(1)}) {
    if (d.z() * side >= 0)
      continue;
    const Real tc = (side * hl - o.z()) / d.z();
    const Vec3 p = o + tc * d;
    if (tc >= 0 && tc < best && p.x() * p.x() + p.y() * p.y() <= r * r) {
      best = tc;
      normal = Vec3(0, 0, side);
    }
  }
  if (best <= 1)
    return {true, best, normal};
  return {};
}

Real signed_distance(const Shape& s, const Vec3& p) {
  // Exact for a finite cylinder: d = (|p_xy| - r, |z| - h).
  const Real dr = std::hypot(p.x(), p.y()) - s.radius;
  const Real dz = std::abs(p.z()) - s.half_length;
  return std::hypot(std::max(dr, Real(0)), std::max(dz, Real(0))) +
         std::min(std::max(dr, dz), Real(0));
}

Real inner_radius(const Shape& s) {
  return std::min(s.radius, s.half_length);
}

// Drawn from its support map (no dedicated mesh).
SurfaceMesh surface_mesh(const Shape& s, const TessellationDetail& detail) {
  return tessellate_convex_support(s, detail);
}

}  // namespace

const ShapeOps kCylinderOps{"cylinder",      support, world_aabb,      volume,       unit_inertia,
                            bounding_radius, ray,     signed_distance, inner_radius, surface_mesh};

}  // namespace tumble
