// The error of grid SDFs against the analytic field they stand for, by cell size (docs/sdf.md,
// "Grids"; plotted by scripts/sdf_grid_figure.py). A torus (ring 0.4 m, tube 0.15 m) is gridded
// two ways: from its exact distance at the nodes (the interpolation's own error) and from a closed
// triangle mesh of it (192 x 96 quads: the mesh's chords add up to 0.08 mm), then sampled
// trilinearly and tricubically at 20,000 fixed random points within 5 cm of the surface.
// Prints CSV: source, cell [m], nodes, build seconds, bytes, max and mean error of each
// interpolation [m].
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "collision/sdf/sdf_grid.hpp"
#include "collision/sdf/sdf_primitives.hpp"

using namespace tumble;

namespace {

constexpr Real kMajor = 0.4, kMinor = 0.15;

void torus_mesh(int around, int tube, std::vector<Vec3>& v,
                std::vector<std::array<std::int32_t, 3>>& t) {
  const Real pi = std::numbers::pi_v<Real>;
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < tube; ++j) {
      const Real u = 2 * pi * i / around, w = 2 * pi * j / tube;
      v.push_back(Vec3((kMajor + kMinor * std::cos(w)) * std::cos(u),
                       (kMajor + kMinor * std::cos(w)) * std::sin(u), kMinor * std::sin(w)));
    }
  const auto at = [&](int i, int j) { return std::int32_t((i % around) * tube + (j % tube)); };
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < tube; ++j) {
      t.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      t.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
}

SdfGrid sampled_grid(Real cell) {
  // The grid covers every sample point (within 5 cm of the surface) and two cells more.
  const Real half = kMajor + kMinor + 0.05 + 2 * cell;
  const int n = int(std::ceil(2 * half / cell)) + 1;
  const int nz = int(std::ceil(2 * (kMinor + 0.05 + 2 * cell) / cell)) + 1;
  const Vec3 origin(-half, -half, -(nz - 1) * cell / 2);
  std::vector<Real> values;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        values.push_back(sdf::torus(origin + cell * Vec3(i, j, k), kMajor, kMinor).distance);
  return SdfGrid(origin, cell, {n, n, nz}, std::move(values));
}

}  // namespace

int main() {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<Real> u(-1, 1);
  std::vector<Vec3> points;
  while (points.size() < 20000) {
    const Vec3 p(0.6 * u(rng), 0.6 * u(rng), 0.22 * u(rng));
    if (std::abs(sdf::torus(p, kMajor, kMinor).distance) < 0.05)
      points.push_back(p);
  }
  std::vector<Vec3> vertices;
  std::vector<std::array<std::int32_t, 3>> triangles;
  torus_mesh(192, 96, vertices, triangles);
  std::printf(
      "source,cell,nodes,build_seconds,bytes,trilinear_max,trilinear_mean,tricubic_max,"
      "tricubic_mean\n");
  for (const char* source : {"analytic", "mesh"}) {
    for (Real cell : {0.08, 0.04, 0.02, 0.01, 0.005}) {
      const auto start = std::chrono::steady_clock::now();
      SdfGrid::BuildReport report;
      const SdfGrid grid = std::string(source) == "analytic"
                               ? sampled_grid(cell)
                               : SdfGrid::from_mesh(vertices, triangles, cell,
                                                    int(std::ceil(0.05 / cell)) + 2, &report);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      Real max[2] = {0, 0}, sum[2] = {0, 0};
      for (const Vec3& p : points) {
        const Real exact = sdf::torus(p, kMajor, kMinor).distance;
        const Real e0 = std::abs(grid.sample(p, GridInterpolation::trilinear).distance - exact);
        const Real e1 = std::abs(grid.sample(p, GridInterpolation::tricubic).distance - exact);
        max[0] = std::max(max[0], e0);
        max[1] = std::max(max[1], e1);
        sum[0] += e0;
        sum[1] += e1;
      }
      const std::int64_t nodes = std::int64_t(grid.nodes()[0]) * grid.nodes()[1] * grid.nodes()[2];
      std::printf("%s,%g,%lld,%.4f,%zu,%.3e,%.3e,%.3e,%.3e\n", source, cell, (long long)nodes,
                  seconds, grid.bytes(), max[0], sum[0] / points.size(), max[1],
                  sum[1] / points.size());
      std::fflush(stdout);
    }
  }
}
