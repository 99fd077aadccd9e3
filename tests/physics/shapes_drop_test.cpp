// scenes/shapes_drop.yaml: a cylinder, a hull, a compound dumbbell and spheres dropped on a
// raised triangle-mesh platform (z = 0.3) and on the plane floor (z = 0) beside it. Over the
// scene's 3 s: no NaN, the total energy (kinetic + gravitational) never above the initial, and
// at the end every body at rest (speed under 1 cm/s at every point: |v| + |w| * reach) on the
// surface it was dropped over, its lowest point no more than 1 cm below that surface.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "collision/shapes/triangle_mesh.hpp"
#include "tests/physics/scene_fixture.hpp"

namespace tumble::test {
namespace {

// Lowest world z of a body's shape.
Real lowest_point(const Shape& shape, const BodyState& b) {
  const Vec3 down_local = b.orientation.conjugate() * Vec3(0, 0, -1);
  return (b.orientation * support(shape, down_local) + b.position).z();
}

TEST(ShapesDrop, EveryShapeComesToRestOnTheSurfaceUnderIt) {
  const auto scene = shipped_scene("shapes_drop.yaml");
  ASSERT_EQ(scene->bodies[body_index(*scene, "platform")].shape.mesh->triangle_count(), 128);
  Simulation world(scene);
  const Real e0 = world.kinetic_energy() + world.potential_energy();
  Real worst_gain = -std::numeric_limits<Real>::infinity();
  const int steps = int(std::ceil(scene->world.duration / scene->world.dt));
  bool finite = true;
  for (int i = 0; i < steps && finite; ++i) {
    world.step();
    for (const BodyState& b : world.state().bodies)
      finite = finite && b.position.allFinite() && b.velocity.allFinite() &&
               b.angular_velocity.allFinite() && b.orientation.coeffs().allFinite();
    worst_gain = std::max(worst_gain, world.kinetic_energy() + world.potential_energy() - e0);
  }
  ASSERT_TRUE(finite) << "a body's state went non-finite";
  std::printf("[ stats    ] initial energy %.6g J, largest rise above it %.3g J\n", e0, worst_gain);
  EXPECT_LE(worst_gain, 1e-9 * std::abs(e0));
  const struct {
    const char* name;
    Real surface;
  } expected[] = {{"cylinder", 0.3},        {"hull", 0.3},
                  {"dumbbell", 0.3},        {"sphere_on_mesh", 0.3},
                  {"sphere_on_plane", 0.0}, {"hull_on_plane", 0.0}};
  for (const auto& e : expected) {
    const int i = body_index(*scene, e.name);
    const BodyState& b = world.state().bodies[i];
    const Shape& shape = scene->bodies[i].shape;
    const Real speed = b.velocity.norm() + b.angular_velocity.norm() * bounding_radius(shape);
    const Real lowest = lowest_point(shape, b);
    std::printf(
        "[ stats    ] %-15s at (%.3f, %.3f, %.3f): lowest point %.4f m over a surface at "
        "%.1f m, speed %.3g m/s\n",
        e.name, b.position.x(), b.position.y(), b.position.z(), lowest, e.surface, speed);
    EXPECT_LT(speed, 0.01) << e.name;
    EXPECT_GE(lowest, e.surface - 0.01) << e.name;
    // Resting on that surface, not stuck above it (nor fallen off the platform).
    EXPECT_LE(lowest, e.surface + 0.01) << e.name;
  }
}

}  // namespace
}  // namespace tumble::test
