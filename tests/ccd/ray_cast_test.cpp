// Ray casts against every primitive, checked by brute force: the segment is sampled at 20000
// points with the exact signed distance; the reported fraction must lie between the last
// sample outside and the first sample inside, a reported miss must have no sample inside, and
// the normal must be the signed distance's gradient at the hit (finite differences).
#include <gtest/gtest.h>

#include "collision/ccd/ray_cast.hpp"
#include "tests/ccd/ccd_test_support.hpp"

namespace tumble::testing {
namespace {

TEST(RayCast, AgreesWithSamplingForEveryShape) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<Real> size(0.1, 1.0);
  const int kSamples = 20000;
  int hits[4] = {0, 0, 0, 0};
  for (int i = 0; i < scaled(4000); ++i) {
    Shape shape;
    switch (i % 4) {
      case 0:
        shape = Shape::sphere(size(rng));
        break;
      case 1:
        shape = Shape::box(Vec3(size(rng), size(rng), size(rng)));
        break;
      case 2:
        shape = Shape::capsule(size(rng), size(rng));
        break;
      default:
        shape = Shape::plane();
    }
    const Transform pose{random_vector(rng, -1, 1), random_rotation(rng)};
    const Vec3 origin = random_vector(rng, -3, 3);
    const Vec3 delta = (pose.translation - origin) * 1.5 + random_vector(rng, -1.5, 1.5);
    const ShapeRayHit hit = ray_cast(shape, pose, origin, delta);
    int first_inside = -1;
    for (int k = 0; k <= kSamples; ++k) {
      if (signed_distance(shape, pose, origin + delta * (Real(k) / kSamples)) <= 0) {
        first_inside = k;
        break;
      }
    }
    if (first_inside < 0) {
      EXPECT_FALSE(hit.hit) << "case " << i << " fraction " << hit.fraction;
      continue;
    }
    ASSERT_TRUE(hit.hit) << "case " << i;
    ++hits[i % 4];
    const Real step = Real(1) / kSamples;
    EXPECT_LE(hit.fraction, first_inside * step + 1e-12) << "case " << i;
    EXPECT_GE(hit.fraction, (first_inside - 1) * step - 1e-12) << "case " << i;
    if (hit.fraction > 0) {
      // The hit point is on the surface and the normal is the distance gradient there.
      const Vec3 p = origin + hit.fraction * delta;
      EXPECT_NEAR(signed_distance(shape, pose, p), 0, 1e-9);
      const Real e = 1e-6;
      Vec3 gradient;
      for (int c = 0; c < 3; ++c) {
        Vec3 dp = Vec3::Zero();
        dp[c] = e;
        gradient[c] =
            (signed_distance(shape, pose, p + dp) - signed_distance(shape, pose, p - dp)) / (2 * e);
      }
      // Box edges and corners have no unique gradient; only compare where it is defined.
      if (std::abs(gradient.norm() - 1) < 1e-3) {
        EXPECT_LT((hit.normal - gradient).norm(), 1e-4) << "case " << i;
      }
    }
  }
  for (int t = 0; t < 4; ++t)
    EXPECT_GT(hits[t], scaled(4000) / 20) << "shape " << t;
}

TEST(RayCast, NanAndStartInside) {
  const Shape s = Shape::sphere(1);
  EXPECT_FALSE(ray_cast(s, {}, Vec3(std::nan(""), 0, 0), Vec3(1, 0, 0)).hit);
  const ShapeRayHit inside = ray_cast(s, {}, Vec3(0.5, 0, 0), Vec3(3, 0, 0));
  EXPECT_TRUE(inside.hit);
  EXPECT_EQ(inside.fraction, 0);
}

}  // namespace
}  // namespace tumble::testing
