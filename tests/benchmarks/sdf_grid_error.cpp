// The error of grid SDFs against the analytic field they stand for, by cell size (docs/sdf.md,
// "Grids"; plotted by scripts/sdf_grid_figure.py). A torus (ring 0.4 m, tube 0.15 m) is gridded
// four ways: from its exact distance at the nodes (the interpolation's own error), from a closed
// triangle mesh of it (192 x 96 quads: the mesh's chords add up to 0.08 mm), from the same mesh
// with cells four times as large and the band near the surface refined to the cell
// (collision/sdf/grid_refinement.hpp), and from the same mesh as an OpenVDB narrow-band level set
// (when the build has OpenVDB; its band covers the 5 cm), then sampled trilinearly and tricubically
// at 20,000 fixed random points within 5 cm of the surface. Prints CSV: source, cell [m], nodes (a
// level set's active voxels), build seconds, bytes, max and mean error of each interpolation [m].
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "collision/sdf/sdf_grid.hpp"
#include "collision/sdf/sdf_primitives.hpp"
#include "collision/sdf/vdb_level_set.hpp"
#include "tests/collision/closed_meshes.hpp"

using namespace tumble;

namespace {

constexpr Real kMajor = 0.4, kMinor = 0.15;

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
  test_meshes::torus_mesh(kMajor, kMinor, 192, 96, vertices, triangles);
  std::printf(
      "source,cell,nodes,build_seconds,bytes,trilinear_max,trilinear_mean,tricubic_max,"
      "tricubic_mean\n");
  for (const char* source : {"analytic", "mesh", "mesh_refined", "openvdb"}) {
    if (std::string(source) == "openvdb" && !VdbLevelSet::available())
      continue;
    for (Real cell : {0.08, 0.04, 0.02, 0.01, 0.005}) {
      const auto start = std::chrono::steady_clock::now();
      SdfGrid::BuildReport report;
      std::optional<SdfGrid> grid;
      std::shared_ptr<const VdbLevelSet> level_set;
      // Each covers the 5 cm measured: the grid's margin and the level set's band.
      const int cover = int(std::ceil(0.05 / cell)) + 2;
      if (std::string(source) == "analytic")
        grid = sampled_grid(cell);
      else if (std::string(source) == "mesh")
        grid = SdfGrid::from_mesh(vertices, triangles, cell, cover, &report);
      else if (std::string(source) == "mesh_refined")  // cells 4 times larger, the band `cell`
        grid = SdfGrid::from_mesh(vertices, triangles, 4 * cell,
                                  int(std::ceil(0.05 / (4 * cell))) + 2, &report, 4);
      else
        level_set = VdbLevelSet::from_mesh(vertices, triangles, cell, Real(std::min(cover, 64)));
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const auto sample = [&](const Vec3& p, GridInterpolation how) {
        return grid ? grid->sample(p, how).distance : level_set->sample(p, how).distance;
      };
      Real max[2] = {0, 0}, sum[2] = {0, 0};
      for (const Vec3& p : points) {
        const Real exact = sdf::torus(p, kMajor, kMinor).distance;
        const Real e0 = std::abs(sample(p, GridInterpolation::trilinear) - exact);
        const Real e1 = std::abs(sample(p, GridInterpolation::tricubic) - exact);
        max[0] = std::max(max[0], e0);
        max[1] = std::max(max[1], e1);
        sum[0] += e0;
        sum[1] += e1;
      }
      const std::int64_t nodes =
          grid ? std::int64_t(grid->nodes()[0]) * grid->nodes()[1] * grid->nodes()[2] +
                     (grid->refinement() ? grid->refinement()->nodes() : 0)
               : level_set->active_voxels();
      const std::size_t bytes = grid ? grid->bytes() : level_set->bytes();
      std::printf("%s,%g,%lld,%.4f,%zu,%.3e,%.3e,%.3e,%.3e\n", source, cell, (long long)nodes,
                  seconds, bytes, max[0], sum[0] / points.size(), max[1], sum[1] / points.size());
      std::fflush(stdout);
    }
  }
}
