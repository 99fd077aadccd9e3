// The bridge's newer shapes against Bullet: a convex hull (the eight corners of a box) and an
// upright cylinder dropped on a plane, and a compound dumbbell dropped on a static triangle
// mesh. Each must come to rest at its analytic height (half the box's height, the cylinder's
// half length, the spheres' radius) in both engines, and the engines must agree on it.
// Measured: tumble rests 0.87 mm (hull), 0.66 mm (cylinder), 0.79 mm (dumbbell) deep (its soft
// contacts hold a small penetration, docs/oracle.md), Bullet within 0.005 mm; the tolerance is
// 1.5 mm.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "apps/bullet_bridge.hpp"
#include "apps/compare_command.hpp"
#include "engine/simulation.hpp"
#include "oracle_fixture.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble {
namespace {

constexpr Real kTolerance = 0.0015;  // m

struct Rest {
  Vec3 tumble_position = Vec3::Zero();
  Vec3 bullet_position = Vec3::Zero();
  Real tumble_speed = 0;
  Real bullet_speed = 0;
};

// Steps both engines to the end of the scene and returns each body's final state.
std::vector<Rest> settle(const std::shared_ptr<const Scene>& scene,
                         std::vector<std::string>& mismatches) {
  std::vector<Rest> rest(scene->bodies.size());
  Simulation world(scene);
  app::BulletWorld bullet(*scene, app::matching_bullet_settings(*scene));
  mismatches = bullet.mismatches();
  const std::int64_t steps = app::scene_steps(*scene);
  for (std::int64_t k = 0; k < steps; ++k) {
    world.step();
    bullet.step();
  }
  for (std::size_t i = 0; i < rest.size(); ++i) {
    const BodyState t = world.state().bodies[i];
    const BodyState b = bullet.body(int(i));
    rest[i] = {t.position, b.position, t.velocity.norm(), b.velocity.norm()};
  }
  return rest;
}

bool left_out(const std::vector<std::string>& mismatches) {
  for (const std::string& m : mismatches)
    if (m.find("left out of Bullet") != std::string::npos)
      return true;
  return false;
}

TEST(ShapeOracle, HullAndCylinderRestOnPlaneAtTheSameHeight) {
  const auto scene = std::make_shared<const Scene>(load_scene_string(R"(
world: {dt: 0.0166667, duration: 2.0}
bodies:
  - {name: floor, shape: {type: plane}, static: true}
  - name: crate
    shape:
      type: hull
      points: [[-0.3, -0.2, -0.15], [0.3, -0.2, -0.15], [-0.3, 0.2, -0.15], [0.3, 0.2, -0.15],
               [-0.3, -0.2, 0.15], [0.3, -0.2, 0.15], [-0.3, 0.2, 0.15], [0.3, 0.2, 0.15]]
    position: [-1, 0, 0.4]
    mass: 2
  - name: drum
    shape: {type: cylinder, radius: 0.2, half_length: 0.25}
    position: [1, 0, 0.5]
    mass: 3
)",
                                                                     "hull_cylinder_drop"));
  std::vector<std::string> mismatches;
  const std::vector<Rest> rest = settle(scene, mismatches);
  EXPECT_FALSE(left_out(mismatches));
  const Real heights[] = {0, 0.15, 0.25};
  for (int i : {1, 2}) {
    const Rest& r = rest[i];
    const Real zt = r.tumble_position.z(), zb = r.bullet_position.z();
    std::printf("body %d: rest z tumble %.6f bullet %.6f (analytic %.3f); speeds %.2e %.2e\n", i,
                zt, zb, heights[i], r.tumble_speed, r.bullet_speed);
    EXPECT_NEAR(zt, heights[i], kTolerance) << "tumble, body " << i;
    EXPECT_NEAR(zb, heights[i], kTolerance) << "Bullet, body " << i;
    EXPECT_NEAR(zt, zb, kTolerance) << "body " << i;
    EXPECT_LT(r.tumble_speed, 0.01);
    EXPECT_LT(r.bullet_speed, 0.01);
  }
}

TEST(ShapeOracle, CompoundRestsOnMeshAtTheSameHeight) {
  const auto scene = std::make_shared<const Scene>(load_scene_string(R"(
world: {dt: 0.0166667, duration: 2.0}
bodies:
  - name: floor
    shape:
      type: mesh
      vertices: [[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]]
      triangles: [[0, 1, 2], [0, 2, 3]]
    static: true
  - name: dumbbell
    shape:
      type: compound
      parts:
        - {shape: {type: sphere, radius: 0.1}, position: [-0.3, 0, 0]}
        - {shape: {type: sphere, radius: 0.1}, position: [0.3, 0, 0]}
        - {shape: {type: cylinder, radius: 0.03, half_length: 0.25}, orientation: [0.7071068, 0, 0.7071068, 0]}
    position: [0.2, 0.1, 0.4]
    mass: 1
)",
                                                                     "compound_on_mesh"));
  std::vector<std::string> mismatches;
  const std::vector<Rest> rest = settle(scene, mismatches);
  EXPECT_FALSE(left_out(mismatches));
  const Rest& r = rest[1];
  std::printf("dumbbell: rest z tumble %.6f bullet %.6f (analytic 0.100)\n", r.tumble_position.z(),
              r.bullet_position.z());
  EXPECT_NEAR(r.tumble_position.z(), 0.1, kTolerance);
  EXPECT_NEAR(r.bullet_position.z(), 0.1, kTolerance);
  EXPECT_NEAR(r.tumble_position.z(), r.bullet_position.z(), kTolerance);
}

}  // namespace
}  // namespace tumble
