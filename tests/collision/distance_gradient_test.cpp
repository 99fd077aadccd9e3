// distance_between's gradients against central differences of the distance itself, on 10,000
// random configurations per pair type (separated and penetrating, fixed seeds). Where the
// distance is not differentiable (parallel features: a kink within the step) central
// differences and the one-sided gradient disagree; such points are recognised by the analytic
// gradient jumping between the two sides, counted and printed, and must stay rare. No other
// disagreement is allowed. A penetrating pair with a cylinder takes its points from the supports
// along the normal (docs/sdf.md, "Cylinders in penetration"); where both supports are faces or
// parallel segments (under 1% of them) its gradients are themselves central differences over
// 1e-6, which this checks against a step a thousand times longer.
#include <gtest/gtest.h>

#include <cstdio>

#include "collision/shapes/shape.hpp"
#include "tests/collision/oracle.hpp"
#include "tests/property_scale.hpp"
#include "tumble/distance.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

using testing::Rng;

Real shape_bounding_radius(const Shape& s) {
  return bounding_radius(s);
}

// The pose moved by the k-th coordinate of a pose gradient: a translation along a world axis, or
// a turn about a world axis through the body's origin.
Transform pose_moved(const Transform& pose, int k, Real h) {
  Transform out = pose;
  if (k < 3) {
    out.translation[k] += h;
  } else {
    out.rotation = (Eigen::AngleAxis<Real>(h, Vec3::Unit(k - 3)) * pose.rotation).normalized();
  }
  return out;
}

struct GradientTally {
  int configurations = 0;
  int penetrating = 0;
  int kinks = 0;
  int unexplained = 0;
  int not_converged = 0;
};

void check_gradient_pair(ShapeType ta, ShapeType tb, GradientTally& tally, Rng& rng) {
  // 400 a pair in the instrumented run (TUMBLE_PROPERTY_SCALE < 1), where a quarter took 51 s:
  // every pair's code still runs under the sanitizers, the optimised build checks the 10,000.
  const int count = property_scale() < 1 ? 400 : 10000;
  // EPA stops on a cylinder's curved core about 1e-8 m short of the exact depth (its relative
  // tolerance, collision/narrow_phase/gjk_epa/epa.hpp), which central differences over 1e-5 m
  // would magnify to 1e-3: pairs with a cylinder take a longer step, whose own truncation error
  // (h^2 times the third derivative, curvatures of order 1/m) is still below the tolerance.
  const bool curved = ta == ShapeType::cylinder || tb == ShapeType::cylinder;
  const Real h = curved ? 1e-3 : 1e-5;
  const Real tolerance = curved ? 2e-3 : 2e-4;
  for (int i = 0; i < count; ++i) {
    const Shape a = testing::random_shape(rng, ta);
    const Shape b = testing::random_shape(rng, tb);
    const Transform pose_a{testing::random_vector_in_box(rng, 5), testing::random_rotation(rng)};
    Transform pose_b{
        pose_a.translation + testing::random_unit_vector(rng) * testing::uniform(rng, 0.1, 2.5),
        testing::random_rotation(rng)};
    if (tb == ShapeType::plane) {
      // A's centre at a height between 0 and 1.5 bounding radii above the plane.
      const Vec3 up = pose_b.rotation * Vec3::UnitZ();
      pose_b.translation =
          pose_a.translation - up * testing::uniform(rng, 0, 1.5) * shape_bounding_radius(a);
    }
    const ShapeDistance d = distance_between(a, pose_a, b, pose_b);
    ++tally.configurations;
    tally.penetrating += d.distance < 0;
    if (!d.converged) {
      ++tally.not_converged;
      continue;
    }
    bool kink = false;
    bool bad = false;
    for (int side = 0; side < 2; ++side) {
      for (int k = 0; k < 6; ++k) {
        const auto at = [&](Real step, bool gradients) {
          return side == 0 ? distance_between(a, pose_moved(pose_a, k, step), b, pose_b, gradients)
                           : distance_between(a, pose_a, b, pose_moved(pose_b, k, step), gradients);
        };
        const Real fd = (at(h, false).distance - at(-h, false).distance) / (2 * h);
        const Real analytic = side == 0 ? d.gradient_a[k] : d.gradient_b[k];
        if (std::abs(fd - analytic) <= tolerance)
          continue;
        const ShapeDistance plus = at(h, true), minus = at(-h, true);
        const PoseGradient& gp = side == 0 ? plus.gradient_a : plus.gradient_b;
        const PoseGradient& gm = side == 0 ? minus.gradient_a : minus.gradient_b;
        if ((gp - gm).norm() > tolerance)
          kink = true;
        else
          bad = true;
      }
    }
    if (bad) {
      ++tally.unexplained;
      ADD_FAILURE() << shape_type_name(ta) << "-" << shape_type_name(tb) << " configuration " << i
                    << ": distance " << d.distance << ", gradient off without a kink";
    } else if (kink) {
      ++tally.kinks;
    }
  }
}

TEST(DistanceGradient, MatchesCentralDifferencesForEveryConvexPair) {
  const ShapeType convex[] = {ShapeType::sphere, ShapeType::box, ShapeType::capsule,
                              ShapeType::cylinder, ShapeType::hull};
  Rng rng(31);
  for (std::size_t i = 0; i < 5; ++i) {
    for (std::size_t j = i; j < 6; ++j) {
      const ShapeType tb = j < 5 ? convex[j] : ShapeType::plane;
      GradientTally t;
      check_gradient_pair(convex[i], tb, t, rng);
      std::printf(
          "%-8s %-8s %5d configurations, %5d penetrating, %4d near a kink, %d not "
          "converged\n",
          std::string(shape_type_name(convex[i])).c_str(), std::string(shape_type_name(tb)).c_str(),
          t.configurations, t.penetrating, t.kinks, t.not_converged);
      EXPECT_EQ(t.unexplained, 0);
      EXPECT_GT(t.penetrating, t.configurations / 10);  // both regimes are exercised
      EXPECT_LT(t.penetrating, t.configurations * 9 / 10);
      EXPECT_LE(t.kinks + t.not_converged, t.configurations / 50);
    }
  }
}

// A plane as the first shape: the same answer as with it second, mirrored (the distance, the normal
// negated, the points and the gradients swapped), so that the differences checked above with the
// plane second hold for it first too.
TEST(DistanceGradient, APlaneFirstIsThePlaneSecondMirrored) {
  const ShapeType convex[] = {ShapeType::sphere, ShapeType::box, ShapeType::capsule,
                              ShapeType::cylinder, ShapeType::hull};
  Rng rng(32);
  int penetrating = 0, compared = 0;
  for (const ShapeType type : convex)
    for (int i = 0; i < scaled(1000); ++i) {
      const Shape b = testing::random_shape(rng, type);
      const Transform pose_b{testing::random_vector_in_box(rng, 5), testing::random_rotation(rng)};
      Transform pose_plane{Vec3::Zero(), testing::random_rotation(rng)};
      const Vec3 up = pose_plane.rotation * Vec3::UnitZ();
      pose_plane.translation =
          pose_b.translation - up * testing::uniform(rng, -0.5, 1.5) * shape_bounding_radius(b);
      const ShapeDistance first = distance_between(Shape::plane(), pose_plane, b, pose_b);
      const ShapeDistance second = distance_between(b, pose_b, Shape::plane(), pose_plane);
      ASSERT_EQ(first.distance, second.distance) << shape_type_name(type) << " " << i;
      ASSERT_EQ(first.normal, Vec3(-second.normal)) << shape_type_name(type) << " " << i;
      ASSERT_EQ(first.point_a, second.point_b) << shape_type_name(type) << " " << i;
      ASSERT_EQ(first.point_b, second.point_a) << shape_type_name(type) << " " << i;
      ASSERT_EQ(first.gradient_a, second.gradient_b) << shape_type_name(type) << " " << i;
      ASSERT_EQ(first.gradient_b, second.gradient_a) << shape_type_name(type) << " " << i;
      penetrating += first.distance < 0;
      ++compared;
    }
  EXPECT_GT(penetrating, compared / 10);
  EXPECT_LT(penetrating, compared * 9 / 10);
}

TEST(DistanceGradient, AgreesWithTheExactAnswerForTwoSpheres) {
  Rng rng(32);
  for (int i = 0; i < 1000; ++i) {
    const Real ra = testing::uniform(rng, 0.1, 1), rb = testing::uniform(rng, 0.1, 1);
    const Transform pa{testing::random_vector_in_box(rng, 3), testing::random_rotation(rng)};
    const Transform pb{testing::random_vector_in_box(rng, 3), testing::random_rotation(rng)};
    const ShapeDistance d = distance_between(Shape::sphere(ra), pa, Shape::sphere(rb), pb);
    const Vec3 ab = pb.translation - pa.translation;
    EXPECT_NEAR(d.distance, ab.norm() - ra - rb, 1e-9);
    EXPECT_NEAR((d.gradient_b.head<3>() - ab.normalized()).norm(), 0, 1e-9);
    EXPECT_NEAR(d.gradient_b.tail<3>().norm(), 0, 1e-9);  // turning a sphere changes nothing
    EXPECT_NEAR((d.gradient_a.head<3>() + d.gradient_b.head<3>()).norm(), 0, 1e-12);
  }
}

TEST(DistanceGradient, ContactPotentialIsTheSpringAndClipsItsGradient) {
  const Transform pa{};
  const Transform pb{Vec3(0, 0, 1.5), Quat::Identity()};
  const ShapeDistance d = distance_between(Shape::sphere(1), pa, Shape::sphere(1), pb);
  ASSERT_NEAR(d.distance, -0.5, 1e-12);
  const ContactPotential p = contact_potential(d, 100, 1e9);
  EXPECT_NEAR(p.value, 12.5, 1e-10);
  EXPECT_NEAR(p.gradient_b.z(), 100 * -0.5 * 1.0, 1e-9);  // k d dd/dz_b, dd/dz_b = +1
  const ContactPotential clipped = contact_potential(d, 100, 10);
  EXPECT_EQ(clipped.gradient_b.z(), -10);
  const ShapeDistance apart = distance_between(Shape::sphere(1), pa, Shape::sphere(1),
                                               Transform{Vec3(0, 0, 3), Quat::Identity()});
  EXPECT_EQ(contact_potential(apart, 100, 10).value, 0);
  EXPECT_THROW(contact_potential(d, -1, 10), Error);
}

TEST(DistanceGradient, RefusesWhatItCannotAnswer) {
  const Transform p{};
  EXPECT_THROW(distance_between(Shape::plane(), p, Shape::plane(), p), Error);
  Transform bad;
  bad.translation.x() = std::nan("");
  EXPECT_THROW(distance_between(Shape::sphere(1), bad, Shape::sphere(1), p), Error);
}

}  // namespace
}  // namespace tumble
