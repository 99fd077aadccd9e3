// distance_between for spheres, capsules, boxes, cylinders and hulls against signed distance
// fields: the distance against brute force along the core or over the surface, and the gradients
// (from grad phi) against central differences of the distance on 10,000 random configurations per
// pair (fixed seeds). Kinks (the field's medial
// axis, a capsule whose nearest core point jumps between two basins) are recognised by the two
// one-sided differences disagreeing, counted and printed; no other disagreement is allowed.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "collision/ccd/projected_descent.hpp"
#include "collision/sdf/sdf_grid.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "tests/collision/field_gradient_tally.hpp"
#include "tests/collision/mesh_fixtures.hpp"
#include "tests/collision/sampled_grid.hpp"
#include "tests/property_scale.hpp"
#include "tumble/distance.hpp"
#include "tumble/error.hpp"
#include "tumble/shape.hpp"

namespace tumble {
namespace {

// The torus (0.6, 0.2) sampled at the nodes of a grid of 4 cm cells over +-1.9 m: tricubic, a
// field smooth everywhere (its interpolant rounds the torus's core ridge); trilinear, one whose
// gradient jumps across the cells' faces.
SdfNode torus_grid_node(GridInterpolation how = GridInterpolation::tricubic) {
  const Real cell = 0.04;
  const int n = 96;
  const Vec3 origin = Vec3::Constant(-cell * (n - 1) / 2);
  return SdfNode::from_grid(
      std::make_shared<const SdfGrid>(test::sampled_grid(
          origin, cell, {n, n, n}, [](const Vec3& p) { return sdf::torus(p, 0.6, 0.2).distance; })),
      how);
}

TEST(SdfDistance, GradientsMatchCentralDifferences) {
  const std::vector<FieldCase> cases = {
      {"sphere-torus", SdfNode::torus(0.6, 0.2), Shape::sphere(0.15)},
      {"capsule-torus", SdfNode::torus(0.6, 0.2), Shape::capsule(0.1, 0.3)},
      {"sphere-bowl",
       SdfNode::combine(SdfKind::difference_of,
                        {SdfNode::box(Vec3(0.7, 0.7, 0.3)),
                         SdfNode::sphere(0.6).placed({Vec3(0, 0, 0.5), Quat::Identity()})}),
       Shape::sphere(0.1)},
      {"capsule-smooth-union",
       SdfNode::combine(SdfKind::smooth_union_of,
                        {SdfNode::sphere(0.4),
                         SdfNode::capsule(0.15, 0.5).placed(
                             {Vec3(0.3, 0, 0), Quat(Eigen::AngleAxis<Real>(1, Vec3::UnitY()))})},
                        8),
       Shape::capsule(0.08, 0.25)},
      // A trilinear interpolant's gradient jumps across every cell face: a ball's centre lands
      // on one with probability nil. (A capsule's least point along its core sits on a face far
      // more often, a kink of phi along the core the least holds on: not asserted, docs/sdf.md.)
      {"sphere-trilinear-grid", torus_grid_node(GridInterpolation::trilinear), Shape::sphere(0.15)},
  };
  std::mt19937_64 rng(51);
  const int count = scaled(10000);
  for (const FieldCase& c : cases)
    expect_round_gradients_match(c, rng, count);
}

// Gradients against central differences of step 1e-5 (the descents stop within about 1e-11 m
// of their least value, which a step of 1e-6 would turn into 1e-5 of slope) on 10,000 random
// configurations per case (400 in the instrumented run, where a quarter would take 80 s). Within
// 2 mm of the torus's core ridge phi is a cone and the descent's point inexact: counted apart.
// Kinks: the least point jumping between two basins or corners.
void expect_field_gradients_match(const std::vector<FieldCase>& cases, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const int count = property_scale() < 1 ? 400 : 10000;
  for (const FieldCase& c : cases) {
    const auto [penetrating, kinks, near_ridge, unexplained] =
        tally_gradients(c, rng, count, 1e-5, -0.2 + 2e-3);
    std::printf(
        "%s: %d configurations, %d penetrating, %d kinks, %d near the ridge, %d unexplained\n",
        c.name, count, penetrating, kinks, near_ridge, unexplained);
    EXPECT_EQ(unexplained, 0) << c.name;
    EXPECT_LT(kinks, count / 50) << c.name;
    EXPECT_LT(near_ridge, count / 100) << c.name;
    EXPECT_GT(penetrating, count / 20) << c.name;
  }
}

// Boxes, cylinders and hulls: the least phi over the solid, by projected gradient descent, against
// fields smooth but for the torus's core ridge (whose value is the same all along it, so a solid
// holding it keeps the same distance: zero gradients, which the differences confirm). Kinks: the
// deepest point jumping between two corners level with the surface.
TEST(SdfDistance, SolidsGradientsMatchCentralDifferences) {
  const std::vector<Vec3> pyramid = {Vec3(0, 0, 0.2), Vec3(0.2, 0, 0), Vec3(-0.2, 0, 0),
                                     Vec3(0, 0.2, 0), Vec3(0, -0.2, 0)};
  const std::vector<FieldCase> cases = {
      {"box-torus", SdfNode::torus(0.6, 0.2), Shape::box(Vec3(0.15, 0.1, 0.05))},
      {"cylinder-torus", SdfNode::torus(0.6, 0.2), Shape::cylinder(0.1, 0.15)},
      {"hull-torus", SdfNode::torus(0.6, 0.2), hull_from_points(pyramid)},
      {"box-grid", torus_grid_node(), Shape::box(Vec3(0.12, 0.08, 0.06))},
  };
  expect_field_gradients_match(cases, 53);
}

TEST(SdfDistance, ASolidsDistanceIsTheLeastOverItsSurface) {
  // Against brute force: phi at 100 x 100 points on each face of the box (and its corners).
  const Shape field = sdf_shape(SdfNode::torus(0.6, 0.2));
  const Vec3 half(0.2, 0.1, 0.05);
  const Shape box = Shape::box(half);
  std::mt19937_64 rng(54);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (int i = 0; i < scaled(300); ++i) {
    const Transform pose_a{Vec3(u(rng), u(rng), 0.4 * u(rng)), field_random_turn(rng)};
    const ShapeDistance d = distance_between(box, pose_a, field, Transform{});
    Real brute = std::numeric_limits<Real>::infinity();
    constexpr int n = 100;
    for (int axis = 0; axis < 3; ++axis)
      for (Real sign : {Real(-1), Real(1)})
        for (int p = 0; p <= n; ++p)
          for (int q = 0; q <= n; ++q) {
            Vec3 local;
            local[axis] = sign * half[axis];
            local[(axis + 1) % 3] = half[(axis + 1) % 3] * (-1 + 2 * Real(p) / n);
            local[(axis + 2) % 3] = half[(axis + 2) % 3] * (-1 + 2 * Real(q) / n);
            brute = std::min(brute, field.sdf->distance(pose_a.apply(local)));
          }
    // Never above the best sample by more than the descent's tolerance; never below it by more
    // than the field's Lipschitz bound between samples (half the diagonal of a sample's cell).
    ASSERT_LE(d.distance, brute + 1e-9) << i;
    ASSERT_GE(d.distance, brute - 2.3e-3) << i;
    EXPECT_NEAR(field.sdf->distance(d.point_b), 0, 1e-9);
    EXPECT_NEAR(field.sdf->distance(d.point_a), d.distance, 1e-12);
  }
}

TEST(SdfDistance, ASolidDeepInACsgBowlsWallIsNearTheLeastOverIt) {
  // A cylinder in and about a bowl carved from a box (a CSG difference): against brute force over
  // the cylinder's solid (its caps and side at 2 mm and its inside at 1 cm). Deep in the bowl's
  // wall, phi (the larger of the box's planes and the ball's outside) is not convex, and has
  // several least points over the cylinder; the descents from its support points alone reached
  // the nearest, up to 4.6 cm above the least on such poses. With the lowest of a grid over the
  // solid as a further seed where it penetrates: about a sixth of the poses more than 0.1 mm
  // above, the worst by 5 to 9 mm over several sets of 300 poses (docs/sdf.md, "Not yet").
  const Shape field = sdf_shape(SdfNode::combine(
      SdfKind::difference_of, {SdfNode::box(Vec3(0.7, 0.7, 0.3)),
                               SdfNode::sphere(0.6).placed({Vec3(0, 0, 0.5), Quat::Identity()})}));
  const Shape cylinder = Shape::cylinder(0.1, 0.15);
  std::vector<Vec3> samples;
  const Real r = cylinder.radius, h = cylinder.half_length;
  for (int i = 0; i <= 150; ++i) {
    const Real z = -h + 2 * h * Real(i) / 150;
    for (int k = 0; k < 314; ++k) {
      const Real angle = 2 * Real(M_PI) * Real(k) / 314;
      samples.emplace_back(r * std::cos(angle), r * std::sin(angle), z);
    }
  }
  for (int i = -50; i <= 50; ++i)
    for (int j = -50; j <= 50; ++j)
      for (Real z : {-h, h}) {
        const Vec3 p(r * Real(i) / 50, r * Real(j) / 50, z);
        if (p.head<2>().norm() <= r)
          samples.push_back(p);
      }
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j)
      for (int k = -15; k <= 15; ++k) {
        const Vec3 p(r * Real(i) / 10, r * Real(j) / 10, h * Real(k) / 15);
        if (p.head<2>().norm() <= r)
          samples.push_back(p);
      }
  std::mt19937_64 rng(55);
  std::uniform_real_distribution<Real> u(-1, 1);
  int above = 0, cases = 0;
  Real worst = 0;
  for (int i = 0; i < scaled(300); ++i) {
    // One draw per statement: the order of a call's arguments is the compiler's.
    const Real x = 0.7 * u(rng);
    const Real y = 0.7 * u(rng);
    const Real z = 0.1 + 0.3 * u(rng);
    std::normal_distribution<Real> n(0, 1);
    Real q[4];
    for (Real& c : q)
      c = n(rng);
    const Transform pose_a{Vec3(x, y, z), Quat(q[0], q[1], q[2], q[3]).normalized()};
    const ShapeDistance d = distance_between(cylinder, pose_a, field, Transform{});
    Real brute = std::numeric_limits<Real>::infinity();
    for (const Vec3& p : samples)
      brute = std::min(brute, field.sdf->distance(pose_a.apply(p)));
    ++cases;
    worst = std::max(worst, d.distance - brute);
    above += d.distance > brute + 1e-4 ? 1 : 0;
    // Never below the least phi over the solid: the brute force's samples lie within 2 mm of
    // every point of the surface and 1 cm inside (phi is 1-Lipschitz; a least inside the solid
    // is a kink of phi, which the inside grid's spacing bounds).
    EXPECT_GE(d.distance, brute - 0.01) << i;
  }
  std::printf(
      "cylinder in a CSG bowl: %d of %d poses more than 0.1 mm above the brute force, "
      "the worst by %.3g m\n",
      above, cases, worst);
  EXPECT_LE(worst, 0.012);
  EXPECT_LE(above, cases / 4);
}

TEST(SdfDistance, CapsuleDistanceIsTheLeastAlongItsCore) {
  const Shape field = sdf_shape(SdfNode::torus(0.6, 0.2));
  const Shape capsule = Shape::capsule(0.1, 0.4);
  std::mt19937_64 rng(52);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (int i = 0; i < scaled(2000); ++i) {
    const Transform pose_a{Vec3(u(rng), u(rng), u(rng)), field_random_turn(rng)};
    const ShapeDistance d = distance_between(capsule, pose_a, field, Transform{});
    Real brute = std::numeric_limits<Real>::infinity();
    for (int k = 0; k <= 4000; ++k) {
      const Vec3 p = pose_a.apply(Vec3(0, 0, -0.4 + 0.8 * Real(k) / 4000));
      brute = std::min(brute, field.sdf->distance(p) - 0.1);
    }
    // Never above the best of the 4,001 samples, and never below it by more than the field's
    // Lipschitz bound allows between samples (1 times half their spacing, 1e-4 m), a bound that
    // holds at the torus's core circle too, where phi has a cone.
    ASSERT_LE(d.distance, brute + 1e-12) << i;
    ASSERT_GE(d.distance, brute - 1e-4) << i;
    // The points: B's on the field's surface, A's on the capsule's.
    EXPECT_NEAR(field.sdf->distance(d.point_b), 0, 1e-9);
  }
  // Swapped: the mirrored answer.
  const Transform pose{Vec3(0.6, 0, 0.45), Quat::Identity()};
  const ShapeDistance ab = distance_between(capsule, pose, field, Transform{});
  const ShapeDistance ba = distance_between(field, Transform{}, capsule, pose);
  EXPECT_DOUBLE_EQ(ab.distance, ba.distance);
  EXPECT_EQ(ab.normal, -ba.normal);
  EXPECT_EQ(ab.gradient_a, ba.gradient_b);
  const Shape floor =
      Shape::triangle_mesh(std::make_shared<const TriangleMesh>(testing::grid_mesh(2, 1)));
  EXPECT_THROW(distance_between(floor, pose, field, Transform{}), Error);
}

// Two balls given as fields: the least of phi_A + phi_B is their distance, c - r_A - r_B for
// centres c apart, apart and overlapping alike; the normal joins the centres, and no turn of
// either ball about its own centre changes it.
TEST(SdfDistance, TwoFieldBallsAreAtTheirClosedFormDistance) {
  const Shape a = sdf_shape(SdfNode::sphere(0.3));
  const Shape b = sdf_shape(SdfNode::sphere(0.5));
  std::mt19937_64 rng(53);
  std::uniform_real_distribution<Real> u(-1, 1);
  int overlapping = 0;
  for (int i = 0; i < scaled(1000); ++i) {
    const Transform pose_b{Vec3(u(rng), u(rng), u(rng)) * 100, field_random_turn(rng)};
    const Transform pose_a{pose_b.translation + Vec3(u(rng), u(rng), u(rng)),
                           field_random_turn(rng)};
    const Vec3 between = pose_a.translation - pose_b.translation;
    const Real centres = between.norm();
    if (centres < 0.05)
      continue;  // nearly concentric: the normal is ill-defined
    const Vec3 n = between / centres;
    const ShapeDistance d = distance_between(a, pose_a, b, pose_b);
    overlapping += d.distance < 0 ? 1 : 0;
    ASSERT_NEAR(d.distance, centres - 0.8, 1e-9) << i;
    ASSERT_TRUE(d.converged) << i;
    ASSERT_NEAR((d.normal - n).norm(), 0, 1e-6) << i;
    ASSERT_NEAR((d.point_a - (pose_a.translation - 0.3 * n)).norm(), 0, 1e-6) << i;
    ASSERT_NEAR((d.point_b - (pose_b.translation + 0.5 * n)).norm(), 0, 1e-6) << i;
    ASSERT_NEAR((d.gradient_a.head<3>() - n).norm(), 0, 1e-6) << i;
    ASSERT_NEAR((d.gradient_b.head<3>() + n).norm(), 0, 1e-6) << i;
    ASSERT_NEAR(d.gradient_a.tail<3>().norm(), 0, 1e-6) << i;
    ASSERT_NEAR(d.gradient_b.tail<3>().norm(), 0, 1e-6) << i;
  }
  EXPECT_GT(overlapping, scaled(1000) / 10);
}

// The descent says when it stopped at its step cap rather than at a least point, which the
// distances against fields report as not converged.
TEST(SdfDistance, TheDescentReportsItsStepCap) {
  // The least of |x - c|^2 over the unit box, c outside it: the corner (1, 1, 1).
  const Vec3 c(2, 3, 4);
  const auto objective = [&](const Vec3& x) {
    return sdf::Sample{(x - c).squaredNorm(), Vec3(2 * (x - c))};
  };
  const auto project = [](const Vec3& x) { return Vec3(x.cwiseMax(Real(-1)).cwiseMin(Real(1))); };
  bool capped = false;
  const auto [x, reached] =
      projected_descent(Vec3(-1, -1, -1), 1, 2000, objective, project, &capped);
  EXPECT_FALSE(capped);
  EXPECT_NEAR((x - Vec3(1, 1, 1)).norm(), 0, 1e-12);
  EXPECT_NEAR(reached.distance, (Vec3(1, 1, 1) - c).squaredNorm(), 1e-12);
  const auto [early, value] =
      projected_descent(Vec3(-1, -1, -1), 1, 2, objective, project, &capped);
  EXPECT_TRUE(capped);
  EXPECT_GT(value.distance, reached.distance);
  EXPECT_GT((early - Vec3(1, 1, 1)).norm(), 1e-3);
}

// A plane's half-space against a field, and a field against a field, on fields smooth wherever the
// least point lands. Fields whose least point sits on a ridge whose value changes along it (a
// box's or a CSG solid's inside) are not asserted: docs/sdf.md, "Gradients", has their counts.
TEST(SdfDistance, PlaneAgainstFieldGradientsMatchCentralDifferences) {
  expect_field_gradients_match({{"plane-torus", SdfNode::torus(0.6, 0.2), Shape::plane()}}, 54);
}

TEST(SdfDistance, FieldBallAgainstFieldGradientsMatchCentralDifferences) {
  expect_field_gradients_match(
      {{"field ball-torus", SdfNode::torus(0.6, 0.2), sdf_shape(SdfNode::sphere(0.15))}}, 55);
}

TEST(SdfDistance, TorusAgainstTorusGradientsMatchCentralDifferences) {
  expect_field_gradients_match(
      {{"torus-torus", SdfNode::torus(0.6, 0.2), sdf_shape(SdfNode::torus(0.4, 0.1))}}, 56);
}

// Two tori apart: the least of phi_A + phi_B is their distance, which no point of A's surface
// beats (phi_B at a surface point of A is that point's distance from B) and which the densest
// sampling of A's surface comes within its spacing of.
TEST(SdfDistance, TwoFieldsApartAreAtTheLeastDistanceOfTheirSurfaces) {
  const Shape a = sdf_shape(SdfNode::torus(0.4, 0.1));
  const Shape b = sdf_shape(SdfNode::torus(0.6, 0.2));
  std::mt19937_64 rng(57);
  std::uniform_real_distribution<Real> u(-1, 1);
  int apart = 0;
  for (int i = 0; i < scaled(400); ++i) {
    const Transform pose_b{Vec3(u(rng), u(rng), u(rng)), field_random_turn(rng)};
    const Transform pose_a{pose_b.translation + Vec3(u(rng), u(rng), u(rng)) * 1.5,
                           field_random_turn(rng)};
    const ShapeDistance d = distance_between(a, pose_a, b, pose_b);
    Real brute = std::numeric_limits<Real>::infinity();
    for (const Vec3& p : a.sdf->surface_points())
      brute = std::min(brute, b.sdf->distance(pose_b.apply_inverse(pose_a.apply(p))));
    if (!(brute > 0.01))
      continue;
    ++apart;
    // Surface points about 1.9 cm apart (a 48-cell grid over the torus's 0.9 m width): the
    // nearest is within 1.4 cm of the true closest point, whose distance it exceeds by less
    // than the square of that over the tori's smaller radius of curvature, 2 mm.
    ASSERT_LE(d.distance, brute + 1e-9) << i;
    ASSERT_GE(d.distance, brute - 2e-3) << i;
    EXPECT_NEAR(a.sdf->distance(pose_a.apply_inverse(d.point_a)), 0, 1e-9) << i;
    EXPECT_NEAR(b.sdf->distance(pose_b.apply_inverse(d.point_b)), 0, 1e-9) << i;
    EXPECT_NEAR((d.point_a - d.point_b).norm(), d.distance, 1e-6) << i;
  }
  EXPECT_GT(apart, scaled(400) / 4);
}

}  // namespace
}  // namespace tumble

namespace tumble {
namespace {

// Where the least point lands on a ridge of a CSG or box field, or on a cell face of a trilinear
// grid, whose value changes along it, the distance is not differentiable there and the gradients
// are one-sided or taken at a point held fixed (docs/sdf.md, "Gradients"): such pairs are not
// held to the differences, but their disagreements are counted here, by kind, so that they are
// reported rather than hidden, and bounded so that they cannot grow unseen. 300 configurations
// each (10 in the instrumented run, where the solids' descents are slow), step 1e-5. Measured
// shares of the 12 entries that disagree: 4.4% (field box-torus), 74% (a plane cutting the bowl,
// whose least point lies on the medial ridge inside the wall), 27% (cylinder-bowl), 28%
// (capsule-trilinear); the bounds leave room for the other compiler's draws and the instrumented
// run's smaller sample.
TEST(SdfDistance, RidgeDisagreementsAreCountedAndBounded) {
  const SdfNode bowl = SdfNode::combine(
      SdfKind::difference_of, {SdfNode::box(Vec3(0.7, 0.7, 0.3)),
                               SdfNode::sphere(0.6).placed({Vec3(0, 0, 0.5), Quat::Identity()})});
  struct RidgeCase {
    FieldCase pair;
    Real bound;  // the largest share of the 12 entries per configuration that may disagree
  };
  const std::vector<RidgeCase> cases = {
      {{"field box-torus", SdfNode::torus(0.6, 0.2),
        sdf_shape(SdfNode::box(Vec3(0.15, 0.1, 0.05)))},
       0.08},
      {{"plane-CSG bowl", bowl, Shape::plane()}, 0.9},
      {{"cylinder-CSG bowl", bowl, Shape::cylinder(0.1, 0.15)}, 0.4},
      {{"capsule-trilinear grid", torus_grid_node(GridInterpolation::trilinear),
        Shape::capsule(0.1, 0.3)},
       0.5},
  };
  std::mt19937_64 rng(58);
  const int count = property_scale() < 1 ? 10 : 300;
  for (const RidgeCase& c : cases) {
    const auto [penetrating, kinks, near_ridge, unexplained] =
        tally_gradients(c.pair, rng, count, 1e-5);
    const int disagreeing = kinks + near_ridge + unexplained;
    std::printf("%s: %d configurations, %d penetrating; of %d entries %d disagree (%d at kinks)\n",
                c.pair.name, count, penetrating, 12 * count, disagreeing, kinks);
    if (property_scale() >= 1) {  // ten configurations are too few for a share
      EXPECT_LE(disagreeing, c.bound * 12 * count) << c.pair.name;
    }
    EXPECT_GT(penetrating, count / 20) << c.pair.name;
  }
}

}  // namespace
}  // namespace tumble
