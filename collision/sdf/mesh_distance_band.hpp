// The two passes a grid's build from a closed mesh makes over the mesh's triangles, shared by the
// dense grid (collision/sdf/sdf_grid.cpp) and its refined band (grid_refinement.cpp): the exact
// distance from nodes near each triangle (Ericson, Real-Time Collision Detection, 5.1.5), and the
// crossings of rows of nodes along x with the surface, whose parity gives the sign (a node with
// an odd count of crossings before it along its row is inside).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "collision/closest_point_on_triangle.hpp"
#include "collision/math.hpp"

namespace tumble::sdf {

// The nodes (origin + cell (i, j, k), clamped to 0 <= i < n[0] and so on) of the box from `low`
// to `high` grown by `reach`: lo[k] to hi[k] along each axis.
inline void node_range_near(const Vec3& low, const Vec3& high, Real reach, const Vec3& origin,
                            Real cell, const std::array<int, 3>& n, int lo[3], int hi[3]) {
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::max(0, int(std::floor((low[k] - reach - origin[k]) / cell)));
    hi[k] = std::min(n[std::size_t(k)] - 1, int(std::ceil((high[k] + reach - origin[k]) / cell)));
  }
}

// Calls visit(i, j, k, distance) for every node (origin + cell (i, j, k), 0 <= i < n[0] and so
// on) in each triangle's box grown by `reach`, with the node's distance to that triangle: a node
// is visited once per triangle near it, and keeps the least.
template <class Visit>
void for_each_node_near_triangles(std::span<const Vec3> vertices,
                                  std::span<const std::array<std::int32_t, 3>> triangles,
                                  const Vec3& origin, Real cell, const std::array<int, 3>& n,
                                  Real reach, Visit&& visit) {
  for (const auto& t : triangles) {
    const Vec3& a = vertices[std::size_t(t[0])];
    const Vec3& b = vertices[std::size_t(t[1])];
    const Vec3& c = vertices[std::size_t(t[2])];
    int lo[3], hi[3];
    node_range_near(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c), reach, origin, cell, n,
                    lo, hi);
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) {
          const Vec3 p = origin + cell * Vec3(Real(x), Real(y), Real(z));
          visit(x, y, z, (p - closest_point_on_triangle(p, a, b, c)).norm());
        }
  }
}

struct RowCrossing {
  std::size_t row;  // j + n[1] k
  Real x;
};

// Where each row of nodes along x (j, k) crosses the surface, sorted by row and then x. The row's
// line is moved off the nodes by an irrational fraction of a cell so that it misses every edge
// and vertex.
inline std::vector<RowCrossing> row_crossings(
    std::span<const Vec3> vertices, std::span<const std::array<std::int32_t, 3>> triangles,
    const Vec3& origin, Real cell, const std::array<int, 3>& n) {
  const Real dy = cell * Real(1.4142135623730951e-4), dz = cell * Real(1.7320508075688772e-4);
  std::vector<RowCrossing> crossings;
  for (const auto& t : triangles) {
    const Vec3& a = vertices[std::size_t(t[0])];
    const Vec3& b = vertices[std::size_t(t[1])];
    const Vec3& c = vertices[std::size_t(t[2])];
    const Real area = (b.y() - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (b.z() - a.z());
    if (area == 0)
      continue;  // parallel to x: no row crosses it
    const int j0 =
        std::max(0, int(std::floor((std::min({a.y(), b.y(), c.y()}) - origin.y() - dy) / cell)));
    const int j1 = std::min(
        n[1] - 1, int(std::ceil((std::max({a.y(), b.y(), c.y()}) - origin.y() - dy) / cell)));
    const int k0 =
        std::max(0, int(std::floor((std::min({a.z(), b.z(), c.z()}) - origin.z() - dz) / cell)));
    const int k1 = std::min(
        n[2] - 1, int(std::ceil((std::max({a.z(), b.z(), c.z()}) - origin.z() - dz) / cell)));
    for (int k = k0; k <= k1; ++k)
      for (int j = j0; j <= j1; ++j) {
        const Real y = origin.y() + cell * Real(j) + dy, z = origin.z() + cell * Real(k) + dz;
        // Barycentric coordinates of (y, z) in the triangle's projection.
        const Real u = ((b.y() - y) * (c.z() - z) - (c.y() - y) * (b.z() - z)) / area;
        const Real v = ((c.y() - y) * (a.z() - z) - (a.y() - y) * (c.z() - z)) / area;
        const Real w = 1 - u - v;
        if (u < 0 || v < 0 || w < 0)
          continue;
        crossings.push_back({std::size_t(j) + std::size_t(n[1]) * std::size_t(k),
                             u * a.x() + v * b.x() + w * c.x()});
      }
  }
  std::sort(crossings.begin(), crossings.end(), [](const RowCrossing& p, const RowCrossing& q) {
    return p.row != q.row ? p.row < q.row : p.x < q.x;
  });
  return crossings;
}

}  // namespace tumble::sdf
