// Grids refined near the surface (collision/sdf/grid_refinement.hpp): where a point's stencil lies
// in the refined band, the grid samples what a dense grid of the fine cells samples there (the
// same exact distances at the same nodes); the refined grid is as close to the analytic ball as
// that dense grid near the surface, in a fraction of its memory; bad factors are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "collision/sdf/sdf_grid.hpp"
#include "tests/collision/closed_meshes.hpp"
#include "tests/property_scale.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

using test_meshes::brute_force_distance;
using test_meshes::Triangles;
using test_meshes::uv_sphere;

// A ball of 0.5 m as 96 x 48 facets; a grid of 8 cm cells refined 4 times (2 cm near the
// surface) and the dense grid of 2 cm cells over the same box.
struct RefinedBall {
  std::vector<Vec3> vertices;
  Triangles triangles;
  SdfGrid::BuildReport refined_report, dense_report;
  SdfGrid refined, dense;
  RefinedBall() : refined(make(0.08, 4, refined_report)), dense(make(0.02, 1, dense_report)) {}
  SdfGrid make(Real cell, int refine, SdfGrid::BuildReport& report) {
    if (vertices.empty())
      uv_sphere(0.5, 96, 48, vertices, triangles);
    // The same box: the dense grid's margin is four times as many of its cells.
    return SdfGrid::from_mesh(vertices, triangles, cell,
                              (SdfGrid::kBand + 1) * (refine == 1 ? 4 : 1), &report, refine);
  }
};

TEST(GridRefinement, TheBandSamplesAsTheDenseGridOfItsCells) {
  const RefinedBall ball;
  ASSERT_NE(ball.refined.refinement(), nullptr);
  EXPECT_EQ(ball.refined.refinement()->cell(), ball.dense.cell());
  EXPECT_EQ(ball.refined.origin(), ball.dense.origin());
  std::mt19937_64 rng(71);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Real h = ball.dense.cell();
  int compared = 0;
  for (int i = 0; i < scaled(20000); ++i) {
    Vec3 direction(u(rng), u(rng), u(rng));
    if (direction.norm() < 1e-3)
      continue;
    // Within 1.2 fine cells of the surface, a trilinear stencil's 8 nodes are within the band of
    // 3 fine cells (1.2 h + sqrt(3) h), where both grids hold the exact distance to the facets.
    const Vec3 p = direction.normalized() * (0.5 + 1.2 * h * u(rng));
    const sdf::Sample a = ball.refined.sample(p, GridInterpolation::trilinear);
    const sdf::Sample b = ball.dense.sample(p, GridInterpolation::trilinear);
    ASSERT_NEAR(a.distance, b.distance, 1e-12) << p.transpose();
    ASSERT_NEAR((a.gradient - b.gradient).norm(), 0, 1e-9) << p.transpose();
    ++compared;
  }
  EXPECT_GT(compared, scaled(20000) * 9 / 10);
}

// Against the exact distance to the facets (brute force over the 9,216 triangles) at points up to
// 3 cm outside them (inside, every edge of the facets starts a ridge of the distance). The
// facets' own field bends sharply near their edges (a cylinder's curvature 1 / d at distance d),
// which every cell size interpolates about as badly: the dense grid of 2 cm is only 1.5 times as
// close as the grid of 8 cm here, and the mean error is compared, not a resolution order.
TEST(GridRefinement, NearTheSurfaceItIsAsCloseAsTheDenseGridInAFractionOfItsMemory) {
  const RefinedBall ball;
  const SdfGrid coarse = SdfGrid::from_mesh(ball.vertices, ball.triangles, 0.08);
  std::mt19937_64 rng(72);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Real sag = 0.5 * (1 - std::cos(std::numbers::pi_v<Real> / 48));
  Real refined_sum = 0, dense_sum = 0, coarse_sum = 0;
  int compared = 0;
  for (int i = 0; i < scaled(2000); ++i) {
    Vec3 direction(u(rng), u(rng), u(rng));
    if (direction.norm() < 1e-3)
      continue;
    const Vec3 p = direction.normalized() * (0.5 + sag + 0.03 * std::abs(u(rng)));
    const Real exact = brute_force_distance(p, ball.vertices, ball.triangles);
    const auto error = [&](const SdfGrid& g) {
      return std::abs(g.sample(p, GridInterpolation::tricubic).distance - exact);
    };
    refined_sum += error(ball.refined);
    dense_sum += error(ball.dense);
    coarse_sum += error(coarse);
    ++compared;
  }
  const Real refined = refined_sum / compared, dense = dense_sum / compared,
             coarse_mean = coarse_sum / compared;
  std::printf(
      "%d points up to 3 cm outside the surface, tricubic, mean error: refined %.3g m, dense "
      "%.3g m, coarse %.3g m; bytes: refined %zu, dense %zu, coarse %zu; build %.3f s refined, "
      "%.3f s dense\n",
      compared, refined, dense, coarse_mean, ball.refined.bytes(), ball.dense.bytes(),
      coarse.bytes(), ball.refined_report.seconds, ball.dense_report.seconds);
  EXPECT_GT(compared, scaled(2000) * 9 / 10);
  // Near the surface the refined grid is the dense one (its stencil's few coarse values beyond
  // the band move the mean by less than a hundredth), and better than its coarse grid alone.
  EXPECT_LT(std::abs(refined - dense), dense / 100);
  EXPECT_LT(refined, coarse_mean);
  EXPECT_LT(ball.refined.bytes(), ball.dense.bytes() / 2);
  EXPECT_GT(ball.refined_report.refined_band_nodes, 0);
  EXPECT_LE(ball.refined_report.refined_band_nodes, ball.refined_report.refined_nodes);
}

TEST(GridRefinement, FactorsOutsideTheRangeAreRefused) {
  std::vector<Vec3> v;
  Triangles t;
  uv_sphere(0.5, 16, 8, v, t);
  EXPECT_THROW(SdfGrid::from_mesh(v, t, 0.1, SdfGrid::kBand + 1, nullptr, 0), Error);
  EXPECT_THROW(SdfGrid::from_mesh(v, t, 0.1, SdfGrid::kBand + 1, nullptr, 17), Error);
  EXPECT_EQ(SdfGrid::from_mesh(v, t, 0.1, SdfGrid::kBand + 1, nullptr, 1).refinement(), nullptr);
  // A table of blocks past its limit is refused before anything is built: 5 mm cells (a coarse
  // grid of 9 M nodes, well within its own limit) refined 16 times over the ball would be
  // (208 x 16 / 8)^3 = 72 M blocks, where 10 cm cells refined 8 times are a few MB.
  const SdfGrid modest = SdfGrid::from_mesh(v, t, 0.1, SdfGrid::kBand + 1, nullptr, 8);
  ASSERT_NE(modest.refinement(), nullptr);
  EXPECT_LT(modest.bytes(), std::size_t(8) << 20);
  try {
    (void)SdfGrid::from_mesh(v, t, 0.005, SdfGrid::kBand + 1, nullptr, 16);
    ADD_FAILURE() << "a table of 72 M blocks was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("table of blocks"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tumble
