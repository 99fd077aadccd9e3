#include "collision/shapes/shape.hpp"

#include "collision/shapes/shape_ops.hpp"

namespace tumble {

std::string_view shape_type_name(ShapeType type) {
  if (static_cast<int>(type) >= kShapeTypeCount)
    return "unknown";
  return shape_ops(type).name;
}

Shape Shape::sphere(Real radius) {
  Shape s;
  s.type = ShapeType::sphere;
  s.radius = radius;
  return s;
}

Shape Shape::box(const Vec3& half_extents) {
  Shape s;
  s.type = ShapeType::box;
  s.half_extents = half_extents;
  return s;
}

Shape Shape::capsule(Real radius, Real half_length) {
  Shape s;
  s.type = ShapeType::capsule;
  s.radius = radius;
  s.half_length = half_length;
  return s;
}

Shape Shape::plane() {
  Shape s;
  s.type = ShapeType::plane;
  return s;
}

Shape Shape::cylinder(Real radius, Real half_length) {
  Shape s;
  s.type = ShapeType::cylinder;
  s.radius = radius;
  s.half_length = half_length;
  return s;
}

Shape Shape::convex_hull(std::shared_ptr<const ConvexHull> hull) {
  Shape s;
  s.type = ShapeType::hull;
  s.hull = std::move(hull);
  return s;
}

Shape Shape::triangle_mesh(std::shared_ptr<const TriangleMesh> mesh) {
  Shape s;
  s.type = ShapeType::mesh;
  s.mesh = std::move(mesh);
  return s;
}

Shape Shape::compound_of(std::shared_ptr<const CompoundShape> compound) {
  Shape s;
  s.type = ShapeType::compound;
  s.compound = std::move(compound);
  return s;
}

Shape Shape::signed_distance_field(std::shared_ptr<const SdfShape> sdf) {
  Shape s;
  s.type = ShapeType::sdf;
  s.sdf = std::move(sdf);
  return s;
}

// Each shape type's answers are its row of the table (collision/shapes/<type>_ops.cpp).

Vec3 support(const Shape& shape, const Vec3& d) {
  return shape_ops(shape.type).support(shape, d);
}

Aabb world_aabb(const Shape& shape, const Transform& pose) {
  return shape_ops(shape.type).world_aabb(shape, pose);
}

Real volume(const Shape& shape) {
  return shape_ops(shape.type).volume(shape);
}

Mat3 unit_inertia(const Shape& shape) {
  return shape_ops(shape.type).unit_inertia(shape);
}

Real bounding_radius(const Shape& shape) {
  return shape_ops(shape.type).bounding_radius(shape);
}

Real inner_radius(const Shape& shape) {
  return shape_ops(shape.type).inner_radius(shape);
}

}  // namespace tumble
