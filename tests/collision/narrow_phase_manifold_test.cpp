// The shape of the manifolds that resting contact needs, against hand-computed geometry: a box
// flat on a plane or on a box gets its four corners (or the overlap's), an edge crossing an edge
// one point with the analytic depth, a capsule lying on something two points.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "tests/collision/oracle.hpp"

namespace tumble::testing {
namespace {

const Real kSqrt2 = std::numbers::sqrt2;

Quat about(const Vec3& axis, Real angle) {
  return Quat(Eigen::AngleAxis<Real>(angle, axis.normalized()));
}

// Each expected position is matched by exactly one contact position (order-free).
void expect_positions(const Manifold& m, const std::vector<Vec3>& expected, Real tolerance) {
  ASSERT_EQ(m.count, int(expected.size()));
  std::vector<bool> used(expected.size(), false);
  for (int i = 0; i < m.count; ++i) {
    int match = -1;
    for (std::size_t k = 0; k < expected.size(); ++k) {
      if (!used[k] && (m.points[i].position - expected[k]).norm() < tolerance)
        match = int(k);
    }
    EXPECT_GE(match, 0) << "unexpected contact at " << m.points[i].position.transpose();
    if (match >= 0)
      used[match] = true;
  }
}

void expect_all_depths(const Manifold& m, Real depth, Real tolerance) {
  for (int i = 0; i < m.count; ++i)
    EXPECT_NEAR(m.points[i].depth, depth, tolerance);
}

TEST(NarrowPhaseManifold, BoxRestingFlatOnPlaneGivesItsFourBottomCorners) {
  const Shape box = Shape::box({0.5, 0.3, 0.2});
  const Transform plane_pose{Vec3(1, 2, -0.5), about(Vec3(1, -2, 0.5), 0.3)};
  const Vec3 up = plane_pose.rotate(Vec3::UnitZ());
  const Real sink = 0.003;
  const Transform box_pose{
      plane_pose.translation + up * (0.2 - sink) + plane_pose.rotate(Vec3(0.3, -0.1, 0)),
      plane_pose.rotation * about(Vec3::UnitZ(), 0.7)};
  Manifold m;
  collide(box, box_pose, Shape::plane(), plane_pose, 0.01, m);
  std::vector<Vec3> expected;
  for (const Real x : {-0.5, 0.5}) {
    for (const Real y : {-0.3, 0.3}) {
      expected.push_back(box_pose.apply(Vec3(x, y, -0.2)) + up * (sink / 2));
    }
  }
  expect_positions(m, expected, 1e-12);
  expect_all_depths(m, sink, 1e-12);
  EXPECT_LT((m.normal - up).norm(), 1e-15);
}

TEST(NarrowPhaseManifold, BoxSwallowedByPlaneKeepsTheDeepestAndThreeMore) {
  const Shape box = Shape::box({0.5, 0.3, 0.2});
  const Transform box_pose{Vec3(0, 0, -2), about(Vec3(1, 2, 3), 0.4)};
  Manifold m;
  collide(box, box_pose, Shape::plane(), {}, 0, m);
  ASSERT_EQ(m.count, 4);
  Real deepest_corner = 0;
  for (int v = 0; v < 8; ++v) {
    const Vec3 corner =
        box_pose.apply(Vec3(v & 1 ? 0.5 : -0.5, v & 2 ? 0.3 : -0.3, v & 4 ? 0.2 : -0.2));
    deepest_corner = std::max(deepest_corner, -corner.z());
  }
  EXPECT_NEAR(m.points[deepest_point(m)].depth, deepest_corner, 1e-12);
}

TEST(NarrowPhaseManifold, BoxRestingOnLargerBoxGivesItsFourCorners) {
  const Shape small = Shape::box({0.5, 0.4, 0.3});
  const Shape large = Shape::box({2, 2, 0.5});
  const Real sink = 0.004;
  const Transform small_pose{Vec3(0.2, -0.1, 0.5 + 0.3 - sink), about(Vec3::UnitZ(), 0.5)};
  const Transform large_pose{};
  std::vector<Vec3> expected;
  for (const Real x : {-0.5, 0.5}) {
    for (const Real y : {-0.4, 0.4}) {
      expected.push_back(small_pose.apply(Vec3(x, y, -0.3)) + Vec3(0, 0, sink / 2));
    }
  }
  for (const bool swap : {false, true}) {
    Manifold m;
    if (swap) {
      collide(large, large_pose, small, small_pose, 0.01, m);
    } else {
      collide(small, small_pose, large, large_pose, 0.01, m);
    }
    expect_positions(m, expected, 1e-12);
    expect_all_depths(m, sink, 1e-12);
    EXPECT_LT((m.normal - (swap ? Vec3(-Vec3::UnitZ()) : Vec3(Vec3::UnitZ()))).norm(), 1e-15);
  }
}

TEST(NarrowPhaseManifold, OffsetEqualBoxesGiveTheCornersOfTheirOverlap) {
  const Shape cube = Shape::box({0.5, 0.5, 0.5});
  const Real sink = 0.005;
  Manifold m;
  collide(cube, {Vec3(0.6, 0.3, 1 - sink), Quat::Identity()}, cube, {}, 0.01, m);
  // The overlap of [-0.5, 0.5]^2 and [0.1, 1.1] x [-0.2, 0.8].
  const Real z = 0.5 - sink / 2;
  expect_positions(m, {{0.1, -0.2, z}, {0.5, -0.2, z}, {0.5, 0.5, z}, {0.1, 0.5, z}}, 1e-12);
  expect_all_depths(m, sink, 1e-12);
}

TEST(NarrowPhaseManifold, BoxTurnedOnEqualBoxReducesTheOctagonToTheLargestSquare) {
  const Shape cube = Shape::box({0.5, 0.5, 0.5});
  const Real sink = 0.01;
  Manifold m;
  collide(cube, {Vec3(0, 0, 1 - sink), about(Vec3::UnitZ(), std::numbers::pi / 4)}, cube, {}, 0.02,
          m);
  ASSERT_EQ(m.count, 4);
  expect_all_depths(m, sink, 1e-12);
  // Every kept point is a vertex of the octagon where the square and the turned square cross.
  for (int i = 0; i < 4; ++i) {
    const Vec3& p = m.points[i].position;
    EXPECT_NEAR(std::max(std::abs(p.x()), std::abs(p.y())), 0.5, 1e-12);
    EXPECT_NEAR(std::abs(p.x()) + std::abs(p.y()), 0.5 * kSqrt2, 1e-12);
  }
  // The best four of a regular octagon span a square of area 2 R^2.
  std::array<Vec3, 4> p;
  for (int i = 0; i < 4; ++i)
    p[i] = m.points[i].position;
  std::sort(p.begin(), p.end(), [](const Vec3& u, const Vec3& v) {
    return std::atan2(u.y(), u.x()) < std::atan2(v.y(), v.x());
  });
  Real area = 0;
  for (int i = 0; i < 4; ++i)
    area += p[i].x() * p[(i + 1) % 4].y() - p[(i + 1) % 4].x() * p[i].y();
  const Real circumradius_squared = 0.25 + std::pow(0.5 * kSqrt2 - 0.5, 2);
  EXPECT_NEAR(area / 2, 2 * circumradius_squared, 1e-12);
}

TEST(NarrowPhaseManifold, CrossingEdgesGiveOnePointWithTheAnalyticDepth) {
  const Shape cube = Shape::box({0.5, 0.5, 0.5});
  // B stands on an edge along x (top edge at z = sqrt2/2); A hangs on an edge along y.
  const Transform pose_b{Vec3::Zero(), about(Vec3::UnitX(), std::numbers::pi / 4)};
  const Real depth = 0.01;
  const Transform pose_a{Vec3(0.1, -0.2, kSqrt2 - depth),
                         about(Vec3::UnitY(), std::numbers::pi / 4)};
  for (const bool swap : {false, true}) {
    Manifold m;
    if (swap) {
      collide(cube, pose_b, cube, pose_a, 0.01, m);
    } else {
      collide(cube, pose_a, cube, pose_b, 0.01, m);
    }
    expect_positions(m, {Vec3(0.1, 0, 0.5 * kSqrt2 - depth / 2)}, 1e-12);
    EXPECT_NEAR(m.points[0].depth, depth, 1e-12);
    EXPECT_LT((m.normal - (swap ? Vec3(-Vec3::UnitZ()) : Vec3(Vec3::UnitZ()))).norm(), 1e-12);
  }
}

TEST(NarrowPhaseManifold, BoxesApartWithinTheMarginReportTheExactDistance) {
  const Shape cube = Shape::box({0.5, 0.5, 0.5});
  {
    // Face to face, 0.01 apart: four points at -0.01.
    Manifold m;
    collide(cube, {Vec3(0, 0, 1.01), Quat::Identity()}, cube, {}, 0.05, m);
    ASSERT_EQ(m.count, 4);
    expect_all_depths(m, -0.01, 1e-12);
  }
  {
    // Edge to edge across a diagonal gap (FCL's "distance 0.1414" case, scaled): the best
    // separating axis only sees 0.01, the exact distance is 0.01 sqrt2.
    Manifold m;
    collide(cube, {Vec3(1.01, 1.01, 0), Quat::Identity()}, cube, {}, 0.05, m);
    ASSERT_EQ(m.count, 1);
    EXPECT_NEAR(m.points[0].depth, -0.01 * kSqrt2, 1e-12);
    EXPECT_LT((m.normal - Vec3(1, 1, 0).normalized()).norm(), 1e-12);
  }
}

TEST(NarrowPhaseManifold, CapsuleLyingOnABoxGetsTwoPoints) {
  const Shape capsule = Shape::capsule(0.2, 0.5);
  const Shape box = Shape::box({1, 1, 0.5});
  const Quat along_x = about(Vec3::UnitY(), std::numbers::pi / 2);
  const Real sink = 0.01;
  const Real z = 0.5 - sink / 2;
  {
    Manifold m;
    collide(capsule, {Vec3(0.3, 0.1, 0.7 - sink), along_x}, box, {}, 0.02, m);
    expect_positions(m, {{-0.2, 0.1, z}, {0.8, 0.1, z}}, 1e-12);
    expect_all_depths(m, sink, 1e-12);
  }
  {
    // Hanging over the edge x = 1: the inner end and the point over the edge.
    Manifold m;
    collide(capsule, {Vec3(0.9, 0.1, 0.7 - sink), along_x}, box, {}, 0.02, m);
    expect_positions(m, {{0.4, 0.1, z}, {1.0, 0.1, z}}, 1e-12);
    expect_all_depths(m, sink, 1e-12);
  }
  {
    // Tilted so that one end is higher than the margin: one point, at the low end.
    Manifold m;
    const Quat tilted = about(Vec3::UnitY(), std::numbers::pi / 2 - 0.2);
    collide(capsule, {Vec3(0, 0, 0.7 - sink + 0.5 * std::sin(0.2)), tilted}, box, {}, 0.02, m);
    ASSERT_EQ(m.count, 1);
    EXPECT_NEAR(m.points[0].depth, sink, 1e-12);
  }
}

TEST(NarrowPhaseManifold, CapsulesParallelGetTwoPointsCrossedOne) {
  const Shape capsule = Shape::capsule(0.2, 0.5);
  const Quat along_x = about(Vec3::UnitY(), std::numbers::pi / 2);
  const Quat along_y = about(Vec3::UnitX(), std::numbers::pi / 2);
  {
    Manifold m;
    collide(capsule, {Vec3(0.3, 0, 0.39), along_x}, capsule, {Vec3::Zero(), along_x}, 0.02, m);
    // Overlap of [-0.2, 0.8] and [-0.5, 0.5] along x, midway between the surfaces.
    expect_positions(m, {{-0.2, 0, 0.195}, {0.5, 0, 0.195}}, 1e-12);
    expect_all_depths(m, 0.01, 1e-12);
  }
  {
    Manifold m;
    collide(capsule, {Vec3(0.1, 0.2, 0.39), along_y}, capsule, {Vec3::Zero(), along_x}, 0.02, m);
    expect_positions(m, {{0.1, 0, 0.195}}, 1e-12);
    EXPECT_NEAR(m.points[0].depth, 0.01, 1e-12);
  }
}

TEST(NarrowPhaseManifold, CapsuleOnPlaneLyingAndStanding) {
  const Shape capsule = Shape::capsule(0.2, 0.5);
  Manifold lying;
  collide(capsule, {Vec3(0, 0, 0.19), about(Vec3::UnitY(), std::numbers::pi / 2)}, Shape::plane(),
          {}, 0.02, lying);
  expect_positions(lying, {{-0.5, 0, -0.005}, {0.5, 0, -0.005}}, 1e-12);
  Manifold standing;
  collide(capsule, {Vec3(0, 0, 0.69), Quat::Identity()}, Shape::plane(), {}, 0.02, standing);
  expect_positions(standing, {{0, 0, -0.005}}, 1e-12);
}

}  // namespace
}  // namespace tumble::testing
