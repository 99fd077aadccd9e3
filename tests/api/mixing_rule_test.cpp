// A scene's own friction and restitution rules replace the defaults (geometric mean, maximum).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/simulation.hpp"
#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

TEST(MixingRule, TheScenesRuleSetsThePairsFriction) {
  auto scene = testing::scene_of({testing::ground(), testing::box_at("box", Vec3(0, 0, 1.0))});
  scene->materials = {Material{"default", 0.5, 0}, Material{"ice", 0.02, 0.1}};
  scene->bodies[1].material = 1;
  {
    World world(scene);
    world.step();
    ASSERT_EQ(world.simulation().contacts().size(), 1u);
    EXPECT_DOUBLE_EQ(world.simulation().contacts()[0].friction, std::sqrt(0.5 * 0.02));
    EXPECT_DOUBLE_EQ(world.simulation().contacts()[0].restitution, 0.1);
  }
  scene->friction_mixing = [](const Material& a, const Material& b) {
    return std::min(a.friction, b.friction);
  };
  scene->restitution_mixing = [](const Material&, const Material&) { return Real(0); };
  World world(scene);
  world.step();
  ASSERT_EQ(world.simulation().contacts().size(), 1u);
  EXPECT_DOUBLE_EQ(world.simulation().contacts()[0].friction, 0.02);
  EXPECT_DOUBLE_EQ(world.simulation().contacts()[0].restitution, 0);
  // A rule out of range is refused when the world is made.
  scene->friction_mixing = [](const Material&, const Material&) { return Real(-1); };
  EXPECT_THROW(World{scene}, SceneError);
}

}  // namespace
}  // namespace tumble
