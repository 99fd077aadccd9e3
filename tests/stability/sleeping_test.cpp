// Sleeping and islands (WorldSettings::sleeping): resting islands fall asleep at rest, a body
// landing on a sleeping island wakes that island and no other, and the sleep state is part of
// the State (hash, copy, replay).
#include <gtest/gtest.h>

#include "tests/stability/stability_run.hpp"

namespace tumble::test {
namespace {

TEST(Sleeping, RestingIslandsSleepAndOnlyTheTouchedOneWakes) {
  for (SolverType solver : {SolverType::impulse, SolverType::penalty}) {
    const auto scene = stability_scene("sleeping_drop.yaml", solver);
    Simulation world(scene);
    const int a = scene->find_body("a");
    const int b = scene->find_body("b");
    const int c = scene->find_body("c");
    bool a_slept = false;
    bool a_woke_after_sleeping = false;
    bool b_slept_in_flight = false;
    std::int64_t c_asleep_from = -1;
    bool c_woke = false;
    Vec3 c_asleep_at = Vec3::Zero();
    const std::int64_t steps = std::llround(scene->world.duration / scene->world.dt);
    for (std::int64_t k = 0; k < steps; ++k) {
      world.step();
      const State& s = world.state();
      if (s.asleep[a] != 0) {
        a_slept = true;
        EXPECT_EQ(s.bodies[a].velocity, Vec3::Zero());
        EXPECT_EQ(s.bodies[a].angular_velocity, Vec3::Zero());
      } else if (a_slept) {
        a_woke_after_sleeping = true;
      }
      if (s.asleep[b] != 0 && s.bodies[b].position.z() > 2)
        b_slept_in_flight = true;
      if (s.asleep[c] != 0 && c_asleep_from < 0) {
        c_asleep_from = k;
        c_asleep_at = s.bodies[c].position;
      }
      if (c_asleep_from >= 0) {
        if (s.asleep[c] == 0)
          c_woke = true;
        EXPECT_EQ(s.bodies[c].position, c_asleep_at) << "a sleeping body does not move";
      }
    }
    const char* label = solver_label(solver);
    EXPECT_TRUE(a_slept) << label;
    EXPECT_TRUE(a_woke_after_sleeping) << label << ": b landing on a must wake it";
    EXPECT_FALSE(b_slept_in_flight) << label;
    ASSERT_GE(c_asleep_from, 0) << label;
    // c rests from the start: asleep once it has been slow for sleep_time (plus settling).
    EXPECT_LE(c_asleep_from * scene->world.dt, scene->world.sleep_time + 0.5) << label;
    EXPECT_FALSE(c_woke) << label << ": c is its own island";
    // b ends up resting on a.
    EXPECT_NEAR(world.state().bodies[b].position.z(), 1.5, 0.01) << label;
  }
}

// With sleeping on, a copied state (with its sleep records) continues exactly as the original.
TEST(Sleeping, RestoredStateContinuesIdentically) {
  const auto scene = stability_scene("sleeping_drop.yaml", SolverType::impulse);
  Simulation world(scene);
  for (int k = 0; k < 100; ++k)  // a and c are asleep by now, b is falling
    world.step();
  ASSERT_NE(world.state().asleep[scene->find_body("c")], 0);
  const State snapshot = world.state();
  for (int k = 0; k < 100; ++k)
    world.step();
  const std::uint64_t expected = state_hash(world.state());
  Simulation other(scene);
  other.set_state(snapshot);
  for (int k = 0; k < 100; ++k)
    other.step();
  EXPECT_EQ(state_hash(other.state()), expected);
  // The sleep records are hashed: the same poses with a body awake hash differently.
  State awake = snapshot;
  awake.asleep.assign(awake.asleep.size(), 0);
  EXPECT_NE(state_hash(awake), state_hash(snapshot));
}

}  // namespace
}  // namespace tumble::test
