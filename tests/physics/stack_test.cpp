#include <gtest/gtest.h>

#include "collision/broad_phase/broad_phase_factory.hpp"
#include "tests/physics/scene_fixture.hpp"

namespace tumble::test {
namespace {

// A 10-box stack stands for 10 s: the top box drifts less than 5 mm.
TEST(ShippedScenes, TenBoxStackStands) {
  const auto scene = shipped_scene("stack10.yaml");
  Simulation world(scene);
  const int top = body_index(*scene, "box9");
  const Vec3 start = world.state().bodies[top].position;
  const std::int64_t steps = std::llround(10.0 / scene->world.dt);
  Real worst = 0;
  for (std::int64_t k = 0; k < steps; ++k) {
    world.step();
    worst = std::max(worst, (world.state().bodies[top].position - start).norm());
  }
  EXPECT_LT(worst, 5e-3);
  for (const BodyState& b : world.state().bodies) {
    EXPECT_TRUE(b.position.allFinite() && b.velocity.allFinite());
  }
}

// The same scene stepped twice from the same state gives the same hash at every step, and a
// reset world replays the first run exactly.
TEST(Determinism, SameSceneSameHashes) {
  const auto scene = shipped_scene("demo.yaml");
  Simulation first(scene);
  Simulation second(scene);
  std::vector<std::uint64_t> hashes;
  for (int k = 0; k < 300; ++k) {
    first.step();
    second.step();
    const std::uint64_t h = state_hash(first.state());
    ASSERT_EQ(h, state_hash(second.state())) << "step " << k;
    ASSERT_EQ(h, first.state_hash()) << "the world reports its hash";
    hashes.push_back(h);
  }
  first.reset();
  for (int k = 0; k < 300; ++k) {
    first.step();
    ASSERT_EQ(state_hash(first.state()), hashes[k]) << "after reset, step " << k;
  }
}

// Every broad-phase structure reports the same pairs in the same order, so the choice of
// structure never changes a simulation: the demo gives the same hash at every step with each.
TEST(Determinism, EveryBroadPhaseGivesTheSameSimulation) {
  const auto base = shipped_scene("demo.yaml");
  std::vector<std::uint64_t> reference;
  for (BroadPhaseType type : concrete_broad_phases()) {
    auto scene = std::make_shared<Scene>(*base);
    scene->world.broadphase = type;
    Simulation world(scene);
    ASSERT_EQ(world.broad_phase_type(), type);
    for (int k = 0; k < 240; ++k) {
      world.step();
      const std::uint64_t h = state_hash(world.state());
      if (reference.size() <= static_cast<std::size_t>(k)) {
        reference.push_back(h);
      } else {
        ASSERT_EQ(h, reference[k]) << broad_phase_name(type) << " differs at step " << k;
      }
    }
  }
}

// A copied state continues exactly as the original (the warm-start cache is part of it).
TEST(Determinism, RestoredStateContinuesIdentically) {
  const auto scene = shipped_scene("stack10.yaml");
  Simulation world(scene);
  for (int k = 0; k < 50; ++k)
    world.step();
  const State snapshot = world.state();
  for (int k = 0; k < 50; ++k)
    world.step();
  const std::uint64_t expected = state_hash(world.state());
  Simulation other(scene);
  other.set_state(snapshot);
  for (int k = 0; k < 50; ++k)
    other.step();
  EXPECT_EQ(state_hash(other.state()), expected);
}

}  // namespace
}  // namespace tumble::test
