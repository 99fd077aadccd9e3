// Contact recycling (collision/narrow_phase/manifold_recycling.hpp) against fresh queries: a kept
// manifold moved with both bodies is the fresh manifold, its depths follow a relative motion
// exactly, and it is refused once the relative pose leaves the tolerances.
#include <gtest/gtest.h>

#include <random>

#include "collision/narrow_phase/manifold_recycling.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"

namespace tumble {
namespace {

Quat random_rotation(std::mt19937& random) {
  std::normal_distribution<Real> n(0, 1);
  Quat q(n(random), n(random), n(random), n(random));
  return q.normalized();
}

Vec3 random_vector(std::mt19937& random, Real scale) {
  std::uniform_real_distribution<Real> u(-scale, scale);
  return Vec3(u(random), u(random), u(random));
}

// Pairs of every convex kind, resting face on face or overlapping at random.
struct PairCase {
  Shape a, b;
};

std::vector<PairCase> cases() {
  return {{Shape::box(Vec3(0.5, 0.4, 0.3)), Shape::box(Vec3(0.3, 0.6, 0.2))},
          {Shape::sphere(0.4), Shape::box(Vec3(0.5, 0.5, 0.5))},
          {Shape::capsule(0.2, 0.5), Shape::box(Vec3(0.6, 0.4, 0.3))},
          {Shape::box(Vec3(0.5, 0.5, 0.5)), Shape::plane()}};
}

// Both bodies moved by one rigid motion: the relative pose is unchanged, so the kept manifold is
// reused, and it is the manifold the query gave before, moved by that motion: the same points (to
// rounding, 1e3 m away), depths, features and normal.
TEST(ManifoldRecycling, MovingBothBodiesTogetherMovesTheManifoldWithThem) {
  std::mt19937 random(71);
  int compared = 0, one_point = 0;
  for (const PairCase& c : cases()) {
    for (int trial = 0; trial < 700; ++trial) {
      const Transform a{random_vector(random, 2), random_rotation(random)};
      Transform b{a.translation + random_vector(random, 0.6), random_rotation(random)};
      if (c.b.type == ShapeType::plane)
        b = {a.translation + a.rotation * Vec3(0, 0, -0.45), a.rotation};
      Manifold before;
      if (collide(c.a, a, c.b, b, 0.01, before) == 0)
        continue;
      const RecyclableManifold kept = make_recyclable(0, 1, before, a, b);
      const Transform motion{random_vector(random, 1e3), random_rotation(random)};
      const Transform a2{motion.apply(a.translation), (motion.rotation * a.rotation).normalized()};
      const Transform b2{motion.apply(b.translation), (motion.rotation * b.rotation).normalized()};
      Manifold recycled;
      if (before.count == 1) {
        // One point: its normal may come from two edges' closest points, which the relative
        // pose's tolerances do not bound; never reused.
        ASSERT_FALSE(recycle(kept, a2, b2, 1e-6, 1e-6, recycled));
        ++one_point;
        continue;
      }
      ASSERT_TRUE(recycle(kept, a2, b2, 1e-6, 1e-6, recycled));
      ASSERT_EQ(recycled.count, before.count);
      EXPECT_LT((recycled.normal - motion.rotate(before.normal)).norm(), 1e-12);
      for (int k = 0; k < before.count; ++k) {
        EXPECT_LT((recycled.points[k].position - motion.apply(before.points[k].position)).norm(),
                  1e-9);
        EXPECT_NEAR(recycled.points[k].depth, before.points[k].depth, 1e-9);
        EXPECT_EQ(recycled.points[k].feature, before.points[k].feature);
      }
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
  EXPECT_GT(one_point, 0);
}

// B moved along the normal by d (within the tolerance): every depth grows by d exactly; moved
// past the tolerance, or turned past it, the kept manifold is refused.
TEST(ManifoldRecycling, DepthsFollowARelativeMotionAndTheTolerancesHold) {
  std::mt19937 random(72);
  const Shape box_a = Shape::box(Vec3(0.5, 0.5, 0.5));
  const Shape box_b = Shape::box(Vec3(0.5, 0.5, 0.5));
  for (int trial = 0; trial < 1000; ++trial) {
    const Transform a{random_vector(random, 5), random_rotation(random)};
    const Transform b{a.apply(Vec3(0.1, -0.05, 0.999)), a.rotation};  // resting on A's top face
    Manifold before;
    ASSERT_EQ(collide(box_b, b, box_a, a, 0.01, before), 4);
    const RecyclableManifold kept = make_recyclable(1, 0, before, b, a);
    std::uniform_real_distribution<Real> u(-1e-3, 1e-3);
    const Real d = u(random);
    // Body "A" of the pair is b; moving a (the pair's B) along the normal (from a to b) by d
    // pushes it d deeper.
    const Transform a2{a.translation + before.normal * d, a.rotation};
    Manifold recycled;
    ASSERT_TRUE(recycle(kept, b, a2, 2e-3, 1e-3, recycled));
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(recycled.points[k].depth, before.points[k].depth + d, 1e-12);
    const Transform far{a.translation + before.normal * 3e-3, a.rotation};
    EXPECT_FALSE(recycle(kept, b, far, 2e-3, 1e-3, recycled));
    const Transform turned{
        a.translation,
        (a.rotation * Quat(Eigen::AngleAxis<Real>(2e-3, Vec3::UnitX()))).normalized()};
    EXPECT_FALSE(recycle(kept, b, turned, 2e-3, 1e-3, recycled));
    EXPECT_TRUE(recycle(kept, b, turned, 2e-3, 3e-3, recycled));
  }
}

}  // namespace
}  // namespace tumble
