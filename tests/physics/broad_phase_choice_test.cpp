#include <gtest/gtest.h>

#include "engine/broad_phase_choice.hpp"
#include "tests/physics/scene_fixture.hpp"

namespace tumble::test {
namespace {

Scene boxes(int count, int statics) {
  Scene scene;
  scene.materials.push_back({"default", 0.5, 0});
  for (int i = 0; i < count; ++i) {
    BodyDesc b;
    b.shape = Shape::box(Vec3(0.5, 0.5, 0.5));
    b.position = Vec3(i * 2.0, 0, 1);
    b.is_static = i < statics;
    b.mass = b.is_static ? 0 : 1;
    scene.bodies.push_back(b);
  }
  return scene;
}

TEST(BroadPhaseChoice, SmallScenesUseBruteForceLargeOnesTheKdTree) {
  EXPECT_EQ(choose_broad_phase(BroadPhaseType::automatic, boxes(kBruteForceBodyLimit, 0)),
            BroadPhaseType::brute);
  EXPECT_EQ(choose_broad_phase(BroadPhaseType::automatic, boxes(kBruteForceBodyLimit + 1, 0)),
            BroadPhaseType::kdtree);
  // Static bodies count: they are proxies the structure has to hold.
  EXPECT_EQ(choose_broad_phase(BroadPhaseType::automatic, boxes(kBruteForceBodyLimit + 1, 30)),
            BroadPhaseType::kdtree);
  // An explicit choice is never overridden.
  EXPECT_EQ(choose_broad_phase(BroadPhaseType::sap, boxes(3, 0)), BroadPhaseType::sap);
}

TEST(BroadPhaseChoice, StatisticsOfAScene) {
  Scene scene = boxes(5, 2);
  BodyDesc plane;
  plane.shape = Shape::plane();
  plane.is_static = true;
  scene.bodies.push_back(plane);
  BodyDesc big;
  big.shape = Shape::sphere(100);
  big.mass = 1;
  scene.bodies.push_back(big);
  const SceneStatistics s = scene_statistics(scene);
  EXPECT_EQ(s.dynamic_bodies, 4);
  EXPECT_EQ(s.static_bodies, 3);
  EXPECT_EQ(s.unbounded_bodies, 1);
  EXPECT_NEAR(s.size_spread, 100 / std::sqrt(0.75), 1e-9);
}

TEST(BroadPhaseChoice, ShippedScenesAreSmall) {
  Simulation world(shipped_scene("demo.yaml"));
  EXPECT_EQ(world.broad_phase_type(), BroadPhaseType::brute);
}

}  // namespace
}  // namespace tumble::test
