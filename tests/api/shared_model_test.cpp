// One compiled model, many worlds: each world steps on its own, and the same inputs give the same
// bits in each as in a world that compiled the scene itself.
#include <gtest/gtest.h>

#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

TEST(SharedModel, WorldsOfOneModelAreIndependentAndIdentical) {
  auto scene = testing::scene_of({testing::ground(), testing::box_at("a", Vec3(0, 0, 1.0)),
                                  testing::box_at("b", Vec3(0.2, 0.1, 2.2))});
  const std::shared_ptr<const Model> model = compile(scene);
  World first(model);
  World second(model);
  World own(scene);
  second.add_force(second.body("b"), Vec3(300, 0, 0));  // only the second world is pushed
  for (int k = 0; k < 90; ++k) {
    first.step();
    second.step();
    own.step();
    ASSERT_EQ(first.state_hash(), own.state_hash()) << "step " << k;
  }
  EXPECT_NE(first.state_hash(), second.state_hash());
  EXPECT_EQ(&scene_of(*model), &first.scene());
  // A world that adds a body leaves the shared model, and its siblings, as they were.
  const std::uint64_t before = first.state_hash();
  second.add_body(testing::box_at("c", Vec3(5, 5, 1)));
  EXPECT_EQ(first.scene().bodies.size(), 3u);
  EXPECT_EQ(second.scene().bodies.size(), 4u);
  EXPECT_EQ(first.state_hash(), before);
}

// World::reset(model): a world put in the initial state of another model of the same bodies
// steps as a new world of that model, bit for bit, whether the static bodies kept their boxes
// (the broad phase kept) or not (rebuilt); a model of other bodies is refused.
TEST(SharedModel, AWorldResetToAnotherModelStepsAsANewWorldOfIt) {
  auto first = testing::scene_of({testing::ground(), testing::box_at("a", Vec3(0, 0, 1.0)),
                                  testing::box_at("b", Vec3(0.2, 0.1, 2.2))});
  first->materials = {Material{"default"}};
  // The same bodies, moved, resized, heavier and on ice; then also on a wider, lower ground.
  auto moved = std::make_shared<Scene>(*first);
  moved->bodies[1].position = Vec3(0.3, -0.2, 0.8);
  moved->bodies[2].shape = Shape::box(Vec3(0.4, 0.6, 0.3));
  moved->bodies[2].mass *= 3;
  moved->bodies[2].inertia *= 3;
  moved->materials[0].friction = 0.05;
  auto new_ground = std::make_shared<Scene>(*moved);
  new_ground->bodies[0].shape = Shape::box(Vec3(30, 30, 0.5));
  new_ground->bodies[0].position = Vec3(0, 0, -3);  // below the old box: a stale one misses it
  for (const auto& next :
       {std::shared_ptr<const Scene>(moved), std::shared_ptr<const Scene>(new_ground)}) {
    const std::shared_ptr<const Model> model = compile(next);
    World reused(first);
    reused.add_force(reused.body("a"), Vec3(50, 0, 0));
    reused.step(40);
    reused.reset(model);
    World fresh(model);
    EXPECT_EQ(reused.state_hash(), fresh.state_hash());
    for (int k = 0; k < 60; ++k) {
      reused.step();
      fresh.step();
      ASSERT_EQ(reused.state_hash(), fresh.state_hash()) << "step " << k;
    }
    EXPECT_EQ(reused.scene().materials[0].friction, 0.05);
  }
  // A static body grown in place: only a broad phase that took its new box finds it there.
  auto grown = std::make_shared<Scene>(*first);
  grown->bodies[0].shape = Shape::box(Vec3(40, 40, 0.5));
  World world(first);
  const Vec3 above_the_growth(30, 0, 5);
  EXPECT_FALSE(world.ray_cast(above_the_growth, Vec3(0, 0, -1), 10).has_value());
  world.reset(compile(grown));
  const std::optional<RayHit> hit = world.ray_cast(above_the_growth, Vec3(0, 0, -1), 10);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, 4.5, 1e-12);
  auto fewer = testing::scene_of({testing::ground(), testing::box_at("a", Vec3(0, 0, 1.0))});
  EXPECT_THROW(world.reset(compile(fewer)), Error);
  auto now_static = std::make_shared<Scene>(*first);
  now_static->bodies[1].is_static = true;
  now_static->bodies[1].mass = 0;
  EXPECT_THROW(world.reset(compile(now_static)), Error);
  EXPECT_THROW(world.reset(std::shared_ptr<const Model>()), Error);
}

TEST(SharedModel, CompileChecksTheScene) {
  auto scene = testing::scene_of({testing::ground()});
  scene->world.substeps = 0;
  try {
    compile(scene);
    FAIL() << "substeps 0 was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field, "world.substeps");
  }
}

}  // namespace
}  // namespace tumble
