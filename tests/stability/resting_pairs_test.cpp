// Resting pairs (State::resting_touches): a pair of two sleeping (or static) bodies is not
// collided again while nothing awake meets its island; the narrow phase takes whether it touches
// from the last phase that collided it. The oracle is the same world made to collide every pair:
// its state copied over at each step with the sleeping bodies marked as just fallen asleep
// (asleep = 1), which puts them through the narrow phase. The bodies must not differ by a bit.
#include <gtest/gtest.h>

#include <string>

#include "engine/simulation.hpp"
#include "tests/stability/stability_run.hpp"

namespace tumble::test {
namespace {

// A pyramid of boxes (base 4, 2 cm apart sideways), a sphere on a box, a lone box, all resting on
// a floor; a box dropped from 22 m onto the pyramid's top, which lands after the pyramid sleeps
// and wakes its island; a sphere dropped from 30 m beside the lone box, which wakes nothing.
std::shared_ptr<const Scene> resting_scene(SolverType solver) {
  std::string bodies =
      "  - {name: drop, shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [0.1, 0, "
      "22], mass: 1}\n"
      "  - {name: ball_drop, shape: {type: sphere, radius: 0.3}, position: [8, 2, 30], mass: 1}\n"
      "  - {name: plinth, shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [-8, 0, "
      "0.5], mass: 2}\n"
      "  - {name: ball, shape: {type: sphere, radius: 0.4}, position: [-8, 0, 1.4], mass: 1}\n"
      "  - {name: lone, shape: {type: box, half_extents: [0.4, 0.3, 0.2]}, position: [8, 0, 0.2], "
      "mass: 1}\n";
  int index = 0;
  for (int layer = 0; layer < 4; ++layer) {
    const int count = 4 - layer;
    for (int k = 0; k < count; ++k) {
      const double x = (k - 0.5 * (count - 1)) * 1.02;
      bodies += "  - {name: p" + std::to_string(index++) +
                ", shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [" +
                std::to_string(x) + ", 0, " + std::to_string(0.5 + layer) + "], mass: 1}\n";
    }
  }
  return sleeping_scene(bodies, solver);
}

bool same_bits(const BodyState& a, const BodyState& b) {
  return a.position == b.position && a.orientation.coeffs() == b.orientation.coeffs() &&
         a.velocity == b.velocity && a.angular_velocity == b.angular_velocity;
}

TEST(RestingPairs, TakingRestingPairsFromTheLastNarrowPhaseChangesNoBit) {
  for (const SolverType solver : {SolverType::impulse, SolverType::penalty}) {
    const auto scene = resting_scene(solver);
    const char* label = solver_label(solver);
    Simulation world(scene);
    Simulation collides_all(scene);
    const int top = scene->find_body("p9");
    bool top_slept = false, top_woke = false;
    std::int64_t resting_pairs = 0, oracle_resting_pairs = 0;
    for (int k = 0; k < 420; ++k) {
      State every_pair = world.state();
      for (std::uint8_t& asleep : every_pair.asleep)
        asleep = asleep != 0 ? 1 : 0;
      collides_all.set_state(every_pair);
      world.step();
      collides_all.step();
      resting_pairs += world.last_step_statistics().resting_pairs;
      oracle_resting_pairs += collides_all.last_step_statistics().resting_pairs;
      const State& s = world.state();
      const State& o = collides_all.state();
      for (std::size_t i = 0; i < s.bodies.size(); ++i) {
        ASSERT_TRUE(same_bits(s.bodies[i], o.bodies[i]))
            << label << ": body " << scene->bodies[i].name << " at step " << k + 1;
        ASSERT_EQ(s.asleep[i] != 0, o.asleep[i] != 0)
            << label << ": body " << scene->bodies[i].name << " at step " << k + 1;
      }
      if (s.asleep[std::size_t(top)] != 0)
        top_slept = true;
      else if (top_slept)
        top_woke = true;
    }
    // The run went through what it is meant to test.
    EXPECT_GT(resting_pairs, 1000) << label;
    EXPECT_EQ(oracle_resting_pairs, 0) << label;
    EXPECT_TRUE(top_slept) << label;
    EXPECT_TRUE(top_woke) << label << ": the dropped box must wake the pyramid";
    // The dropped box rests on the pyramid's top, which still stands.
    const State& s = world.state();
    EXPECT_NEAR(s.bodies[std::size_t(scene->find_body("drop"))].position.z(), 4.5, 0.02) << label;
    EXPECT_NEAR(s.bodies[std::size_t(top)].position.z(), 3.5, 0.02) << label;
  }
}

// Once everything sleeps, the narrow phase collides no pair at all.
TEST(RestingPairs, ASleepingWorldCollidesNoPair) {
  auto scene = std::make_shared<Scene>(*resting_scene(SolverType::impulse));
  // Without the dropped bodies, everything falls asleep where it rests.
  for (const char* name : {"drop", "ball_drop"})
    scene->bodies.erase(scene->bodies.begin() + scene->find_body(name));
  Simulation world(scene);
  int all_asleep_at = -1;
  for (int k = 0; k < 600 && all_asleep_at < 0; ++k) {
    world.step();
    bool all = true;
    for (std::size_t i = 0; i < scene->bodies.size(); ++i)
      all = all && (scene->bodies[i].is_static || world.state().asleep[i] != 0);
    if (all)
      all_asleep_at = k;
  }
  ASSERT_GE(all_asleep_at, 0) << "the resting bodies never all slept";
  world.step();  // their contacts are found once more where they now rest
  const State before = world.state();
  for (int k = 0; k < 30; ++k) {
    world.step();
    const StepStatistics& s = world.last_step_statistics();
    ASSERT_GT(s.candidate_pairs, 10);
    EXPECT_EQ(s.resting_pairs, s.candidate_pairs) << "step " << k;
    EXPECT_EQ(s.recomputed_pairs + s.recycled_pairs, 0) << "step " << k;
  }
  for (std::size_t i = 0; i < scene->bodies.size(); ++i)
    EXPECT_TRUE(same_bits(world.state().bodies[i], before.bodies[i])) << scene->bodies[i].name;
}

}  // namespace
}  // namespace tumble::test
