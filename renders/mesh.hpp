// Triangle meshes for drawing shapes. One function per shape type, plus a generic tessellation
// of any convex shape driven only by its support map, which every new convex ShapeType renders
// through until it gets a dedicated mesh.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/math.hpp"
#include "collision/shapes/shape.hpp"

namespace tumble::render {

// Unindexed-friendly indexed mesh in the shape's local frame. Triangles wind counter-clockwise
// seen from outside; normals are unit and point outwards.
struct Mesh {
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

Mesh tessellate_sphere(Real radius, const TessellationDetail& detail);
Mesh tessellate_box(const Vec3& half_extents);
Mesh tessellate_capsule(Real radius, Real half_length, const TessellationDetail& detail);

// Any bounded convex shape: the support points along the vertex directions of a subdivided
// icosahedron, joined with the icosahedron's own connectivity. A direction d is the normal of a
// supporting plane at support(d), so smooth parts are shaded with d; triangles spanning an edge
// or corner (where many directions share one point) take their face normal, and triangles that
// collapse to a point or segment are dropped.
Mesh tessellate_convex_support(const Shape& shape, const TessellationDetail& detail);

// The surface of a signed distance field, by marching tetrahedra on a grid of `cells` cells along
// the longest side of its bounds (renders/sdf_mesh.cpp).
Mesh tessellate_sdf(const SdfShape& field, int cells);

// The mesh for a bounded shape: a dedicated one where there is one, else the generic convex
// path. Throws std::invalid_argument for shapes it cannot draw (unbounded ones: planes are drawn
// as floors by the renderer, not meshed here).
Mesh tessellate(const Shape& shape, const TessellationDetail& detail);

// Unit directions of an icosahedron subdivided `subdivision` times, and its triangles.
void icosphere(int subdivision, std::vector<Vec3>& directions, std::vector<std::uint32_t>& indices);

// Signed volume enclosed by a closed mesh (divergence theorem) [m^3]; positive when the
// triangles wind outwards.
Real enclosed_volume(const Mesh& mesh);

}  // namespace tumble::render
