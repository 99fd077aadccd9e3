// What changes made between steps leave behind: removed bodies stop mattering everywhere
// (continuous collision included), moved and removed bodies wake what rested on them, ray casts see
// the poses of now, reset forgets the last episode, and the last step's reports stay as they were.
#include <gtest/gtest.h>

#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

using testing::box_at;
using testing::ground;
using testing::scene_of;

TEST(WorldBetweenSteps, ContinuousCollisionIgnoresARemovedWall) {
  BodyDesc ball = dynamic_body("ball", Shape::sphere(0.1));
  ball.position = Vec3(0, 0, 1);
  ball.velocity = Vec3(100, 0, 0);
  BodyDesc wall = static_body("wall", Shape::box(Vec3(0.05, 2, 2)));
  wall.position = Vec3(5, 0, 1);
  auto scene = scene_of({ball, wall}, Vec3::Zero());
  scene->world.ccd = CcdMode::on;
  World world(scene);
  world.remove_body(world.body("wall"));
  world.step(6);  // 10 m: through where the wall was
  EXPECT_NEAR(world.body_state(world.body("ball")).position.x(), 10, 1e-9);
}

TEST(WorldBetweenSteps, MovingOrRemovingABodyWakesWhatRestedOnIt) {
  auto scene = scene_of({ground(), box_at("low", Vec3(0, 0, 1)), box_at("high", Vec3(0, 0, 2)),
                         box_at("lone", Vec3(4, 0, 1))});
  scene->world.sleeping = true;
  World world(scene);
  world.step(150);
  const BodyId high = world.body("high");
  world.remove_body(world.body("low"));
  world.set_pose(world.body("lone"), Vec3(4, 0, 5), Quat::Identity());
  world.step(60);
  EXPECT_NEAR(world.body_state(high).position.z(), 1.0, 0.02);
  EXPECT_NEAR(world.body_state(world.body("lone")).position.z(), 1.0, 0.02);
}

TEST(WorldBetweenSteps, RayCastsSeeWhereBodiesAreNow) {
  BodyDesc a = dynamic_body("a", Shape::sphere(0.5));
  a.position = Vec3(-2, 0, 0);
  a.velocity = Vec3(30, 0, 0);
  BodyDesc b = dynamic_body("b", Shape::sphere(0.5));
  b.position = Vec3(0, 0, 0);
  World world(scene_of({a, b}, Vec3::Zero()));
  world.step(3);
  const Vec3 at = world.body_state(world.body("b")).position;
  ASSERT_GT(at.x(), 0.2) << "b was not hit";
  // Near b's leading edge, which its box of the start of the step does not reach.
  const std::optional<RayHit> hit = world.ray_cast(at + Vec3(0.45, 0, 5), Vec3(0, 0, -1), 10);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->body, world.body("b"));
  EXPECT_NEAR(hit->distance, 5 - std::sqrt(0.25 - 0.45 * 0.45), 1e-9);
}

TEST(WorldBetweenSteps, ResetForgetsContactsForcesAndTargets) {
  BodyDesc paddle = kinematic_body("paddle", Shape::sphere(0.2));
  paddle.position = Vec3(3, 0, 3);
  auto scene = scene_of({ground(), box_at("box", Vec3(0, 0, 1)), paddle});
  World world(scene);
  world.step(30);
  ASSERT_FALSE(world.contact_reports().empty());
  world.add_force(world.body("box"), Vec3(0, 0, 1e5));
  world.set_kinematic_target(world.body("paddle"), Vec3(4, 0, 3), Quat::Identity());
  world.reset();
  EXPECT_TRUE(world.contact_reports().empty());
  World fresh(scene);
  world.step(20);
  fresh.step(20);
  EXPECT_EQ(world.state_hash(), fresh.state_hash());
}

TEST(WorldBetweenSteps, TheLastStepsReportsStayAsTheyWere) {
  World world(scene_of({ground(), box_at("box", Vec3(0, 0, 1)), box_at("other", Vec3(4, 0, 1))}));
  world.step(60);
  const auto total = [&] {
    Real sum = 0;
    for (const ContactReport& r : world.contact_reports())
      for (int k = 0; k < r.point_count; ++k)
        sum += r.points[std::size_t(k)].normal_impulse;
    return sum;
  };
  const Real before = total();
  world.set_pose(world.body("box"), Vec3(0, 0, 3), Quat::Identity());
  world.remove_body(world.body("other"));
  EXPECT_EQ(total(), before);
  EXPECT_EQ(world.contact_reports().size(), 2u);
}

TEST(WorldBetweenSteps, AKinematicPlatformHoldsABoxAsAStaticFloorDoes) {
  const auto sink = [](bool kinematic) {
    BodyDesc floor = kinematic ? kinematic_body("floor", Shape::box(Vec3(5, 5, 0.5)))
                               : static_body("floor", Shape::box(Vec3(5, 5, 0.5)));
    World world(scene_of({floor, box_at("box", Vec3(0, 0, 1.0))}));
    world.step(240);
    return 1.0 - world.body_state(world.body("box")).position.z();
  };
  EXPECT_NEAR(sink(true), sink(false), 1e-6);
}

TEST(WorldBetweenSteps, PenaltyReportsCarryTheWeightToo) {
  auto scene = scene_of({ground(), box_at("box", Vec3(0, 0, 1.0))});
  scene->world.solver = SolverType::penalty;
  World world(scene);
  world.step(240);
  Real up = 0;
  for (const ContactReport& r : world.contact_reports())
    for (int k = 0; k < r.point_count; ++k)
      up -= r.normal.z() * r.points[std::size_t(k)].normal_impulse;  // the box is body B
  EXPECT_NEAR(up / (scene->bodies[1].mass * 9.81 * scene->world.dt), 1.0, 1e-3);
}

TEST(WorldBetweenSteps, BadCompoundPartsAreRefused) {
  EXPECT_THROW(compound_from_parts({{Shape::box(Vec3(-0.5, -0.5, 0.5)), Transform{}}}), Error);
  Shape no_hull;
  no_hull.type = ShapeType::hull;
  EXPECT_THROW(compound_from_parts({{no_hull, Transform{}}}), Error);
  auto scene = scene_of({ground()});
  BodyDesc spinning_ground = ground();
  spinning_ground.name = "g2";
  spinning_ground.angular_velocity = Vec3(0, 0, 1);
  scene->bodies.push_back(spinning_ground);
  EXPECT_THROW(World{scene}, SceneError);
}

TEST(WorldBetweenSteps, AMovedFromWorldThrows) {
  World world(scene_of({ground()}));
  World other(std::move(world));
  EXPECT_THROW(world.step(), Error);  // NOLINT(bugprone-use-after-move): the point of the test
  EXPECT_THROW(world.body("ground"), Error);
  EXPECT_FALSE(world.is_valid(BodyId{0, 0}));
  EXPECT_NO_THROW(other.step());
}

}  // namespace
}  // namespace tumble
