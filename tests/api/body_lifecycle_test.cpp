// Adding and removing bodies between steps: ids stay valid until removed, removed ids fail
// cleanly whether or not the slot is reused, the broad phase and caches follow, and a replay of
// the same adds and removes gives the same bits.
#include <gtest/gtest.h>

#include <random>

#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

using testing::box_at;
using testing::ground;
using testing::scene_of;

TEST(BodyLifecycle, AddedBodyFallsAndRestsOnTheGround) {
  World world(scene_of({ground()}));
  const BodyId box = world.add_body(box_at("box", Vec3(0, 0, 2)));
  EXPECT_EQ(world.body("box"), box);
  world.step(120);
  EXPECT_NEAR(world.body_state(box).position.z(), 1.0, 0.01);
  EXPECT_EQ(world.body_count(), 2);
}

TEST(BodyLifecycle, RemovedIdsFailAndSlotsAreReusedWithANewGeneration) {
  World world(scene_of({ground(), box_at("a", Vec3(0, 0, 1)), box_at("b", Vec3(3, 0, 1))}));
  const BodyId a = world.body("a");
  const BodyId b = world.body("b");
  world.step();
  world.remove_body(a);
  EXPECT_FALSE(world.is_valid(a));
  EXPECT_THROW(world.body_state(a), Error);
  EXPECT_THROW(world.remove_body(a), Error);
  EXPECT_FALSE(world.find_body("a").has_value());
  EXPECT_TRUE(world.is_valid(b));
  const BodyId c = world.add_body(box_at("c", Vec3(-3, 0, 1)));
  EXPECT_EQ(c.index, a.index) << "the freed slot is reused";
  EXPECT_NE(c.generation, a.generation);
  EXPECT_THROW(world.add_force(a, Vec3(1, 0, 0)), Error);
  world.step(10);
  EXPECT_EQ(world.bodies().size(), 3u);
}

TEST(BodyLifecycle, ABoxOnARemovedBoxFalls) {
  World world(scene_of({ground(), box_at("low", Vec3(0, 0, 1)), box_at("high", Vec3(0, 0, 2))}));
  world.step(60);
  const BodyId high = world.body("high");
  EXPECT_NEAR(world.body_state(high).position.z(), 2.0, 0.01);
  world.remove_body(world.body("low"));
  world.step(60);
  EXPECT_NEAR(world.body_state(high).position.z(), 1.0, 0.01);
  for (const ContactReport& r : world.contact_reports()) {
    EXPECT_TRUE(world.is_valid(r.body_a));
    EXPECT_TRUE(world.is_valid(r.body_b));
  }
}

std::vector<std::uint64_t> run_with_adds_and_removes(int threads) {
  World world(scene_of({ground()}));
  world.set_threads(threads);
  std::mt19937 random(7);
  std::uniform_real_distribution<Real> across(-3, 3);
  std::vector<BodyId> alive;
  std::vector<std::uint64_t> hashes;
  for (int step = 0; step < 240; ++step) {
    if (step % 6 == 0) {
      BodyDesc d = box_at("", Vec3(across(random), across(random), 3), 0.3);
      alive.push_back(world.add_body(d));
    }
    if (step % 15 == 14 && !alive.empty()) {
      const std::size_t k = random() % alive.size();
      world.remove_body(alive[k]);
      alive.erase(alive.begin() + std::ptrdiff_t(k));
    }
    world.step();
    hashes.push_back(world.state_hash());
  }
  return hashes;
}

TEST(BodyLifecycle, ReplayIsBitIdentical) {
  const std::vector<std::uint64_t> first = run_with_adds_and_removes(1);
  EXPECT_EQ(first, run_with_adds_and_removes(1));
  EXPECT_EQ(first, run_with_adds_and_removes(2));
}

TEST(BodyLifecycle, AddedBodiesAreChecked) {
  World world(scene_of({ground()}));
  BodyDesc bad = box_at("bad", Vec3(0, 0, 1));
  bad.mass = -1;
  try {
    world.add_body(bad);
    FAIL() << "a negative mass was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field, "bodies[1].mass");
    EXPECT_NE(std::string(e.what()).find("got -1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(world.add_body(ground()), SceneError) << "a duplicate name";
  EXPECT_EQ(world.body_count(), 1);
}

}  // namespace
}  // namespace tumble
