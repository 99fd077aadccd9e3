// Meshes the mesh and compound tests share: a flat grid, a closed box, a single triangle.
#pragma once

#include <cstdlib>
#include <memory>
#include <vector>

#include "collision/shapes/shape.hpp"
#include "collision/shapes/triangle_mesh.hpp"
#include "tests/property_scale.hpp"

namespace tumble::testing {

// n x n squares of side `cell` in the plane z = 0, centred on the origin, two triangles each,
// normals +z. Diagonals alternate direction so the grid has no preferred diagonal.
inline TriangleMesh grid_mesh(int n, Real cell) {
  std::vector<Vec3> vertices;
  std::vector<TriangleMesh::Triangle> triangles;
  const Real half = n * cell / 2;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      vertices.emplace_back(i * cell - half, j * cell - half, 0);
  const auto at = [n](int i, int j) { return std::int32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if ((i + j) % 2 == 0) {
        triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      } else {
        triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
        triangles.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    }
  }
  return TriangleMesh::build(std::move(vertices), std::move(triangles));
}

// The closed surface of the box [-h, h] under `pose`, outward normals.
inline TriangleMesh box_mesh(const Vec3& h, const Transform& pose = {}) {
  std::vector<Vec3> vertices;
  for (int v = 0; v < 8; ++v)
    vertices.push_back(pose.apply(
        Vec3((v & 1) ? h.x() : -h.x(), (v & 2) ? h.y() : -h.y(), (v & 4) ? h.z() : -h.z())));
  // Each face as a quad (counter-clockwise seen from outside), split in two.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<TriangleMesh::Triangle> triangles;
  for (const auto& q : quads) {
    triangles.push_back({q[0], q[1], q[2]});
    triangles.push_back({q[0], q[2], q[3]});
  }
  return TriangleMesh::build(std::move(vertices), std::move(triangles));
}

inline Shape mesh_shape(TriangleMesh mesh) {
  return Shape::triangle_mesh(std::make_shared<const TriangleMesh>(std::move(mesh)));
}

}  // namespace tumble::testing
