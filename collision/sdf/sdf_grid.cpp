// Grid SDFs: the build from a mesh and the interpolation (collision/sdf/sdf_grid.hpp).
#include "collision/sdf/sdf_grid.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "collision/closest_point_on_triangle.hpp"
#include "collision/sdf/closed_mesh.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

// Godunov's upwind solution of |grad u| = 1 at a node from its smallest neighbour along each axis
// (Zhao 2005, eq. 2.4), for cells of size h.
Real eikonal_update(Real a, Real b, Real c, Real h) {
  if (a > b)
    std::swap(a, b);
  if (b > c)
    std::swap(b, c);
  if (a > b)
    std::swap(a, b);
  Real u = a + h;
  if (u <= b)
    return u;
  u = (a + b + std::sqrt(2 * h * h - (a - b) * (a - b))) / 2;
  if (u <= c)
    return u;
  const Real s = a + b + c;
  return (s + std::sqrt(s * s - 3 * (a * a + b * b + c * c - h * h))) / 3;
}

}  // namespace

SdfGrid::SdfGrid(const Vec3& origin, Real cell, std::array<int, 3> nodes, std::vector<Real> values)
    : origin_(origin), cell_(cell), nodes_(nodes), values_(std::move(values)) {
  if (!(cell > 0) || !std::isfinite(cell) || !origin.allFinite())
    throw Error("SDF grid: the cell size must be positive and finite, the origin finite");
  std::int64_t count = 1;
  for (int n : nodes) {
    if (n < 2)
      throw Error("SDF grid: at least 2 nodes along each axis");
    count *= n;
  }
  if (count > kMaxNodes || std::int64_t(values_.size()) != count)
    throw Error("SDF grid: " + std::to_string(values_.size()) + " values for " +
                std::to_string(count) + " nodes (at most " + std::to_string(kMaxNodes) + ")");
  for (Real v : values_)
    if (!std::isfinite(v))
      throw Error("SDF grid: a node's value is not finite");
}

SdfGrid SdfGrid::from_mesh(std::span<const Vec3> vertices,
                           std::span<const std::array<std::int32_t, 3>> triangles, Real cell,
                           int margin_cells, BuildReport* report) {
  const auto start_time = std::chrono::steady_clock::now();
  require_closed_mesh(vertices, triangles, "SDF grid");
  if (!(cell > 0) || !std::isfinite(cell))
    throw Error("SDF grid: the cell size must be positive and finite");
  Aabb bounds;
  for (const Vec3& v : vertices)
    bounds.grow(v);
  margin_cells = std::max(margin_cells, kBand + 1);
  const Vec3 origin = bounds.min - Vec3::Constant(margin_cells * cell);
  std::array<int, 3> n{};
  std::int64_t count = 1;
  for (int k = 0; k < 3; ++k) {
    const Real span = (bounds.max[k] - bounds.min[k]) / cell + 2 * margin_cells;
    if (!(span < Real(kMaxNodes)))
      throw Error("SDF grid: more than " + std::to_string(kMaxNodes) + " nodes; use larger cells");
    n[std::size_t(k)] = int(std::ceil(span)) + 1;
    count *= n[std::size_t(k)];
    if (count > kMaxNodes)
      throw Error("SDF grid: more than " + std::to_string(kMaxNodes) + " nodes; use larger cells");
  }
  const auto index = [&](int i, int j, int k) {
    return std::size_t(i) +
           std::size_t(n[0]) * (std::size_t(j) + std::size_t(n[1]) * std::size_t(k));
  };
  const auto node = [&](int i, int j, int k) {
    return Vec3(origin + cell * Vec3(Real(i), Real(j), Real(k)));
  };
  std::vector<Real> distance(std::size_t(count), kInfinity);
  std::vector<std::uint8_t> fixed(std::size_t(count), 0);

  // The band: exact distances to the nearest triangle.
  const Real band = kBand * cell;
  for (const auto& t : triangles) {
    const Vec3& a = vertices[std::size_t(t[0])];
    const Vec3& b = vertices[std::size_t(t[1])];
    const Vec3& c = vertices[std::size_t(t[2])];
    Aabb box;
    box.grow(a);
    box.grow(b);
    box.grow(c);
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::max(0, int(std::floor((box.min[k] - band - origin[k]) / cell)));
      hi[k] =
          std::min(n[std::size_t(k)] - 1, int(std::ceil((box.max[k] + band - origin[k]) / cell)));
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) {
          const Vec3 p = node(x, y, z);
          const Real d = (p - closest_point_on_triangle(p, a, b, c)).norm();
          Real& slot = distance[index(x, y, z)];
          slot = std::min(slot, d);
        }
  }
  std::int64_t band_nodes = 0;
  for (std::size_t i = 0; i < distance.size(); ++i)
    if (distance[i] <= band) {
      fixed[i] = 1;
      ++band_nodes;
    } else {
      distance[i] = kInfinity;
    }

  // Beyond the band: fast sweeping in the 8 orderings, twice.
  int sweeps = 0;
  for (int round = 0; round < 2; ++round)
    for (int order = 0; order < 8; ++order) {
      ++sweeps;
      const int sx = order & 1 ? -1 : 1, sy = order & 2 ? -1 : 1, sz = order & 4 ? -1 : 1;
      for (int zi = 0; zi < n[2]; ++zi) {
        const int z = sz > 0 ? zi : n[2] - 1 - zi;
        for (int yi = 0; yi < n[1]; ++yi) {
          const int y = sy > 0 ? yi : n[1] - 1 - yi;
          for (int xi = 0; xi < n[0]; ++xi) {
            const int x = sx > 0 ? xi : n[0] - 1 - xi;
            const std::size_t here = index(x, y, z);
            if (fixed[here])
              continue;
            const auto least = [&](int axis) {
              Real m = kInfinity;
              int c[3] = {x, y, z};
              for (int step = -1; step <= 1; step += 2) {
                c[axis] += step;
                if (c[axis] >= 0 && c[axis] < n[std::size_t(axis)])
                  m = std::min(m, distance[index(c[0], c[1], c[2])]);
                c[axis] -= step;
              }
              return m;
            };
            const Real a = least(0), b = least(1), c = least(2);
            if (std::min({a, b, c}) == kInfinity)
              continue;
            distance[here] = std::min(distance[here], eikonal_update(a, b, c, cell));
          }
        }
      }
    }

  // The sign: parity of the crossings along each row in x, the row's line moved off the nodes by
  // an irrational fraction of a cell so that it misses every edge and vertex.
  const Real dy = cell * Real(1.4142135623730951e-4), dz = cell * Real(1.7320508075688772e-4);
  struct Crossing {
    std::size_t row;
    Real x;
  };
  std::vector<Crossing> crossings;
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
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& p, const Crossing& q) {
    return p.row != q.row ? p.row < q.row : p.x < q.x;
  });
  for (std::size_t first = 0; first < crossings.size();) {
    std::size_t last = first;
    while (last < crossings.size() && crossings[last].row == crossings[first].row)
      ++last;
    if ((last - first) % 2 != 0)
      throw Error(
          "SDF grid: the mesh is not closed (a line crosses its surface an odd number of "
          "times); a grid SDF needs a closed, consistently oriented mesh");
    const int j = int(crossings[first].row % std::size_t(n[1]));
    const int k = int(crossings[first].row / std::size_t(n[1]));
    std::size_t next = first;
    bool inside = false;
    for (int i = 0; i < n[0]; ++i) {
      const Real x = origin.x() + cell * Real(i);
      while (next < last && crossings[next].x < x) {
        inside = !inside;
        ++next;
      }
      if (inside)
        distance[index(i, j, k)] = -distance[index(i, j, k)];
    }
    first = last;
  }
  for (Real v : distance)
    if (!std::isfinite(v))
      throw Error("SDF grid: a node was left without a distance");
  SdfGrid grid(origin, cell, n, std::move(distance));
  if (report != nullptr) {
    report->nodes = count;
    report->band_nodes = band_nodes;
    report->sweeps = sweeps;
    report->bytes = grid.bytes();
    report->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  }
  return grid;
}

Aabb SdfGrid::box() const {
  return {origin_,
          origin_ + cell_ * Vec3(Real(nodes_[0] - 1), Real(nodes_[1] - 1), Real(nodes_[2] - 1))};
}

sdf::Sample SdfGrid::sample(const Vec3& p, GridInterpolation how) const {
  const Aabb b = box();
  const Vec3 q = p.cwiseMax(b.min).cwiseMin(b.max);
  if (q == p)
    return inside_sample(p, how);
  // Outside the grid: the boundary's value plus the way to it, a lower bound of the distance.
  const sdf::Sample s = inside_sample(q, how);
  const Vec3 out = p - q;
  const Real d = out.norm();
  return {s.distance + d, Vec3(out / d)};
}

sdf::Sample SdfGrid::inside_sample(const Vec3& p, GridInterpolation how) const {
  int cell_index[3];
  Real t[3];
  for (int k = 0; k < 3; ++k) {
    const Real u = (p[k] - origin_[k]) / cell_;
    const int i = std::clamp(int(std::floor(u)), 0, nodes_[std::size_t(k)] - 2);
    cell_index[k] = i;
    t[k] = std::clamp(u - Real(i), Real(0), Real(1));
  }
  if (how == GridInterpolation::trilinear)
    return sdf::interpolate(cell_index, t, cell_, how,
                            [&](int i, int j, int k) { return value(i, j, k); });
  // Catmull-Rom reaches one node before and two after the cell: the grid's edge node repeats.
  return sdf::interpolate(cell_index, t, cell_, how, [&](int i, int j, int k) {
    return value(std::clamp(i, 0, nodes_[0] - 1), std::clamp(j, 0, nodes_[1] - 1),
                 std::clamp(k, 0, nodes_[2] - 1));
  });
}

}  // namespace tumble
