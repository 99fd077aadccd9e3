// How the world picks an island's substeps from its contacts' loads (docs/architecture.md,
// "Substeps per island") in an island of hundreds of contacts, which may leave one in a hundred
// sagging beyond the tolerance: a tall stack in it still stands, and the weight of a heavy body
// on a light one counts however large the island.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "engine/simulation.hpp"
#include "tests/physics/body_builders.hpp"

namespace tumble::test {
namespace {

constexpr Real kHalf = 0.25;  // half extent of the cubes [m]

Scene floor_scene(Real restitution) {
  Scene s;
  s.materials.push_back(Material{"default", 0.5, restitution});
  s.bodies.push_back(static_body("floor", Shape::box(Vec3(50, 50, 1)), Vec3(0, 0, -1)));
  return s;
}

// A tower of twelve cubes standing on the middle one of 120 that touch side by side in a row on
// the floor: an island of some 250 contacts, of which the tower's dozen need the most substeps.
// The few the island may leave sagging beyond the tolerance must not topple it: its top moves
// less than 1 cm in 10 s, as a tower alone does (tests/stability/defaults_test.cpp).
TEST(SubstepChoice, ATowerInALargeIslandStillStands) {
  Scene s = floor_scene(0);
  constexpr int kRow = 120;
  for (int i = 0; i < kRow; ++i) {
    s.bodies.push_back(dynamic_body("row" + std::to_string(i), Shape::box(Vec3::Constant(kHalf)),
                                    Vec3(2 * kHalf * i, 0, kHalf), Vec3::Zero(), 1));
  }
  for (int k = 1; k <= 12; ++k) {
    s.bodies.push_back(dynamic_body("tower" + std::to_string(k), Shape::box(Vec3::Constant(kHalf)),
                                    Vec3(2 * kHalf * (kRow / 2), 0, kHalf + 2 * kHalf * k),
                                    Vec3::Zero(), 1));
  }
  const auto scene = std::make_shared<const Scene>(std::move(s));
  const std::size_t top = scene->bodies.size() - 1;
  const Vec3 start = scene->bodies[top].position;
  Simulation world(scene);
  Real drift = 0;
  int most = 0;
  for (int step = 0; step < 600; ++step) {
    world.step();
    most = std::max(most, world.last_step_statistics().max_substeps);
    drift = std::max(drift, (world.state().bodies[top].position - start).norm());
  }
  std::printf("[substeps] tower in a row: top moved %.3g m, substeps up to %d\n", drift, most);
  EXPECT_LT(drift, 0.01);
}

// A 250 kg cube on one of 120 cubes of 0.5 kg that touch side by side in a row on the floor:
// one contact among some 240 of the island carries 500 times the light cube's weight, and the
// island takes the substeps that keep it from sinking more than 1 cm into the light cube.
TEST(SubstepChoice, AHeavyCubeOnALightOneInALargeIslandGetsItsSubsteps) {
  Scene s = floor_scene(0);
  constexpr int kRow = 120;
  for (int i = 0; i < kRow; ++i) {
    s.bodies.push_back(dynamic_body("light" + std::to_string(i), Shape::box(Vec3::Constant(kHalf)),
                                    Vec3(2 * kHalf * i, 0, kHalf), Vec3::Zero(), 0.5));
  }
  const int under = 1 + kRow / 2;
  const Real light_top = 2 * kHalf;
  s.bodies.push_back(dynamic_body("heavy", Shape::box(Vec3::Constant(kHalf)),
                                  Vec3(2 * kHalf * (kRow / 2), 0, light_top + kHalf), Vec3::Zero(),
                                  250));
  const auto scene = std::make_shared<const Scene>(std::move(s));
  const int heavy = static_cast<int>(scene->bodies.size()) - 1;
  Simulation world(scene);
  int most = 0;
  Real deepest = 0;
  for (int step = 0; step < 120; ++step) {
    world.step();
    most = std::max(most, world.last_step_statistics().max_substeps);
    const auto& b = world.state().bodies;
    const Real gap =
        (b[std::size_t(heavy)].position.z() - kHalf) - (b[std::size_t(under)].position.z() + kHalf);
    deepest = std::max(deepest, -gap);
  }
  EXPECT_GE(most, 32);
  EXPECT_LT(deepest, 0.01);
}

}  // namespace
}  // namespace tumble::test
