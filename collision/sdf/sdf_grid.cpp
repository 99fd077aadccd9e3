// Grid SDFs: the build from a mesh and the interpolation (collision/sdf/sdf_grid.hpp).
#include "collision/sdf/sdf_grid.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "collision/sdf/closed_mesh.hpp"
#include "collision/sdf/mesh_distance_band.hpp"
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
                           int margin_cells, BuildReport* report, int refine) {
  const auto start_time = std::chrono::steady_clock::now();
  require_closed_mesh(vertices, triangles, "SDF grid");
  if (!(cell > 0) || !std::isfinite(cell))
    throw Error("SDF grid: the cell size must be positive and finite");
  if (refine < 1 || refine > GridRefinement::kMaxRefine)
    throw Error("SDF grid: refine must be from 1 to " + std::to_string(GridRefinement::kMaxRefine) +
                ", got " + std::to_string(refine));
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
  if (refine > 1)
    GridRefinement::check_size(n, refine);
  const auto index = [&](int i, int j, int k) {
    return std::size_t(i) +
           std::size_t(n[0]) * (std::size_t(j) + std::size_t(n[1]) * std::size_t(k));
  };
  std::vector<Real> distance(std::size_t(count), kInfinity);
  std::vector<std::uint8_t> fixed(std::size_t(count), 0);

  // The band: exact distances to the nearest triangle.
  const Real band = kBand * cell;
  sdf::for_each_node_near_triangles(vertices, triangles, origin, cell, n, band,
                                    [&](int x, int y, int z, Real d) {
                                      Real& slot = distance[index(x, y, z)];
                                      slot = std::min(slot, d);
                                    });
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

  // The sign: parity of the crossings along each row in x.
  const std::vector<sdf::RowCrossing> crossings =
      sdf::row_crossings(vertices, triangles, origin, cell, n);
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
  if (refine > 1)
    grid.refinement_ = std::make_shared<const GridRefinement>(
        GridRefinement::build(vertices, triangles, grid, refine));
  if (report != nullptr) {
    if (grid.refinement_) {
      report->refined_nodes = grid.refinement_->nodes();
      report->refined_band_nodes = grid.refinement_->band_nodes();
    }
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
  sdf::Sample fine;
  if (refinement_ && refinement_->sample(p, how, fine))
    return fine;
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
