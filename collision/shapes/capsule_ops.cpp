// The capsule's row of the shape table (collision/shapes/shape_ops.hpp): the segment from
// (0, 0, -half_length) to (0, 0, half_length) swept by a sphere of `radius`.
#include <algorithm>
#include <numbers>

#include "collision/shapes/shape_rows.hpp"
#include "collision/shapes/surface_mesh.hpp"

namespace tumble {
namespace {

using shape_geometry::sign_or_plus;
using shape_geometry::unit_or_z;

Vec3 support(const Shape& s, const Vec3& d) {
  return Vec3(0, 0, sign_or_plus(d.z()) * s.half_length) + unit_or_z(d) * s.radius;
}

Aabb world_aabb(const Shape& s, const Transform& pose) {
  const Vec3 axis = pose.rotation * Vec3(0, 0, s.half_length);
  const Vec3 e = axis.cwiseAbs() + Vec3::Constant(s.radius);
  return {pose.translation - e, pose.translation + e};
}

Real volume(const Shape& s) {
  constexpr Real pi = std::numbers::pi_v<Real>;
  const Real r = s.radius;
  return pi * r * r * (2 * s.half_length) + Real(4) / 3 * pi * r * r * r;
}

Mat3 unit_inertia(const Shape& s) {
  // Cylinder of height 2a plus two hemispherical caps. A cap of mass m_h has its centroid 3r/8
  // from its flat face and a transverse inertia of (83/320) m_h r^2 about it; with the
  // parallel-axis shift the two caps give m_s (2r^2/5 + a^2 + 3ar/4) (m_s both caps).
  const Real r = s.radius;
  const Real a = s.half_length;
  const Real v_cyl = 2 * a;            // proportional to pi r^2 (2a)
  const Real v_sph = Real(4) / 3 * r;  // proportional to pi r^2 (4r/3)
  const Real m_cyl = v_cyl / (v_cyl + v_sph);
  const Real m_sph = v_sph / (v_cyl + v_sph);
  const Real axial = m_cyl * r * r / 2 + m_sph * Real(2) / 5 * r * r;
  const Real transverse =
      m_cyl * (r * r / 4 + a * a / 3) + m_sph * (Real(2) / 5 * r * r + a * a + Real(3) / 4 * a * r);
  return Vec3(transverse, transverse, axial).asDiagonal();
}

Real bounding_radius(const Shape& s) {
  return s.half_length + s.radius;
}

// Its side (Ericson 5.3.7's cylinder without caps) and two end spheres (5.3.2).
ShapeRayHit ray(const Shape& s, const Vec3& o, const Vec3& d) {
  const Real r = s.radius;
  const Real hl = s.half_length;
  Vec3 normal;
  Real best = shape_geometry::disc_side_hit(o, d, r, hl, normal);
  Real t = 0;
  for (Real end : {-hl, hl}) {
    const Vec3 centre(0, 0, end);
    if (shape_geometry::sphere_hit(o - centre, d, r, t) && t < best) {
      best = t;
      normal = (o + t * d - centre) / r;
    }
  }
  if (best <= 1)
    return {true, best, normal};
  return {};
}

Real signed_distance(const Shape& s, const Vec3& p) {
  const Real z = std::clamp(p.z(), -s.half_length, s.half_length);
  return (p - Vec3(0, 0, z)).norm() - s.radius;
}

Real inner_radius(const Shape& s) {
  return s.radius;
}

SurfaceMesh surface_mesh(const Shape& s, const TessellationDetail& detail) {
  return tessellate_capsule(s.radius, s.half_length, detail);
}

}  // namespace

const ShapeOps kCapsuleOps{"capsule",       support, world_aabb,      volume,       unit_inertia,
                           bounding_radius, ray,     signed_distance, inner_radius, surface_mesh};

}  // namespace tumble
