// Closed triangle meshes for the tests of SDFs built from meshes, triangles counter-clockwise
// seen from outside, and the brute-force distance to them.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "collision/closest_point_on_triangle.hpp"
#include "collision/math.hpp"

namespace tumble::test_meshes {

using Triangles = std::vector<std::array<std::int32_t, 3>>;

// A closed UV sphere of `radius`.
inline void uv_sphere(Real radius, int around, int rings, std::vector<Vec3>& v, Triangles& t) {
  const Real pi = std::numbers::pi_v<Real>;
  v.push_back(Vec3(0, 0, -radius));
  for (int i = 1; i < rings; ++i) {
    const Real theta = pi * Real(i) / Real(rings);
    for (int k = 0; k < around; ++k) {
      const Real phi = 2 * pi * Real(k) / Real(around);
      v.push_back(radius * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                -std::cos(theta)));
    }
  }
  v.push_back(Vec3(0, 0, radius));
  const auto at = [&](int ring, int k) { return 1 + (ring - 1) * around + (k % around); };
  const int top = int(v.size()) - 1;
  for (int k = 0; k < around; ++k) {
    t.push_back({0, at(1, k + 1), at(1, k)});
    t.push_back({top, at(rings - 1, k), at(rings - 1, k + 1)});
  }
  for (int i = 1; i < rings - 1; ++i)
    for (int k = 0; k < around; ++k) {
      t.push_back({at(i, k), at(i, k + 1), at(i + 1, k + 1)});
      t.push_back({at(i, k), at(i + 1, k + 1), at(i + 1, k)});
    }
}

// A closed box of half extents `h`, centred on the origin.
inline void box_mesh(const Vec3& h, std::vector<Vec3>& v, Triangles& t) {
  for (int i = 0; i < 8; ++i)
    v.push_back(Vec3(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z()));
  // Each face's corners counter-clockwise seen from outside.
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    t.push_back({f[0], f[1], f[2]});
    t.push_back({f[0], f[2], f[3]});
  }
}

// A closed torus of ring `major` and tube `minor`, `around` quads along the ring by `tube` around
// the tube.
inline void torus_mesh(Real major, Real minor, int around, int tube, std::vector<Vec3>& v,
                       Triangles& t) {
  const Real pi = std::numbers::pi_v<Real>;
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < tube; ++j) {
      const Real u = 2 * pi * i / around, w = 2 * pi * j / tube;
      v.push_back(Vec3((major + minor * std::cos(w)) * std::cos(u),
                       (major + minor * std::cos(w)) * std::sin(u), minor * std::sin(w)));
    }
  const auto at = [&](int i, int j) { return std::int32_t((i % around) * tube + (j % tube)); };
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < tube; ++j) {
      t.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      t.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
}

inline Real brute_force_distance(const Vec3& p, const std::vector<Vec3>& v, const Triangles& t) {
  Real best = std::numeric_limits<Real>::infinity();
  for (const auto& tri : t)
    best = std::min(
        best, (p - closest_point_on_triangle(p, v[std::size_t(tri[0])], v[std::size_t(tri[1])],
                                             v[std::size_t(tri[2])]))
                  .norm());
  return best;
}

}  // namespace tumble::test_meshes
