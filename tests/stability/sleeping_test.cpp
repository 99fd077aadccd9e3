// Sleeping and islands (WorldSettings::sleeping): resting islands fall asleep at rest, a body
// landing on a sleeping island wakes that island and no other, and the sleep state is part of
// the State (hash, copy, replay).
#include <gtest/gtest.h>

#include <string>

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

// A tower of `count` unit boxes of 1 kg, b0 at the bottom, as YAML lines of `bodies:`.
std::string tower_of_boxes(int count) {
  std::string bodies;
  for (int k = 0; k < count; ++k)
    bodies += "  - {name: b" + std::to_string(k) +
              ", shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [0, 0, " +
              std::to_string(0.5 + k) + "], mass: 1}\n";
  return bodies;
}

// A sleeping pair keeps the impulses it fell asleep with (State::sleeping_contacts), and a woken
// island warm-starts from them: a woken tower of boxes then holds nearly still, where the same
// tower woken with no impulses (the state's sleeping impulses cleared) first sags.
TEST(Sleeping, AWokenIslandStartsFromTheImpulsesItSleptWith) {
  const std::string bodies = tower_of_boxes(8);
  for (SolverType solver : {SolverType::impulse, SolverType::penalty}) {
    const char* label = solver_label(solver);
    const auto scene = sleeping_scene(bodies, solver);
    const int bottom = scene->find_body("b0");
    const int floor = scene->find_body("floor");
    Simulation world(scene);
    for (int k = 0; k < 240 && world.state().asleep[std::size_t(bottom)] == 0; ++k)
      world.step();
    for (int k = 0; k < 10; ++k)
      world.step();
    ASSERT_NE(world.state().asleep[std::size_t(bottom)], 0) << label << ": the tower never slept";
    const State slept = world.state();
    // Every touching pair is set aside, none is left in the solver's cache.
    EXPECT_EQ(slept.sleeping_contacts.size(), 8u) << label;
    EXPECT_TRUE(slept.contacts.empty()) << label;
    if (solver == SolverType::impulse) {
      // The floor holds the tower's weight over a step.
      for (const CachedManifold& m : slept.sleeping_contacts) {
        if (std::min(m.body_a, m.body_b) != std::min(bottom, floor) ||
            std::max(m.body_a, m.body_b) != std::max(bottom, floor))
          continue;
        Real normal = 0;
        for (int k = 0; k < m.count; ++k)
          normal += m.points[std::size_t(k)].normal_impulse;
        const Real weight = 8 * 9.81 * scene->world.dt;
        EXPECT_NEAR(normal, weight, 0.05 * weight) << label;
      }
    }
    // Woken, warm and cold: the sum of the boxes' speeds after one step.
    const auto speed_after_waking = [&](const State& from) {
      Simulation woken(scene);
      woken.set_state(from);
      woken.wake(bottom);
      woken.step();
      Real speed = 0;
      for (const BodyState& b : woken.state().bodies)
        speed += b.velocity.norm();
      EXPECT_EQ(woken.state().asleep[std::size_t(bottom)], 0) << label;
      return speed;
    };
    State cold = slept;
    cold.sleeping_contacts.clear();
    const Real warm = speed_after_waking(slept);
    const Real cold_speed = speed_after_waking(cold);
    EXPECT_LT(warm, 0.5 * cold_speed)
        << label << ": warm " << warm << " m/s, cold " << cold_speed << " m/s";
  }
}

// A sleeping body taken out of a sleeping tower (removed, or moved away) takes its pairs out of
// the sleep records, and what rested on it wakes and falls.
TEST(Sleeping, ABodyTakenOutOfASleepingTowerLeavesNoSleepRecordAndWhatRestedOnItFalls) {
  const std::string bodies = tower_of_boxes(4);
  const auto scene = sleeping_scene(bodies, SolverType::impulse);
  const int second = scene->find_body("b1");
  const int top = scene->find_body("b3");
  for (const bool remove : {true, false}) {
    Simulation world(scene);
    for (int k = 0; k < 120; ++k)
      world.step();
    ASSERT_NE(world.state().asleep[std::size_t(top)], 0) << "the tower never slept";
    ASSERT_FALSE(world.state().resting_touches.empty());
    ASSERT_FALSE(world.state().sleeping_contacts.empty());
    const Real top_before = world.state().bodies[std::size_t(top)].position.z();
    if (remove)
      world.remove_body(second);
    else
      world.teleport(second, Vec3(10, 0, 0.5), Quat::Identity());
    const auto involves = [&](const auto& entry) {
      return entry.body_a == second || entry.body_b == second;
    };
    for (const RestingTouch& t : world.state().resting_touches)
      EXPECT_FALSE(involves(t)) << (remove ? "removed" : "moved");
    for (const CachedManifold& m : world.state().sleeping_contacts)
      EXPECT_FALSE(involves(m)) << (remove ? "removed" : "moved");
    for (int k = 0; k < 30; ++k)
      world.step();
    // The two boxes above fell by about the removed box's height.
    EXPECT_NEAR(world.state().bodies[std::size_t(top)].position.z(), top_before - 1, 0.05)
        << (remove ? "removed" : "moved");
  }
}

}  // namespace
}  // namespace tumble::test
