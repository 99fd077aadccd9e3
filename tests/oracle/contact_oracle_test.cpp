// Contact scenes against Bullet, each against its analytic answer as well: a bounce, a slide,
// a stack; and the chaotic demo and a benchmark pyramid by statistics. Tolerances are the
// measured differences (docs/oracle.md) with a margin of about a half, so a change in either
// engine's contact model that moves the answer is noticed.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "apps/compare_command.hpp"
#include "oracle_fixture.hpp"

namespace tumble {
namespace {

std::vector<Real> apexes(const std::vector<Real>& z) {
  std::vector<Real> a;
  for (std::size_t i = 1; i + 1 < z.size(); ++i) {
    if (z[i] > z[i - 1] && z[i] >= z[i + 1] && z[i] > 0.15)
      a.push_back(z[i]);
  }
  return a;
}

// Ball of radius 0.1 from 2.1 m, e = 0.8: apex k above the resting height is e^(2k) * 2 m.
TEST(ContactOracle, BounceApexesAgreeWithEachOtherAndTheory) {
  auto scene = test::oracle_scene("bounce.yaml");
  std::vector<Real> zt, zb;
  Real max_error = 0;
  test::lockstep(scene, app::scene_steps(*scene),
                 [&](std::int64_t, const Simulation& w, const app::BulletWorld& b) {
                   zt.push_back(w.state().bodies[0].position.z());
                   zb.push_back(b.body(0).position.z());
                   max_error = std::max(max_error,
                                        (w.state().bodies[0].position - b.body(0).position).norm());
                 });
  const std::vector<Real> at = apexes(zt);
  const std::vector<Real> ab = apexes(zb);
  ASSERT_GE(at.size(), 4u);
  ASSERT_GE(ab.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    const Real theory = 0.1 + std::pow(0.8, 2 * (k + 1)) * 2.0;
    EXPECT_NEAR(at[k], theory, 0.01 * theory) << "tumble apex " << k;
    EXPECT_NEAR(ab[k], theory, 0.01 * theory) << "Bullet apex " << k;
    EXPECT_NEAR(at[k], ab[k], 0.01 * theory) << "apex " << k;
  }
  // Measured 0.0135 m: impacts one substep apart shift the later arcs.
  EXPECT_LE(max_error, 0.02);
}

// Box on a 30 degree incline, friction 0.3: a = g (sin 30 - 0.3 cos 30) down the slope.
TEST(ContactOracle, SlideAgreesWithEachOtherAndTheory) {
  auto scene = test::oracle_scene("incline_slide.yaml");
  const int box = scene->find_body("box");
  const Vec3 down_slope = Vec3(0, -std::cos(M_PI / 6), -std::sin(M_PI / 6));
  const Real a = 9.81 * (0.5 - 0.3 * std::cos(M_PI / 6));
  Real max_error = 0, st = 0, sb = 0;
  test::lockstep(scene, app::scene_steps(*scene),
                 [&](std::int64_t, const Simulation& w, const app::BulletWorld& b) {
                   const Vec3 xt = w.state().bodies[box].position;
                   const Vec3 xb = b.body(box).position;
                   max_error = std::max(max_error, (xt - xb).norm());
                   st = (xt - scene->bodies[box].position).dot(down_slope);
                   sb = (xb - scene->bodies[box].position).dot(down_slope);
                 });
  const Real theory = 0.5 * a * 1.0 * 1.0;
  EXPECT_NEAR(st, theory, 0.01 * theory);
  EXPECT_NEAR(sb, theory, 0.01 * theory);
  // Measured 0.0050 m after 1.18 m of sliding.
  EXPECT_LE(max_error, 0.008);
}

// Ten unit cubes stacked: both stacks stand, and agree to the sag of their contact models.
TEST(ContactOracle, StackStandsInBothAndAgrees) {
  auto scene = test::oracle_scene("stack10.yaml");
  const app::CompareResult r =
      app::compare_scene(scene, app::scene_steps(*scene), app::CompareMode::paths, 20);
  // Measured 0.0093 m (tumble's soft contacts sag a few mm more than Bullet's).
  EXPECT_LE(r.max_position_error, 0.015);
  EXPECT_LE(r.max_orientation_error, 0.005);
  EXPECT_EQ(r.samples.back().tumble_at_rest, 10);
  EXPECT_EQ(r.samples.back().bullet_at_rest, 10);
}

// The demo is chaotic (spinning shapes hit each other): statistics only.
TEST(ContactOracle, DemoAgreesStatistically) {
  auto scene = test::oracle_scene("demo.yaml");
  const app::CompareResult r =
      app::compare_scene(scene, app::scene_steps(*scene), app::CompareMode::automatic, 50);
  EXPECT_TRUE(r.chaotic);
  // Measured: centre of mass within 0.19 m; 7 of 8 bodies at rest in both at the end; top of
  // the pile within 0.43 m and final energy within 17% (a crate or plank that ends on a tray
  // wall in one engine and on the floor in the other is a coin toss in a chaotic scene).
  EXPECT_LE(r.max_com_error, 0.3);
  const auto& last = r.samples.back();
  EXPECT_NEAR(last.tumble_at_rest, last.bullet_at_rest, 1);
  EXPECT_LE(r.final_pile_height_error, 0.65);
  EXPECT_LE(r.final_energy_error, 0.25 * std::abs(last.bullet_kinetic + last.bullet_potential));
}

// The 210-cube benchmark pyramid, 2 s: it stands in both.
TEST(ContactOracle, BenchmarkPyramidAgreesStatistically) {
  auto scene = test::oracle_scene("bench/pyramid_20.yaml");
  const app::CompareResult r = app::compare_scene(scene, 120, app::CompareMode::automatic, 10);
  EXPECT_TRUE(r.chaotic);
  EXPECT_LE(r.max_com_error, 0.02);
  EXPECT_LE(r.final_pile_height_error, 0.05);
  EXPECT_EQ(r.samples.back().tumble_at_rest, 210);
  EXPECT_EQ(r.samples.back().bullet_at_rest, 210);
}

}  // namespace
}  // namespace tumble
