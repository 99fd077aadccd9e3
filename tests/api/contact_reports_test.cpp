// Contact reports: every touching pair with its points, normal (from B to A), depth and the
// impulses of the last step; over a resting box they carry its weight.
#include <gtest/gtest.h>

#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

using testing::box_at;
using testing::ground;
using testing::scene_of;

// The upward impulse the reports put on `body` over the last step.
Vec3 impulse_on(const World& world, BodyId body) {
  Vec3 total = Vec3::Zero();
  for (const ContactReport& r : world.contact_reports()) {
    // The impulse pushes A along the normal and B against it.
    const Real sign = r.body_a == body ? 1 : (r.body_b == body ? -1 : 0);
    for (int k = 0; k < r.point_count; ++k) {
      const ContactPointReport& p = r.points[std::size_t(k)];
      total += sign * (r.normal * p.normal_impulse + p.friction_impulse);
    }
  }
  return total;
}

TEST(ContactReports, ARestingBoxsImpulsesBalanceItsWeight) {
  auto scene = scene_of({ground(), box_at("box", Vec3(0, 0, 1.0))});
  World world(scene);
  const BodyId box = world.body("box");
  world.step(120);
  const Real weight_impulse = scene->bodies[1].mass * 9.81 * scene->world.dt;
  const Vec3 j = impulse_on(world, box);
  EXPECT_NEAR(j.z() / weight_impulse, 1.0, 1e-6);
  EXPECT_LE(std::hypot(j.x(), j.y()) / weight_impulse, 1e-6);
  ASSERT_EQ(world.contact_reports().size(), 1u);
  const ContactReport& r = world.contact_reports()[0];
  EXPECT_EQ(r.point_count, 4);
  // The box is body B (the ground comes first): the normal points from the box to the ground.
  EXPECT_EQ(r.body_b, box);
  EXPECT_NEAR(r.normal.z(), -1.0, 1e-9);
  for (int k = 0; k < r.point_count; ++k) {
    EXPECT_NEAR(r.points[std::size_t(k)].position.z(), 0.5, 1e-3);
    EXPECT_LT(std::abs(r.points[std::size_t(k)].depth), 1e-3);
    EXPECT_GT(r.points[std::size_t(k)].normal_impulse, 0);
  }
}

TEST(ContactReports, AStackPassesEachBoxsWeightDown) {
  auto scene =
      scene_of({ground(), box_at("low", Vec3(0, 0, 1.0)), box_at("high", Vec3(0, 0, 2.0))});
  World world(scene);
  world.step(180);
  const Real w = scene->bodies[1].mass * 9.81 * scene->world.dt;
  // The high box is held up by one weight; the low box by two from below, less one from above.
  EXPECT_NEAR(impulse_on(world, world.body("high")).z() / w, 1.0, 1e-6);
  EXPECT_NEAR(impulse_on(world, world.body("low")).z() / w, 1.0, 1e-6);
}

TEST(ContactReports, EmptyBeforeTheFirstStepAndWhenNothingTouches) {
  World world(scene_of({ground(), box_at("box", Vec3(0, 0, 5))}));
  EXPECT_TRUE(world.contact_reports().empty());
  world.step();
  EXPECT_TRUE(world.contact_reports().empty());
}

}  // namespace
}  // namespace tumble
