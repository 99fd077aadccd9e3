// The shape table (collision/shapes/shape_ops.hpp) and the helpers its rows share.
#include "collision/shapes/shape_ops.hpp"

#include <array>
#include <cmath>
#include <limits>

#include "collision/shapes/shape_rows.hpp"

namespace tumble {
namespace {

// In ShapeType order (include/tumble/shape.hpp).
constexpr std::array<const ShapeOps*, kShapeTypeCount> kRows{
    &kSphereOps, &kBoxOps,  &kCapsuleOps,  &kPlaneOps, &kCylinderOps,
    &kHullOps,   &kMeshOps, &kCompoundOps, &kSdfOps};

}  // namespace

const ShapeOps& shape_ops(ShapeType type) {
  return *kRows[static_cast<std::size_t>(type)];
}

namespace shape_geometry {

bool sphere_hit(const Vec3& o, const Vec3& d, Real r, Real& t) {
  const Real a = d.squaredNorm();
  const Real b = o.dot(d);
  const Real c = o.squaredNorm() - r * r;
  if (a == 0 || b >= 0)
    return false;  // still or moving away from the centre
  const Real disc = b * b - a * c;
  if (disc < 0)
    return false;
  // Entering root -(b + sqrt(disc)) / a written as c / q to avoid cancellation (b < 0).
  const Real q = -b + std::sqrt(disc);
  t = c / q;
  return t >= 0 && t <= 1;
}

Real disc_side_hit(const Vec3& o, const Vec3& d, Real radius, Real half_length, Vec3& normal) {
  normal = Vec3::UnitZ();
  const Vec3 oxy(o.x(), o.y(), 0);
  const Vec3 dxy(d.x(), d.y(), 0);
  Real t = 0;
  if (!sphere_hit(oxy, dxy, radius, t))
    return std::numeric_limits<Real>::infinity();
  const Real z = o.z() + t * d.z();
  if (z < -half_length || z > half_length)
    return std::numeric_limits<Real>::infinity();
  normal = (oxy + t * dxy) / radius;
  return t;
}

}  // namespace shape_geometry
}  // namespace tumble
