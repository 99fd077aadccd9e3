// The plane's row of the shape table (collision/shapes/shape_ops.hpp): the solid half-space
// z <= 0 of its frame; infinite, so only ever static.
#include <limits>
#include <stdexcept>

#include "collision/shapes/shape_rows.hpp"
#include "collision/shapes/surface_mesh.hpp"

namespace tumble {
namespace {

Vec3 support(const Shape&, const Vec3&) {
  return Vec3::Zero();  // unbounded in most directions; never asked for
}

Aabb world_aabb(const Shape&, const Transform& pose) {
  const Real inf = std::numeric_limits<Real>::infinity();
  Aabb box{Vec3::Constant(-inf), Vec3::Constant(inf)};
  const Vec3 n = pose.rotation * Vec3::UnitZ();
  for (int k = 0; k < 3; ++k) {
    // Solid below the plane: bounded above along +k when the normal is exactly +k.
    const Vec3 axis = Vec3::Unit(k);
    if (n == axis)
      box.max[k] = pose.translation[k];
    if (n == -axis)
      box.min[k] = pose.translation[k];
  }
  return box;
}

Real volume(const Shape&) {
  return std::numeric_limits<Real>::infinity();
}

Mat3 unit_inertia(const Shape&) {
  return Mat3::Zero();
}

Real bounding_radius(const Shape&) {
  return std::numeric_limits<Real>::infinity();
}

ShapeRayHit ray(const Shape&, const Vec3& o, const Vec3& d) {
  if (d.z() < 0) {
    const Real t = -o.z() / d.z();
    if (t <= 1)
      return {true, t, Vec3::UnitZ()};
  }
  return {};
}

Real signed_distance(const Shape&, const Vec3& p) {
  return p.z();
}

// Static only: never swept, never asked.
Real inner_radius(const Shape&) {
  return 0;
}

SurfaceMesh surface_mesh(const Shape&, const TessellationDetail&) {
  throw std::invalid_argument("a plane has no mesh; the renderer draws it as a floor");
}

}  // namespace

const ShapeOps kPlaneOps{"plane",         support, world_aabb,      volume,       unit_inertia,
                         bounding_radius, ray,     signed_distance, inner_radius, surface_mesh};

}  // namespace tumble
