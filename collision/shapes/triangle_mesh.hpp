// A static triangle mesh: vertices, triangles, a static bounding volume hierarchy over the
// triangles (so a query touches only nearby triangles), per-edge adjacency with convexity flags
// (for internal-edge handling in the narrow phase) and, when the mesh is closed, its volume and
// inertia by the divergence theorem.
//
// BVH: binned surface area heuristic over triangle centroids (Wald, "On fast Construction of
// SAH-based Bounding Volume Hierarchies", IEEE RT 2007), nodes in one flat array, depth first,
// the left child right after its parent. Mass properties: Eberly, "Polyhedral Mass Properties
// (Revisited)", Geometric Tools 2002 (integrals over signed tetrahedra from the origin).
//
// Meshes are static in tumble (a triangle soup has no well-defined inside for collision), so
// the vertices stay in the body frame as given: the mesh is not re-centred at its centre of mass.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "collision/aabb.hpp"
#include "collision/math.hpp"

namespace tumble {

// Thrown by TriangleMesh::build for unusable input; what() names the triangle or vertex.
struct MeshError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// How the edge between a triangle and its neighbour bends. Seen from the front (the side the
// counter-clockwise normal points to): convex is a ridge, concave a valley.
enum class EdgeKind : std::uint8_t { boundary, flat, convex, concave };

class TriangleMesh {
 public:
  using Triangle = std::array<std::int32_t, 3>;

  // Validates and builds. Throws MeshError on: no triangles, a non-finite vertex, an index out
  // of range, a triangle that repeats a vertex, or one with (near) zero area (below 1e-12 of the
  // squared size of the mesh), or an edge shared by more than two triangles.
  static TriangleMesh build(std::vector<Vec3> vertices, std::vector<Triangle> triangles);

  const std::vector<Vec3>& vertices() const { return vertices_; }
  const std::vector<Triangle>& triangles() const { return triangles_; }
  int triangle_count() const { return int(triangles_.size()); }
  Vec3 corner(int triangle, int k) const { return vertices_[triangles_[triangle][k]]; }
  // Unit normal; the corners run counter-clockwise around it.
  const Vec3& normal(int triangle) const { return normals_[triangle]; }
  // The edge from corner k to corner k+1 (mod 3).
  EdgeKind edge_kind(int triangle, int edge) const { return edge_kinds_[triangle][edge]; }
  // Whether a contact at the corner k may have a normal other than the face normal: the vertex
  // touches a boundary or convex edge. Corners inside a flat or concave region may not.
  bool corner_is_active(int triangle, int k) const { return active_corners_[triangle][k]; }

  const Aabb& local_bounds() const { return bounds_; }
  Aabb world_aabb(const Transform& pose) const;
  // Farthest vertex along `direction` (local frame).
  Vec3 support(const Vec3& direction) const;
  Real bounding_radius() const { return bounding_radius_; }

  // Closed: every edge has exactly two triangles, consistently oriented. Only a closed mesh has
  // a volume; an open one reports volume 0 and zero inertia.
  bool is_closed() const { return closed_; }
  Real volume() const { return volume_; }
  Vec3 centroid() const { return centroid_; }
  // Inertia per unit mass about the centroid, local axes [m^2]; zero for an open mesh.
  const Mat3& unit_inertia() const { return unit_inertia_; }

  // Calls visit(triangle) for every triangle whose bounding box overlaps `box` (local frame), in
  // a fixed order. Allocation-free: the traversal stack lives on the call stack.
  template <class Visit>
  void for_each_overlapping(const Aabb& box, Visit&& visit) const;

  struct Node {
    Aabb bounds;
    std::int32_t first = 0;  // leaf: first index into leaf_triangles_; inner: right child
    std::int32_t count = 0;  // leaf: triangle count (> 0); inner: 0
  };
  static constexpr int kMaxDepth = 64;
  const std::vector<Node>& nodes() const { return nodes_; }

 private:
  void build_adjacency();
  void build_hierarchy();
  void compute_mass_properties();

  std::vector<Vec3> vertices_;
  std::vector<Triangle> triangles_;
  std::vector<Vec3> normals_;
  std::vector<std::array<EdgeKind, 3>> edge_kinds_;
  std::vector<std::array<bool, 3>> active_corners_;
  std::vector<Node> nodes_;
  std::vector<std::int32_t> leaf_triangles_;
  Aabb bounds_;
  Real bounding_radius_ = 0;
  bool closed_ = false;
  Real volume_ = 0;
  Vec3 centroid_ = Vec3::Zero();
  Mat3 unit_inertia_ = Mat3::Zero();
};

template <class Visit>
void TriangleMesh::for_each_overlapping(const Aabb& box, Visit&& visit) const {
  if (nodes_.empty())
    return;
  std::array<std::int32_t, kMaxDepth + 1> stack;
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::int32_t index = stack[--top];
    const Node& node = nodes_[index];
    if (!node.bounds.overlaps(box))
      continue;
    if (node.count > 0) {
      for (std::int32_t i = node.first; i < node.first + node.count; ++i) {
        const int t = int(leaf_triangles_[i]);
        Aabb triangle_box;
        for (int k = 0; k < 3; ++k)
          triangle_box.grow(corner(t, k));
        if (triangle_box.overlaps(box))
          visit(t);
      }
      continue;
    }
    // Right child pushed first so the left one is visited first.
    stack[top++] = node.first;
    stack[top++] = index + 1;
  }
}

}  // namespace tumble
