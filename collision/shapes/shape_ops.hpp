// Everything the engine asks of a shape type, as one row of a table indexed by ShapeType: its
// name, support point, bounding box, volume, inertia, bounding radius, ray cast, signed distance
// and inner radius. Each row is written in one file, collision/shapes/<type>_ops.cpp, so a new
// shape type is one new row here (and one new row and column of pair functions in the narrow
// phase's collide_table, collision/narrow_phase/narrow_phase.cpp); collision/shapes/shape.hpp and
// collision/ccd/ray_cast.hpp call through the table.
#pragma once

#include <string_view>

#include "collision/aabb.hpp"
#include "collision/math.hpp"
#include "tumble/shape.hpp"

namespace tumble {

struct SurfaceMesh;
struct TessellationDetail;

struct ShapeRayHit {
  bool hit = false;
  // Where along the ray the surface is first met: point = origin + fraction * delta, in [0, 1].
  // A ray starting inside the shape hits at fraction 0.
  Real fraction = 1;
  Vec3 normal = Vec3::UnitZ();  // outward surface normal at the hit (world); -delta/|delta| at 0
};

struct ShapeOps {
  std::string_view name;
  // Farthest point along a direction (local frame; the direction need not be unit). A plane has
  // none (its row returns the origin; nothing asks).
  Vec3 (*support)(const Shape& shape, const Vec3& direction);
  Aabb (*world_aabb)(const Shape& shape, const Transform& pose);
  Real (*volume)(const Shape& shape);        // m^3
  Mat3 (*unit_inertia)(const Shape& shape);  // per unit mass, about the centre of mass [m^2]
  Real (*bounding_radius)(const Shape& shape);
  // The segment from `origin` to `origin + delta` (local frame), for a ray that starts outside
  // the shape (ray_cast() answers a ray that starts inside).
  ShapeRayHit (*ray)(const Shape& shape, const Vec3& origin, const Vec3& delta);
  // Signed distance of a local point to the surface (negative inside).
  Real (*signed_distance)(const Shape& shape, const Vec3& point);
  // Radius of a ball about the local origin (the centre of mass) that lies inside the shape: how
  // far the shape can move before it could pass through something thin (continuous collision).
  Real (*inner_radius)(const Shape& shape);
  // The surface as triangles, local frame (collision/shapes/surface_mesh.hpp); throws
  // std::invalid_argument for an unbounded shape.
  SurfaceMesh (*surface_mesh)(const Shape& shape, const TessellationDetail& detail);
};

const ShapeOps& shape_ops(ShapeType type);

}  // namespace tumble
