// Thousands of bodies in one place pair each with each, and the narrow phase would exhaust the
// memory (it ended in std::bad_alloc). A step stops at the documented candidate-pair limit instead
// (64 per body, at least 1,000,000; engine/scene_limits.hpp), naming the step and the counts, and
// a dense but physical pile stays far below it.
#include <gtest/gtest.h>

#include <string>

#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

TEST(CandidatePairLimit, ThousandsOfBodiesInOnePlaceStopTheStepWithTheReason) {
  std::vector<BodyDesc> bodies;
  // 1,500 balls at one point: 1,124,250 pairs, past the floor of 1,000,000 (and 64 x 1,500).
  for (int i = 0; i < 1500; ++i) {
    BodyDesc b = dynamic_body("ball" + std::to_string(i), Shape::sphere(0.5));
    b.position = Vec3(0, 0, 1);
    bodies.push_back(std::move(b));
  }
  World world(testing::scene_of(std::move(bodies)));
  try {
    world.step();
    FAIL() << "1,500 balls in one place were stepped";
  } catch (const StepLimitError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("step 0: the broad phase found 1124250 candidate pairs among 1500 bodies"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("more than the limit of 1000000"), std::string::npos) << m;
  }
}

TEST(CandidatePairLimit, ADensePileIsFarBelowIt) {
  // 1,000 unit boxes packed face to face in a 10 x 10 x 10 block resting on the ground: every box
  // touches up to 26 neighbours (faces, edges, corners), 12,000 to 13,000 candidate pairs.
  std::vector<BodyDesc> bodies{testing::ground()};
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 10; ++y)
      for (int z = 0; z < 10; ++z)
        bodies.push_back(testing::box_at("box" + std::to_string(100 * x + 10 * y + z),
                                         Vec3(x - 4.5, y - 4.5, z + 1.0)));
  World world(testing::scene_of(std::move(bodies)));
  EXPECT_NO_THROW(world.step(3));
}

}  // namespace
}  // namespace tumble
