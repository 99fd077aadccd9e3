// Ray casts and signed distances through each shape type's row of the shape table
// (collision/shapes/shape_ops.hpp), where the per-shape methods are written and cited.
#include "collision/ccd/ray_cast.hpp"

namespace tumble {

Real signed_distance(const Shape& shape, const Transform& pose, const Vec3& point) {
  return shape_ops(shape.type).signed_distance(shape, pose.apply_inverse(point));
}

ShapeRayHit ray_cast(const Shape& shape, const Transform& pose, const Vec3& origin,
                     const Vec3& delta) {
  ShapeRayHit out;
  if (!origin.allFinite() || !delta.allFinite())
    return out;
  if (signed_distance(shape, pose, origin) <= 0) {
    out.hit = true;
    out.fraction = 0;
    const Real length = delta.norm();
    out.normal = length > 0 ? Vec3(-delta / length) : Vec3::UnitZ();
    return out;
  }
  const Vec3 o = pose.apply_inverse(origin);
  const Vec3 d = pose.rotate_inverse(delta);
  out = shape_ops(shape.type).ray(shape, o, d);
  if (out.hit)
    out.normal = pose.rotate(out.normal);
  return out;
}

}  // namespace tumble
