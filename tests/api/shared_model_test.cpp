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
