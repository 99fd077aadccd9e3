// Shapes, in their local frame with the centre of mass at the origin. Sphere, box, capsule (core
// segment along local z), plane (the half-space z <= 0), cylinder (axis along local z), convex
// hull, static triangle mesh, compound (several convex parts in one body), and a solid given by a
// signed distance field (docs/sdf.md).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "tumble/math.hpp"

namespace tumble {

// The shared geometry of hulls, meshes and compounds; built by the functions at the end of this
// file, opaque to users (collision/shapes/convex_hull.hpp, triangle_mesh.hpp, compound_shape.hpp).
class ConvexHull;
class TriangleMesh;
class CompoundShape;
class SdfShape;

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
  sdf = 8,
};
inline constexpr int kShapeTypeCount = 9;

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
  std::shared_ptr<const SdfShape> sdf;  // sdf: the field, re-centred on its centre of mass
  // sdf: the time [s] a field that changes with time (a morph) is evaluated at; a World keeps it
  // at its clock.
  Real field_time = 0;

  static Shape sphere(Real radius);
  static Shape box(const Vec3& half_extents);
  static Shape capsule(Real radius, Real half_length);
  static Shape plane();
  static Shape cylinder(Real radius, Real half_length);
  static Shape convex_hull(std::shared_ptr<const ConvexHull> hull);
  static Shape triangle_mesh(std::shared_ptr<const TriangleMesh> mesh);
  static Shape compound_of(std::shared_ptr<const CompoundShape> compound);
  static Shape signed_distance_field(std::shared_ptr<const SdfShape> sdf);

  // Bounded shapes can be dynamic; a plane is infinite and only ever static.
  bool is_bounded() const { return type != ShapeType::plane; }
};

// Shapes built from data. Each throws tumble::Error naming what is wrong (too few points, a flat
// hull, a triangle index out of range, a part that is not convex).
//
// The convex hull of `points` (at least 4, not all in one plane), re-centred on its centre of
// mass; `centre_of_mass` (if given) receives that centre in the points' frame, where a body must
// be placed for the hull to sit where the points were.
Shape hull_from_points(std::span<const Vec3> points, Vec3* centre_of_mass = nullptr);
// A static triangle mesh; each triangle lists three vertex indices, counter-clockwise seen from
// the side bodies rest on.
Shape mesh_from_triangles(std::vector<Vec3> vertices,
                          std::vector<std::array<std::int32_t, 3>> triangles);
// One convex part of a compound: its shape and its pose in the compound's frame.
struct CompoundPart {
  Shape shape;
  Transform pose;
};
// A compound of spheres, boxes, capsules, cylinders and hulls (at most 256), of one density,
// re-centred on its centre of mass like hull_from_points.
Shape compound_from_parts(std::vector<CompoundPart> parts, Vec3* centre_of_mass = nullptr);

// Training shapes (BodyDesc::train_shape): simpler collision geometry for a body whose mass,
// inertia and centre of mass stay those of its detailed shape. They live in that body's frame,
// so these builders keep the points or parts where they are given (no re-centring).
Shape hull_in_frame(std::span<const Vec3> points);
Shape compound_in_frame(std::vector<CompoundPart> parts);

// A simple shape fitted around `detailed`, in its frame: the smallest box, sphere or capsule
// centred on the frame's origin (the centre of mass) and aligned with its axes (the capsule along
// the axis of largest extent) that contains the shape, or its convex hull. Round parts count by
// their exact extent; a cylinder by 32 points on each rim. Throws tumble::Error for a plane.
enum class ShapeFit : std::uint8_t { box, sphere, capsule, hull };
Shape fit_shape(const Shape& detailed, ShapeFit fit);

}  // namespace tumble
