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

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0)
    return a;
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  const Real vc = d1 * d4 - d3 * d2;
  const Real vb = d5 * d2 - d1 * d6;
  const Real va = d3 * d6 - d5 * d4;
  if (d3 >= 0 && d4 <= d3)
    return b;
  if (vc <= 0 && d1 >= 0 && d3 <= 0)
    return a + ab * (d1 / (d1 - d3));
  if (d6 >= 0 && d5 <= d6)
    return c;
  if (vb <= 0 && d2 >= 0 && d6 <= 0)
    return a + ac * (d2 / (d2 - d6));
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  return a + ab * (vb / (va + vb + vc)) + ac * (vc / (va + vb + vc));
}

}  // namespace shape_geometry
}  // namespace tumble
