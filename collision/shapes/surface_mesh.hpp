// Triangle meshes of shapes' surfaces, for drawing them (renders/) and for anything else that
// needs a shape as triangles. Each shape's row of the shape table (collision/shapes/shape_ops.hpp)
// names its tessellation: a dedicated one (sphere, box, capsule, a mesh's own triangles, a
// compound's parts, a field's zero set) or the generic one of any convex shape driven only by its
// support map, which a new convex ShapeType draws through until it gets its own.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/math.hpp"

namespace tumble {

class CompoundShape;
class SdfShape;
class TriangleMesh;
struct Shape;

// Unindexed-friendly indexed mesh in the shape's local frame. Triangles wind counter-clockwise
// seen from outside; normals are unit and point outwards.
struct SurfaceMesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  std::vector<std::uint32_t> indices;  // three per triangle

  int triangle_count() const { return static_cast<int>(indices.size() / 3); }
};

// How finely curved surfaces are cut; `detail` 1 is coarse, 3 is smooth at 1280x720.
struct TessellationDetail {
  int segments = 32;    // around a sphere's or capsule's axis
  int subdivision = 3;  // icosphere subdivisions of the generic path (20 * 4^n triangles)
};

SurfaceMesh tessellate_sphere(Real radius, const TessellationDetail& detail);
SurfaceMesh tessellate_box(const Vec3& half_extents);
SurfaceMesh tessellate_capsule(Real radius, Real half_length, const TessellationDetail& detail);

// Any bounded convex shape: the support points along the vertex directions of a subdivided
// icosahedron, joined with the icosahedron's own connectivity. A direction d is the normal of a
// supporting plane at support(d), so smooth parts are shaded with d; triangles spanning an edge
// or corner (where many directions share one point) take their face normal, and triangles that
// collapse to a point or segment are dropped.
SurfaceMesh tessellate_convex_support(const Shape& shape, const TessellationDetail& detail);

// The surface of a signed distance field, by marching tetrahedra on a grid of `cells` cells along
// the longest side of its bounds (collision/shapes/sdf_surface_mesh.cpp).
SurfaceMesh tessellate_sdf(const SdfShape& field, int cells);

// A triangle mesh as it is: its own triangles, flat shaded (each corner carries the face normal).
SurfaceMesh tessellate_triangle_mesh(const TriangleMesh& mesh);
// A compound: its parts' meshes, each placed by its pose.
SurfaceMesh tessellate_compound(const CompoundShape& compound, const TessellationDetail& detail);

// The mesh of a bounded shape, as its row of the shape table makes it. Throws
// std::invalid_argument for shapes it cannot draw (unbounded ones: planes are drawn as floors by
// the renderer, not meshed here).
SurfaceMesh tessellate(const Shape& shape, const TessellationDetail& detail);

// Unit directions of an icosahedron subdivided `subdivision` times, and its triangles.
void icosphere(int subdivision, std::vector<Vec3>& directions, std::vector<std::uint32_t>& indices);

// Signed volume enclosed by a closed mesh (divergence theorem) [m^3]; positive when the
// triangles wind outwards.
Real enclosed_volume(const SurfaceMesh& mesh);

}  // namespace tumble
