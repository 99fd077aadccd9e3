// Simulation::teleport drops the warm-start cache of the moved body's pairs, whose cached contacts
// belong to the old pose: the step after a teleport is the step a fresh world takes from the same
// poses and velocities.
#include <gtest/gtest.h>

#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble::test {
namespace {

constexpr const char* kScene = R"(
world: {dt: 0.01}
bodies:
  - {name: floor, shape: {type: plane}, static: true, orientation: [0.9987502603949663, 0.04997916927067833, 0, 0]}
  - {name: box, shape: {type: box, half_extents: [0.5, 0.4, 0.3]}, position: [0, 0, 0.3], mass: 2}
  - {name: ball, shape: {type: sphere, radius: 0.3}, position: [3, 0, 0.3], mass: 1}
)";

TEST(Teleport, DropsTheMovedBodysCacheAndStepsLikeAFreshWorld) {
  auto scene = std::make_shared<const Scene>(load_scene_string(kScene, "teleport.yaml"));
  Simulation world(scene);
  for (int i = 0; i < 100; ++i)
    world.step();
  const auto pairs_with = [&](int body) {
    int n = 0;
    for (const CachedManifold& m : world.state().contacts)
      n += m.body_a == body || m.body_b == body;
    return n;
  };
  ASSERT_GT(pairs_with(1), 0);  // the box rests on the floor: warm-start entries exist
  ASSERT_GT(pairs_with(2), 0);
  // Teleport the box to a tilted pose far away, just touching the floor with one edge. The
  // floor is an incline of 0.1 rad, so that the resting box's cache carries friction as well.
  const Quat floor_tilt = scene->bodies[0].orientation;
  const Quat tilt = floor_tilt * Quat(Eigen::AngleAxis<Real>(0.3, Vec3::UnitX()));
  const Vec3 target = floor_tilt * Vec3(-5, 4, 0.3 * std::cos(0.3) + 0.4 * std::sin(0.3) - 1e-3);
  // The same move without dropping the cache (what a bare set_state of edited poses does).
  State stale_state = world.state();
  stale_state.bodies[1].position = target;
  stale_state.bodies[1].orientation = tilt;
  Simulation stale(scene);
  stale.set_state(stale_state);
  world.teleport(1, target, tilt);
  EXPECT_EQ(pairs_with(1), 0);
  EXPECT_GT(pairs_with(2), 0);  // the ball's pair is untouched

  // A fresh world with the box already there (same velocities, the ball's cache empty too):
  // the box's next step is the same, since its pairs start cold in both.
  Scene fresh_scene = *scene;
  fresh_scene.bodies[1].position = target;
  fresh_scene.bodies[1].orientation = tilt;
  fresh_scene.bodies[1].velocity = world.state().bodies[1].velocity;
  fresh_scene.bodies[1].angular_velocity = world.state().bodies[1].angular_velocity;
  Simulation fresh(std::make_shared<const Scene>(fresh_scene));
  world.step();
  fresh.step();
  stale.step();
  const BodyState& a = world.state().bodies[1];
  const BodyState& b = fresh.state().bodies[1];
  // Equal up to rounding: the two worlds' histories differ in per-body integrator carries
  // (the gyroscopic term), which touch the last bits only.
  EXPECT_LT((a.position - b.position).norm(), 1e-12);
  EXPECT_LT((a.velocity - b.velocity).norm(), 1e-12);
  EXPECT_LT((a.angular_velocity - b.angular_velocity).norm(), 1e-12);
  // With the stale cache, last step's resting impulses kick the box: the test can tell.
  EXPECT_GT((stale.state().bodies[1].velocity - b.velocity).norm(), 1e-6);
}

}  // namespace
}  // namespace tumble::test
