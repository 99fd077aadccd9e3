// Forces, torques and impulses through tumble::World against the integrator's discrete solution
// (symplectic Euler per substep: v += h a, then x += h v) and against r x F.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/simulation.hpp"
#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

using testing::box_at;
using testing::scene_of;

Real relative(const Vec3& got, const Vec3& want) {
  return (got - want).norm() / std::max(want.norm(), Real(1e-300));
}

TEST(WorldForces, ConstantForceFollowsTheDiscreteSolution) {
  auto scene = scene_of({box_at("box", Vec3(0, 0, 10))});
  World world(scene);
  const BodyId box = world.body("box");
  const Real m = scene->bodies[0].mass;
  const Vec3 force(3.5, -2.0, 40.0);
  const Vec3 g = scene->world.gravity;
  const int substeps = scene->world.substeps;
  const Real h = scene->world.dt / substeps;
  Vec3 x(0, 0, 10), v = Vec3::Zero();
  for (int step = 0; step < 120; ++step) {
    world.add_force(box, force);
    world.step();
    const Vec3 a = g + force * (1 / m);
    for (int s = 0; s < substeps; ++s) {
      v += a * h;
      x += v * h;
    }
    const BodyState state = world.body_state(box);
    ASSERT_LE(relative(state.velocity, v), 1e-12) << "step " << step;
    ASSERT_LE(relative(state.position, x), 1e-12) << "step " << step;
  }
}

TEST(WorldForces, ForcesActForOneStepOnly) {
  auto scene = scene_of({box_at("box", Vec3::Zero())}, Vec3::Zero());
  World world(scene);
  const BodyId box = world.body("box");
  world.add_force(box, Vec3(10, 0, 0));
  world.add_force(box, Vec3(0, 5, 0));  // forces add up
  world.step();
  const Vec3 after_one = world.body_state(box).velocity;
  const Real m = scene->bodies[0].mass;
  EXPECT_LE(relative(after_one, Vec3(10, 5, 0) * (scene->world.dt / m)), 1e-14);
  world.step();
  EXPECT_EQ(world.body_state(box).velocity, after_one);
}

TEST(WorldForces, OffsetForceTurnsTheBodyByRCrossF) {
  // A sphere has no gyroscopic term: the angular velocity is dt I^-1 (r x F) exactly.
  BodyDesc ball = dynamic_body("ball", Shape::sphere(0.5));
  auto scene = scene_of({ball}, Vec3::Zero());
  World world(scene);
  const BodyId id = world.body("ball");
  const Vec3 force(0, 8, 0);
  const Vec3 point(0.3, 0, 0.2);
  world.add_force_at(id, force, point);
  world.step();
  const Real m = scene->bodies[0].mass;
  const Real moment = scene->bodies[0].inertia(0, 0);
  const Real dt = scene->world.dt;
  const BodyState s = world.body_state(id);
  EXPECT_LE(relative(s.velocity, force * (dt / m)), 1e-12);
  EXPECT_LE(relative(s.angular_velocity, point.cross(force) * (dt / moment)), 1e-12);
}

TEST(WorldForces, TorqueOnABoxMatchesTheSubstepRecurrence) {
  // About a principal axis a box turns without gyroscopic coupling: w = dt tau / I_zz.
  auto scene = scene_of({box_at("box", Vec3::Zero(), 0.3)}, Vec3::Zero());
  World world(scene);
  const BodyId box = world.body("box");
  const Vec3 torque(0, 0, 2.5);
  world.add_torque(box, torque);
  world.step();
  const Real izz = scene->bodies[0].inertia(2, 2);
  EXPECT_LE(relative(world.body_state(box).angular_velocity, torque * (scene->world.dt / izz)),
            1e-12);
}

TEST(WorldForces, ImpulseChangesVelocityAtOnce) {
  auto scene = scene_of({box_at("box", Vec3(1, 2, 3))}, Vec3::Zero());
  World world(scene);
  const BodyId box = world.body("box");
  const Vec3 impulse(0, 0, 4);
  const Vec3 point(1.5, 2, 3);  // half a metre along x from the centre
  world.apply_impulse(box, impulse, point);
  const Real m = scene->bodies[0].mass;
  const Real iyy = scene->bodies[0].inertia(1, 1);
  const BodyState s = world.body_state(box);
  EXPECT_LE(relative(s.velocity, impulse / m), 1e-15);
  EXPECT_LE(relative(s.angular_velocity, Vec3(0.5, 0, 0).cross(impulse) / iyy), 1e-14);
}

TEST(WorldForces, SetVelocityAndPose) {
  auto scene = scene_of({box_at("box", Vec3::Zero())}, Vec3::Zero());
  World world(scene);
  const BodyId box = world.body("box");
  world.set_velocity(box, Vec3(1, 0, 0), Vec3(0, 0, 2));
  world.set_pose(box, Vec3(5, 5, 5), Quat::Identity());
  EXPECT_EQ(world.body_state(box).position, Vec3(5, 5, 5));
  world.step();
  EXPECT_NEAR(world.body_state(box).position.x(), 5 + scene->world.dt, 1e-12);
  EXPECT_NEAR(world.body_state(box).angular_velocity.z(), 2, 1e-9);
}

TEST(WorldForces, AForceWakesASleepingBody) {
  auto scene = scene_of({testing::ground(), box_at("box", Vec3(0, 0, 1.0))});
  scene->world.sleeping = true;
  World world(scene);
  const BodyId box = world.body("box");
  world.step(180);
  ASSERT_NE(world.simulation().state().asleep[std::size_t(box.index)], 0) << "did not fall asleep";
  world.add_force(box, Vec3(0, 0, 400));
  world.step();
  EXPECT_EQ(world.simulation().state().asleep[std::size_t(box.index)], 0);
  EXPECT_GT(world.body_state(box).velocity.z(), 0);
}

}  // namespace
}  // namespace tumble
