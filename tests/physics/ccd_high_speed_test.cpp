// The shipped high-speed scene (scenes/high_speed.yaml, after Jolt's HighSpeedTest): 2000
// bodies at 250 m/s inside a closed box of 0.5 m walls. In 0.6 s every body flies 150 m, more
// than the box is wide, so every body meets a wall at least once; none may leave the box. The
// same scene with `ccd: off` is run too and its escapes printed (they show the walls are thin
// enough to tunnel through); only the swept run is asserted.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/physics/scene_fixture.hpp"
#include "tests/property_scale.hpp"

namespace tumble::test {
namespace {

int scaled_steps(int steps) {
  return scaled(steps);
}

// Bodies whose centre is beyond a wall's outer face (interior half size 50 m, walls 0.5 m).
int escapes(const Simulation& world) {
  int out = 0;
  for (std::size_t i = 0; i < world.state().bodies.size(); ++i) {
    if (world.scene().bodies[i].is_static)
      continue;
    if (world.state().bodies[i].position.cwiseAbs().maxCoeff() > 50.5)
      ++out;
  }
  return out;
}

int run_and_count(CcdMode ccd, int steps, std::int64_t* stopped) {
  auto scene = std::make_shared<Scene>(*shipped_scene("high_speed.yaml"));
  scene->world.ccd = ccd;
  Simulation world(scene);
  for (int k = 0; k < steps; ++k) {
    world.step();
    if (stopped != nullptr)
      *stopped += world.last_step_statistics().stopped_bodies;
  }
  return escapes(world);
}

TEST(HighSpeedScene, NoBodyLeavesTheClosedBox) {
  const int steps = scaled_steps(36);
  std::int64_t stopped = 0;
  const int swept = run_and_count(CcdMode::automatic, steps, &stopped);
  const int unswept = run_and_count(CcdMode::off, steps, nullptr);
  std::printf(
      "high_speed.yaml, %d steps: %d escaped with ccd (%lld stops at a time of impact), "
      "%d escaped with ccd: off\n",
      steps, swept, static_cast<long long>(stopped), unswept);
  EXPECT_EQ(swept, 0);
  EXPECT_GT(stopped, 0);
}

}  // namespace
}  // namespace tumble::test
