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

constexpr int kRow = 120;    // cubes in the row
constexpr int kMiddle = 60;  // the row's cube that carries the load

// A floor and kRow cubes of `mass` touching side by side in a row on it along x (bodies 1 to
// kRow), and one cube of `top_mass` over the middle one of them at each height in `levels`
// (counted in cubes above the row).
Scene row_of_cubes(Real mass, Real top_mass, int levels) {
  Scene s;
  s.materials.push_back(Material{"default", 0.5, 0});
  s.bodies.push_back(static_body("floor", Shape::box(Vec3(50, 50, 1)), Vec3(0, 0, -1)));
  const Shape cube = Shape::box(Vec3::Constant(kHalf));
  for (int i = 0; i < kRow; ++i) {
    s.bodies.push_back(dynamic_body("row" + std::to_string(i), cube, Vec3(2 * kHalf * i, 0, kHalf),
                                    Vec3::Zero(), mass));
  }
  for (int k = 1; k <= levels; ++k) {
    s.bodies.push_back(dynamic_body("top" + std::to_string(k), cube,
                                    Vec3(2 * kHalf * kMiddle, 0, kHalf + 2 * kHalf * k),
                                    Vec3::Zero(), top_mass));
  }
  return s;
}

// Steps `scene` `steps` times, calling watch(world) after each step; returns the most substeps
// any island took.
template <class Watch>
int most_substeps(const std::shared_ptr<const Scene>& scene, int steps, const Watch& watch) {
  Simulation world(scene);
  int most = 0;
  for (int step = 0; step < steps; ++step) {
    world.step();
    most = std::max(most, world.last_step_statistics().max_substeps);
    watch(world);
  }
  return most;
}

// A tower of twelve cubes standing on the middle one of 120 that touch side by side in a row on
// the floor: an island of some 250 contacts, of which the tower's dozen need the most substeps.
// The few the island may leave sagging beyond the tolerance must not topple it: its top moves
// less than 1 cm in 10 s, as a tower alone does (tests/stability/defaults_test.cpp).
TEST(SubstepChoice, ATowerInALargeIslandStillStands) {
  const auto scene = std::make_shared<const Scene>(row_of_cubes(1, 1, 12));
  const std::size_t top = scene->bodies.size() - 1;
  const Vec3 start = scene->bodies[top].position;
  Real drift = 0;
  const int most = most_substeps(scene, 600, [&](const Simulation& world) {
    drift = std::max(drift, (world.state().bodies[top].position - start).norm());
  });
  std::printf("[substeps] tower in a row: top moved %.3g m, substeps up to %d\n", drift, most);
  EXPECT_LT(drift, 0.01);
}

// A 250 kg cube on one of 120 cubes of 0.5 kg that touch side by side in a row on the floor:
// one contact among some 240 of the island carries 500 times the light cube's weight, and the
// island takes the substeps that keep it from sinking more than 1 cm into the light cube.
TEST(SubstepChoice, AHeavyCubeOnALightOneInALargeIslandGetsItsSubsteps) {
  const auto scene = std::make_shared<const Scene>(row_of_cubes(0.5, 250, 1));
  const int under = 1 + kMiddle;
  const int heavy = static_cast<int>(scene->bodies.size()) - 1;
  Real deepest = 0;
  const int most = most_substeps(scene, 120, [&](const Simulation& world) {
    const auto& b = world.state().bodies;
    const Real gap =
        (b[std::size_t(heavy)].position.z() - kHalf) - (b[std::size_t(under)].position.z() + kHalf);
    deepest = std::max(deepest, -gap);
  });
  EXPECT_GE(most, 32);
  EXPECT_LT(deepest, 0.01);
}

}  // namespace
}  // namespace tumble::test
