// Kinematic bodies: they reach their targets exactly, push dynamic bodies, ignore contacts and
// gravity, and keep their velocity without a target.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

using testing::box_at;
using testing::ground;
using testing::scene_of;

TEST(KinematicBody, ReachesItsTargetAtTheEndOfTheStep) {
  BodyDesc paddle = kinematic_body("paddle", Shape::box(Vec3(0.1, 0.5, 0.5)));
  paddle.position = Vec3(0, 0, 2);
  auto scene = scene_of({paddle});
  World world(scene);
  const BodyId id = world.body("paddle");
  const Real dt = scene->world.dt;
  for (int k = 1; k <= 60; ++k) {
    const Vec3 target(0.02 * k, std::sin(0.1 * k), 2);
    const Quat turn(Eigen::AngleAxis<Real>(0.03 * k, Vec3(0, 0, 1)));
    const Vec3 before = world.body_state(id).position;
    world.set_kinematic_target(id, target, turn);
    world.step();
    const BodyState s = world.body_state(id);
    ASSERT_EQ(s.position, target) << "step " << k;
    ASSERT_LE(s.orientation.angularDistance(turn), 1e-12) << "step " << k;
    ASSERT_LE((s.velocity - (target - before) / dt).norm(), 1e-9) << "step " << k;
  }
}

TEST(KinematicBody, KeepsItsVelocityWithoutATargetAndIgnoresGravity) {
  BodyDesc paddle = kinematic_body("paddle", Shape::sphere(0.2));
  paddle.position = Vec3(0, 0, 1);
  auto scene = scene_of({ground(), paddle});
  World world(scene);
  const BodyId id = world.body("paddle");
  world.set_velocity(id, Vec3(0, 0, -1), Vec3::Zero());
  world.step(120);  // two seconds: straight through the ground, which it ignores
  const BodyState s = world.body_state(id);
  EXPECT_NEAR(s.position.z(), 1 - 2.0, 1e-9);
  EXPECT_EQ(s.velocity, Vec3(0, 0, -1));
}

TEST(KinematicBody, PushesADynamicBoxAndIsNotPushedBack) {
  BodyDesc paddle = kinematic_body("paddle", Shape::box(Vec3(0.1, 1.0, 0.4)));
  paddle.position = Vec3(-1.0, 0, 0.9);
  auto scene = scene_of({ground(), paddle, box_at("box", Vec3(0, 0, 1.0))});
  World world(scene);
  const BodyId p = world.body("paddle");
  const BodyId box = world.body("box");
  world.step(30);  // the box settles
  const Real speed = 1.0;
  const Real dt = scene->world.dt;
  for (int k = 0; k < 150; ++k) {
    const Vec3 at = world.body_state(p).position + Vec3(speed * dt, 0, 0);
    world.set_kinematic_target(p, at, Quat::Identity());
    world.step();
    ASSERT_EQ(world.body_state(p).position, at);
  }
  // The paddle moved 2.5 m; the box's near face (0.5 m from its centre) stays ahead of the
  // paddle's face (0.1 m from its centre), so the box moved about 2.5 - 1 + 0.6 m.
  const BodyState b = world.body_state(box);
  const Real gap = b.position.x() - 0.5 - (world.body_state(p).position.x() + 0.1);
  EXPECT_GT(b.position.x(), 1.0);
  EXPECT_GT(gap, -0.02) << "the box was pushed through";
  EXPECT_LT(gap, 0.05) << "the box was not pushed";
  EXPECT_NEAR(b.position.z(), 1.0, 0.02) << "the box should slide on the ground";
}

TEST(KinematicBody, TargetsFromYaml) {
  const auto scene = load_scene_text(R"(
world: {gravity: [0, 0, 0]}
bodies:
  - {name: lift, kinematic: true, shape: {type: box, half_extents: [1, 1, 0.1]}}
)");
  World world(scene);
  const BodyId lift = world.body("lift");
  world.set_kinematic_target(lift, Vec3(0, 0, 1), Quat::Identity());
  world.step();
  EXPECT_EQ(world.body_state(lift).position, Vec3(0, 0, 1));
}

}  // namespace
}  // namespace tumble
