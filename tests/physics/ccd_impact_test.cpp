// What the sweep does to a body it stops, and to a body it must leave alone:
//   - a body stopped at a time of impact has its approach reflected there by the pair's
//     restitution (the analytic bounce: v_n' = -e v_n, the tangential part kept), once;
//   - a box sliding fast over a mesh floor it rests on is not stopped: frictionless, it travels
//     v t exactly as over a plane (the mesh once counted as zero thickness, and the sweep held
//     such a box a hair above the floor every step).
#include <gtest/gtest.h>

#include <memory>

#include "collision/shapes/triangle_mesh.hpp"
#include "engine/simulation.hpp"
#include "tests/physics/body_builders.hpp"

namespace tumble::test {
namespace {

Scene empty_scene(Real restitution) {
  return frictionless_space("ccd_impact_test", restitution);
}

TEST(CcdImpact, AStoppedBodyBouncesByTheRestitution) {
  for (const Real e : {0.0, 0.5, 1.0}) {
    Scene s = empty_scene(e);
    // A 1 cm wall at x = 0 and a 1 cm sphere 2 m before it at 600 m/s along x (10 m a step),
    // with a sideways speed the frictionless wall keeps.
    s.bodies.push_back(static_body("wall", Shape::box(Vec3(0.005, 2, 2)), Vec3::Zero()));
    s.bodies.push_back(
        dynamic_body("bullet", Shape::sphere(0.005), Vec3(-2, 0, 0), Vec3(600, 3, 0), 2));
    Simulation world(std::make_shared<const Scene>(std::move(s)));
    world.step();
    EXPECT_EQ(world.last_step_statistics().stopped_bodies, 1) << "e = " << e;
    const BodyState& b = world.state().bodies[1];
    EXPECT_LT(b.position.x(), -0.005) << "e = " << e;
    EXPECT_NEAR(b.velocity.x(), -e * 600, 1e-9 * 600) << "e = " << e;
    EXPECT_NEAR(b.velocity.y(), 3, 1e-9) << "e = " << e;
    // Once: the next steps' contacts find it leaving, or resting with no approach left.
    for (int k = 0; k < 5; ++k)
      world.step();
    EXPECT_NEAR(world.state().bodies[1].velocity.x(), -e * 600, 1e-9 * 600) << "e = " << e;
    EXPECT_LT(world.state().bodies[1].position.x(), -0.005) << "e = " << e;
  }
}

TEST(CcdImpact, AStoppedBodyAndADynamicPartnerShareTheImpulseByMass) {
  Scene s = empty_scene(0);
  // A fast 2 kg sphere into a resting 6 kg box: a plastic impact along x leaves both at the
  // common speed 2 * 600 / 8 = 150 m/s, the momentum kept.
  s.bodies.push_back(
      dynamic_body("bullet", Shape::sphere(0.005), Vec3(-2, 0, 0), Vec3(600, 0, 0), 2));
  BodyDesc block =
      dynamic_body("block", Shape::box(Vec3(0.005, 0.5, 0.5)), Vec3::Zero(), Vec3::Zero(), 6);
  s.bodies.push_back(block);
  Simulation world(std::make_shared<const Scene>(std::move(s)));
  world.step();
  ASSERT_EQ(world.last_step_statistics().stopped_bodies, 1);
  const Real v_bullet = world.state().bodies[0].velocity.x();
  const Real v_block = world.state().bodies[1].velocity.x();
  EXPECT_NEAR(v_bullet, 150, 1e-9 * 600);
  EXPECT_NEAR(v_block, 150, 1e-9 * 600);
  EXPECT_NEAR(2 * v_bullet + 6 * v_block, 2 * 600, 1e-9 * 1200);
}

TEST(CcdImpact, ABoxSlidingFastOverAMeshFloorIsNotStopped) {
  // Two triangles 400 m square at z = 0; a 1 m box resting on them (its face 1 mm up, inside
  // the contact margin), sliding at 40 m/s: 0.67 m a step, more than half its thickness, so the
  // sweep takes it. Frictionless and without gravity, it must travel 40 m/s * t exactly.
  Scene s = empty_scene(0);
  auto floor = std::make_shared<const TriangleMesh>(TriangleMesh::build(
      {Vec3(-200, -200, 0), Vec3(200, -200, 0), Vec3(200, 200, 0), Vec3(-200, 200, 0)},
      {{0, 1, 2}, {0, 2, 3}}));
  s.bodies.push_back(static_body("floor", Shape::triangle_mesh(floor), Vec3::Zero()));
  s.bodies.push_back(
      dynamic_body("box", Shape::box(Vec3(0.5, 0.5, 0.5)), Vec3(-50, 3, 0.501), Vec3(40, 0, 0), 2));
  Simulation world(std::make_shared<const Scene>(std::move(s)));
  std::int64_t swept = 0;
  for (int k = 0; k < 60; ++k) {
    world.step();
    swept += world.last_step_statistics().swept_bodies;
    EXPECT_EQ(world.last_step_statistics().stopped_bodies, 0) << "step " << k;
  }
  EXPECT_EQ(swept, 60);  // the sweep ran every step, and let the box go
  const BodyState& b = world.state().bodies[1];
  EXPECT_NEAR(b.position.x(), -50 + 40 * 60 * world.scene().world.dt, 1e-9);
  EXPECT_NEAR(b.velocity.x(), 40, 1e-9);
  EXPECT_NEAR(b.position.z(), 0.501, 1e-6);
}

}  // namespace
}  // namespace tumble::test
