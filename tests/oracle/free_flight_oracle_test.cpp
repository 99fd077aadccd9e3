// Free flight against Bullet: with no contact both engines integrate the centre of mass by
// semi-implicit Euler (v += h g, x += h v), so the paths must agree to rounding (1e-9
// relative), whatever the bodies' shapes and spins.
#include <gtest/gtest.h>

#include "apps/compare_command.hpp"
#include "oracle_fixture.hpp"

namespace tumble {
namespace {

TEST(FreeFlightOracle, ShippedSceneAgreesToRounding) {
  auto scene = test::oracle_scene("free_flight.yaml");
  const app::CompareResult r =
      app::compare_scene(scene, app::scene_steps(*scene), app::CompareMode::paths, 50);
  EXPECT_FALSE(r.chaotic);
  EXPECT_LE(r.max_relative_position_error, 1e-9);
  EXPECT_LE(r.max_orientation_error, 1e-12);
}

// Several shapes thrown with spin, with substeps: the centre of mass still follows the same
// discrete parabola in both engines; orientations are compared in the rotation test.
TEST(FreeFlightOracle, SpinningShapesWithSubstepsAgreeToRounding) {
  auto scene = std::make_shared<const Scene>(load_scene_string(R"(
world: {dt: 0.01, steps: 300, substeps: 3}
bodies:
  - {name: ball, shape: {type: sphere, radius: 0.3}, position: [0, 0, 5], velocity: [2, -1, 9],
     angular_velocity: [1, 2, 3], mass: 2}
  - {name: crate, shape: {type: box, half_extents: [0.2, 0.5, 0.9]}, position: [10, 0, 5],
     velocity: [-3, 0.5, 4], angular_velocity: [0.3, -4, 1], density: 300}
  - {name: pill, shape: {type: capsule, radius: 0.2, half_length: 0.6}, position: [0, 10, 5],
     velocity: [0, -2, 12], angular_velocity: [5, 0, 0.5], mass: 0.7}
)",
                                                               "thrown"));
  Real max_relative = 0;
  test::lockstep(scene, 300, [&](std::int64_t, const Simulation& world, const app::BulletWorld& b) {
    for (int i = 0; i < 3; ++i) {
      const Vec3 x = world.state().bodies[i].position;
      const Vec3 y = b.body(i).position;
      const Real travelled = (y - scene->bodies[i].position).norm();
      if (travelled > 0)
        max_relative = std::max(max_relative, (x - y).norm() / travelled);
      // Velocities too: both add h g per internal step.
      EXPECT_LE((world.state().bodies[i].velocity - b.body(i).velocity).norm(), 1e-9);
    }
  });
  EXPECT_LE(max_relative, 1e-9);
}

}  // namespace
}  // namespace tumble
