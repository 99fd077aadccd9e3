// The sphere's row of the shape table (collision/shapes/shape_ops.hpp): centred on its origin.
#include <numbers>

#include "collision/shapes/shape_rows.hpp"
#include "collision/shapes/surface_mesh.hpp"

namespace tumble {
namespace {

using shape_geometry::unit_or_z;

Vec3 support(const Shape& s, const Vec3& d) {
  return unit_or_z(d) * s.radius;
}

Aabb world_aabb(const Shape& s, const Transform& pose) {
  const Vec3 r = Vec3::Constant(s.radius);
  return {pose.translation - r, pose.translation + r};
}

Real volume(const Shape& s) {
  return Real(4) / 3 * std::numbers::pi_v<Real> * s.radius * s.radius * s.radius;
}

Mat3 unit_inertia(const Shape& s) {
  return Mat3::Identity() * (Real(2) / 5 * s.radius * s.radius);
}

Real bounding_radius(const Shape& s) {
  return s.radius;
}

ShapeRayHit ray(const Shape& s, const Vec3& o, const Vec3& d) {
  Real t = 0;
  if (shape_geometry::sphere_hit(o, d, s.radius, t))
    return {true, t, (o + t * d) / s.radius};
  return {};
}

Real signed_distance(const Shape& s, const Vec3& p) {
  return p.norm() - s.radius;
}

Real inner_radius(const Shape& s) {
  return s.radius;
}

SurfaceMesh surface_mesh(const Shape& s, const TessellationDetail& detail) {
  return tessellate_sphere(s.radius, detail);
}

}  // namespace

const ShapeOps kSphereOps{"sphere",        support, world_aabb,      volume,       unit_inertia,
                          bounding_radius, ray,     signed_distance, inner_radius, surface_mesh};

}  // namespace tumble
