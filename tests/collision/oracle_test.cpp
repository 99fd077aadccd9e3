// The test oracle is checked too, against cases whose answer is known another way, so that a
// bug in it cannot make the narrow phase tests pass by agreeing with the same mistake.
#include "tests/collision/oracle.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace tumble::testing {
namespace {

TEST(Oracle, HullDistanceOfAnAxisAlignedBoxMatchesItsFormula) {
  Rng rng(501);
  const Vec3 h(0.5, 0.3, 0.8);
  for (int i = 0; i < 300; ++i) {
    const Vec3 centre = random_vector_in_box(rng, 1.5);
    std::vector<Vec3> corners;
    for (int v = 0; v < 8; ++v) {
      corners.push_back(
          centre + Vec3(v & 1 ? h.x() : -h.x(), v & 2 ? h.y() : -h.y(), v & 4 ? h.z() : -h.z()));
    }
    // Signed distance of the origin to the box centred at `centre`.
    const Vec3 q = (-centre).cwiseAbs() - h;
    const Real expected = q.cwiseMax(0).norm() + std::min(q.maxCoeff(), Real(0));
    EXPECT_NEAR(hull_signed_distance_of_origin(corners), expected, 1e-12);
  }
}

TEST(Oracle, HullDistanceOfFlatAndDegenerateSets) {
  // A unit square in the plane z = 2, seen from the origin below its centre.
  EXPECT_NEAR(hull_signed_distance_of_origin({{-1, -1, 2}, {1, -1, 2}, {1, 1, 2}, {-1, 1, 2}}), 2,
              1e-12);
  // Beside its edge.
  EXPECT_NEAR(hull_signed_distance_of_origin({{2, -1, 0}, {3, -1, 0}, {3, 1, 0}, {2, 1, 0}}), 2,
              1e-12);
  // Collinear points and a single point.
  EXPECT_NEAR(hull_signed_distance_of_origin({{1, 1, 0}, {1, 2, 0}, {1, 3, 0}}), std::sqrt(2.0),
              1e-12);
  EXPECT_NEAR(hull_signed_distance_of_origin({{0, 3, 4}}), 5, 1e-12);
  // The origin on a flat set: distance zero.
  EXPECT_NEAR(hull_signed_distance_of_origin({{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}}), 0, 1e-12);
}

TEST(Oracle, SegmentDistanceMatchesDenseSampling) {
  Rng rng(502);
  for (int i = 0; i < 100; ++i) {
    const Vec3 p0 = random_vector_in_box(rng, 1);
    const Vec3 p1 = random_vector_in_box(rng, 1);
    const Vec3 q0 = random_vector_in_box(rng, 1);
    const Vec3 q1 = i % 10 == 0 ? Vec3(q0 + (p1 - p0) * 0.7) : random_vector_in_box(rng, 1);
    const Real distance = segment_segment_distance(p0, p1, q0, q1);
    Real sampled = std::numeric_limits<Real>::infinity();
    const int n = 400;
    for (int s = 0; s <= n; ++s) {
      for (int t = 0; t <= n; ++t) {
        sampled = std::min(
            sampled, (p0 + (p1 - p0) * (Real(s) / n) - q0 - (q1 - q0) * (Real(t) / n)).norm());
      }
    }
    EXPECT_LE(distance, sampled + 1e-12);
    EXPECT_GE(distance, sampled - 0.01);
  }
}

TEST(Oracle, BruteForceSignedDistanceOfSpheresAndCapsules) {
  // Spheres: |c| - r; a capsule over a box face: height of the core above the face minus r.
  EXPECT_NEAR(brute_force_signed_distance(Shape::sphere(1), {Vec3(3, 4, 0), Quat::Identity()},
                                          Shape::sphere(2), {}),
              2, 1e-12);
  EXPECT_NEAR(
      brute_force_signed_distance(
          Shape::capsule(0.2, 0.5),
          {Vec3(0, 0, 0.6), Quat(Eigen::AngleAxis<Real>(1.5707963267948966, Vec3::UnitY()))},
          Shape::box({1, 1, 0.5}), {}),
      -0.1, 1e-12);
  EXPECT_NEAR(brute_force_signed_distance(Shape::box({0.5, 0.5, 0.5}),
                                          {Vec3(0, 0, 0.2), Quat::Identity()}, Shape::plane(), {}),
              -0.3, 1e-12);
}

}  // namespace
}  // namespace tumble::testing
