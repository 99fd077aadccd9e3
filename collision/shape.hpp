// Shapes, in their local frame with the centre of mass at the origin. Sphere, box, capsule (core
// segment along local z), plane (the half-space z <= 0), cylinder (axis along local z), convex
// hull (collision/convex_hull.hpp), and the static triangle mesh and compound body (added by the
// mesh work).
#pragma once

#include <cstdint>
#include <memory>
#include <string_view>

#include "collision/aabb.hpp"
#include "collision/math.hpp"

namespace tumble {

class ConvexHull;     // collision/convex_hull.hpp
class TriangleMesh;   // collision/triangle_mesh.hpp
class CompoundShape;  // collision/compound_shape.hpp

// The values are fixed: dispatch tables and saved data index by them.
enum class ShapeType : std::uint8_t {
  sphere = 0,
  box = 1,
  capsule = 2,
  plane = 3,
  cylinder = 4,
  hull = 5,
  mesh = 6,
  compound = 7,
};
inline constexpr int kShapeTypeCount = 8;

std::string_view shape_type_name(ShapeType type);

// A flat value type: one struct for every primitive, so shapes sit in contiguous arrays and
// dispatch is an index into a table. Fields a type does not use stay zero.
struct Shape {
  ShapeType type = ShapeType::sphere;
  Real radius = 0;                   // sphere, capsule, cylinder [m]
  Real half_length = 0;              // capsule: half the core segment; cylinder: half height [m]
  Vec3 half_extents = Vec3::Zero();  // box [m]
  // hull: the shared, immutable hull (vertices re-centred on its centre of mass).
  std::shared_ptr<const ConvexHull> hull;
  std::shared_ptr<const TriangleMesh> mesh;       // mesh (static only)
  std::shared_ptr<const CompoundShape> compound;  // compound

  static Shape sphere(Real radius);
  static Shape box(const Vec3& half_extents);
  static Shape capsule(Real radius, Real half_length);
  static Shape plane();
  static Shape cylinder(Real radius, Real half_length);
  static Shape convex_hull(std::shared_ptr<const ConvexHull> hull);
  static Shape triangle_mesh(std::shared_ptr<const TriangleMesh> mesh);
  static Shape compound_of(std::shared_ptr<const CompoundShape> compound);

  // Bounded shapes can be dynamic; a plane is infinite and only ever static.
  bool is_bounded() const { return type != ShapeType::plane; }
};

// Farthest point of the shape along `direction` (local frame; direction need not be unit).
// For a plane the support is unbounded in most directions; it is never asked for.
Vec3 support(const Shape& shape, const Vec3& direction);

// World-space bounding box of the shape under `pose`. A plane's box is infinite except along a
// world axis that is exactly its normal.
Aabb world_aabb(const Shape& shape, const Transform& pose);

// Volume [m^3]; infinite for a plane.
Real volume(const Shape& shape);

// Inertia tensor per unit mass about the centre of mass, in the local frame [m^2].
// Multiply by the body's mass to get kg m^2.
Mat3 unit_inertia(const Shape& shape);

// Radius of the smallest origin-centred sphere that holds the shape [m]; used to bound the
// speed of surface points from linear and angular velocity.
Real bounding_radius(const Shape& shape);

}  // namespace tumble
