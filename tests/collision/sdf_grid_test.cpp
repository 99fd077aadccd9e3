// Grid SDFs (collision/sdf/sdf_grid.hpp): the build from a closed mesh against a brute-force
// distance to every triangle, the interpolants' gradients against central differences, the
// interpolation error falling with the cell size, and bad meshes refused (fixed seeds).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "collision/sdf/sdf_grid.hpp"
#include "collision/sdf/sdf_primitives.hpp"
#include "tests/collision/closed_meshes.hpp"
#include "tests/collision/sampled_grid.hpp"
#include "tests/property_scale.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

using test_meshes::brute_force_distance;
using test_meshes::Triangles;
using test_meshes::uv_sphere;

TEST(SdfGrid, MeshBuildIsExactInTheBandAndSignedEverywhere) {
  std::vector<Vec3> v;
  Triangles t;
  uv_sphere(0.5, 48, 24, v, t);
  SdfGrid::BuildReport report;
  const Real cell = 0.04;
  const SdfGrid grid = SdfGrid::from_mesh(v, t, cell, SdfGrid::kBand + 1, &report);
  EXPECT_EQ(report.nodes, std::int64_t(grid.nodes()[0]) * grid.nodes()[1] * grid.nodes()[2]);
  EXPECT_GT(report.band_nodes, 0);
  EXPECT_LT(report.band_nodes, report.nodes);
  // The sphere's chords lie inside it by at most r (1 - cos(pi / 24)) = 4.3 mm: nodes farther
  // than that from the sphere have the sphere's sign.
  const Real chord = 0.5 * (1 - std::cos(std::numbers::pi_v<Real> / 24));
  int band = 0, far = 0;
  Real worst_far = 0;
  // Every node, or every fourth row under the sanitizers (TUMBLE_PROPERTY_SCALE < 1): the brute
  // force over 2,304 triangles per node is most of the test's time.
  const int stride = property_scale() < 1 ? 4 : 1;
  for (int k = 0; k < grid.nodes()[2]; ++k)
    for (int j = 0; j < grid.nodes()[1]; j += stride)
      for (int i = 0; i < grid.nodes()[0]; ++i) {
        const Vec3 p = grid.origin() + cell * Vec3(Real(i), Real(j), Real(k));
        const Real value = grid.value(i, j, k);
        const Real exact = brute_force_distance(p, v, t);
        const Real sphere = p.norm() - 0.5;
        if (std::abs(sphere) > chord + 1e-9) {
          ASSERT_EQ(value < 0, sphere < 0) << p.transpose();
        }
        if (exact <= SdfGrid::kBand * cell) {
          ++band;
          ASSERT_NEAR(std::abs(value), exact, 1e-12) << p.transpose();
        } else {
          ++far;
          // Fast sweeping: first-order upwind, whose error grows with the way from the band
          // (measured: 0.83 cell at worst, at the grid's far corners and the sphere's centre).
          // Contacts read only the band.
          worst_far = std::max(worst_far, std::abs(std::abs(value) - exact));
        }
      }
  EXPECT_GT(band, 1000 / stride);
  EXPECT_GT(far, 1000 / stride);
  EXPECT_LT(worst_far, cell) << "largest error beyond the band " << worst_far;
}

TEST(SdfGrid, OpenOrBrokenMeshesAreRefused) {
  std::vector<Vec3> v;
  Triangles t;
  uv_sphere(0.5, 16, 8, v, t);
  Triangles open(t.begin() + 1, t.end());  // one triangle missing
  EXPECT_THROW(SdfGrid::from_mesh(v, open, 0.05), Error);
  EXPECT_THROW(SdfGrid::from_mesh(v, t, 0), Error);
  EXPECT_THROW(SdfGrid::from_mesh(v, t, 1e-6), Error);  // too many nodes
  Triangles bad = t;
  bad[0][1] = 9999;
  EXPECT_THROW(SdfGrid::from_mesh(v, bad, 0.05), Error);
  EXPECT_THROW(SdfGrid::from_mesh({}, {}, 0.05), Error);
}

// A grid of a torus's exact distance at the nodes, `cells` cells along its width.
SdfGrid torus_grid(int cells) {
  const Real major = 0.4, minor = 0.15;
  const Real half = major + minor + 0.1;
  const Real cell = 2 * half / cells;
  std::array<int, 3> n{cells + 1, cells + 1, int(std::ceil(2 * (minor + 0.1) / cell)) + 1};
  const Vec3 origin(-half, -half, -(n[2] - 1) * cell / 2);
  return test::sampled_grid(origin, cell, n,
                            [&](const Vec3& p) { return sdf::torus(p, major, minor).distance; });
}

TEST(SdfGrid, GradientsAreThoseOfTheInterpolant) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<Real> u(-0.6, 0.6);
  const SdfGrid grid = torus_grid(24);
  const Real h = 1e-6;
  for (GridInterpolation how : {GridInterpolation::trilinear, GridInterpolation::tricubic}) {
    int checked = 0;
    for (int i = 0; i < 5000; ++i) {
      const Vec3 p(u(rng), u(rng), u(rng) / 3);
      const sdf::Sample s = grid.sample(p, how);
      Vec3 fd;
      bool near_face = false;
      for (int k = 0; k < 3; ++k) {
        Vec3 e = Vec3::Zero();
        e[k] = h;
        fd[k] = (grid.sample(p + e, how).distance - grid.sample(p - e, how).distance) / (2 * h);
        // The trilinear interpolant is not differentiable across cell faces.
        const Real f = (p[k] - grid.origin()[k]) / grid.cell();
        near_face = near_face || std::abs(f - std::round(f)) < 1e-4;
      }
      if (near_face && how == GridInterpolation::trilinear)
        continue;
      ++checked;
      ASSERT_LT((s.gradient - fd).norm(), 1e-6) << p.transpose();
    }
    EXPECT_GT(checked, 4900);
  }
}

TEST(SdfGrid, InterpolationErrorFallsWithTheCellSize) {
  // Near the surface (within 5 cm), against the exact torus: trilinear falls as h^2, the
  // Catmull-Rom tricubic faster until the torus's own curvature dominates; both must at least
  // halve when the cell halves, and tricubic must beat trilinear.
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<Real> u(-1, 1);
  std::vector<Vec3> points;
  while (points.size() < 4000) {
    const Vec3 p(0.6 * u(rng), 0.6 * u(rng), 0.25 * u(rng));
    if (std::abs(sdf::torus(p, 0.4, 0.15).distance) < 0.05)
      points.push_back(p);
  }
  Real previous[2] = {1e9, 1e9};
  for (int cells : {12, 24, 48}) {
    const SdfGrid grid = torus_grid(cells);
    Real worst[2] = {0, 0};
    for (const Vec3& p : points) {
      const Real exact = sdf::torus(p, 0.4, 0.15).distance;
      worst[0] = std::max(worst[0],
                          std::abs(grid.sample(p, GridInterpolation::trilinear).distance - exact));
      worst[1] = std::max(worst[1],
                          std::abs(grid.sample(p, GridInterpolation::tricubic).distance - exact));
    }
    EXPECT_LT(worst[1], worst[0]) << cells;
    EXPECT_LT(worst[0], previous[0] / 2) << cells;
    EXPECT_LT(worst[1], previous[1] / 2) << cells;
    previous[0] = worst[0];
    previous[1] = worst[1];
  }
}

}  // namespace
}  // namespace tumble
