// FieldOverride: a field set before the scene is read is read and checked as if the file said
// so; aliased nodes change only where the path points.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scenes/scene_loader.hpp"

namespace tumble {
namespace {

constexpr const char* kScene = R"(world:
  dt: 0.01
materials:
  rubber: {friction: 0.9, restitution: 0.5}
bodies:
  - {name: floor, shape: {type: plane}, static: true}
  - name: crate
    shape: &cube {type: box, half_extents: [0.5, 0.5, 0.5]}
    position: [0, 0, 0.5]
    mass: 2
  - {name: twin, shape: *cube, position: [3, 0, 0.5], mass: 2, material: rubber}
)";

Scene overridden(std::vector<FieldOverride> overrides) {
  return load_scene_string(kScene, "override.yaml", overrides);
}

std::string override_error_of(std::vector<FieldOverride> overrides) {
  try {
    overridden(std::move(overrides));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(FieldOverride, SetsAFieldTheFileGives) {
  EXPECT_EQ(overridden({}).world.dt, 0.01);
  EXPECT_EQ(overridden({{"world.dt", "0.005"}}).world.dt, 0.005);
  EXPECT_EQ(overridden({{"materials.rubber.friction", "0.25"}}).materials[1].friction, 0.25);
}

TEST(FieldOverride, AddsAFieldTheFileLeavesOut) {
  const Scene s = overridden({{"world.substeps", "7"},
                              {"materials.default.friction", "0.3"},
                              {"world.gravity", "[0, 0, -1.62]"}});
  EXPECT_EQ(s.world.substeps, 7);
  EXPECT_EQ(s.materials[0].friction, 0.3);
  EXPECT_EQ(s.world.gravity.z(), -1.62);
  EXPECT_EQ(s.world.dt, 0.01);  // the rest as written
}

TEST(FieldOverride, NamesListItemsByIndexOrName) {
  EXPECT_EQ(overridden({{"bodies.1.mass", "5"}}).bodies[1].mass, 5);
  EXPECT_EQ(overridden({{"bodies.twin.mass", "7"}}).bodies[2].mass, 7);
  EXPECT_EQ(overridden({{"bodies.twin.position.0", "4"}}).bodies[2].position.x(), 4);
}

TEST(FieldOverride, ChangesOneAliasOfASharedNodeOnly) {
  const Scene s = overridden({{"bodies.twin.shape.half_extents", "[0.25, 0.25, 0.25]"}});
  EXPECT_EQ(s.bodies[2].shape.half_extents.x(), 0.25);
  EXPECT_EQ(s.bodies[1].shape.half_extents.x(), 0.5);  // the anchor's body keeps its cube
  const Scene t = overridden({{"bodies.crate.shape.half_extents.2", "1"}});
  EXPECT_EQ(t.bodies[1].shape.half_extents.z(), 1);
  EXPECT_EQ(t.bodies[2].shape.half_extents.z(), 0.5);
}

TEST(FieldOverride, LaterOverridesWin) {
  EXPECT_EQ(overridden({{"world.dt", "0.002"}, {"world.dt", "0.004"}}).world.dt, 0.004);
}

TEST(FieldOverride, ABadValueGetsTheLoadersMessage) {
  const std::string dt = override_error_of({{"world.dt", "-1"}});
  EXPECT_NE(dt.find("world.dt"), std::string::npos) << dt;
  EXPECT_NE(dt.find("got -1"), std::string::npos) << dt;
  const std::string unknown = override_error_of({{"world.dtt", "0.1"}});
  EXPECT_NE(unknown.find("unknown field 'dtt'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("did you mean 'dt'"), std::string::npos) << unknown;
  const std::string solver = override_error_of({{"world.solver", "fast"}});
  EXPECT_NE(solver.find("world.solver"), std::string::npos) << solver;
}

TEST(FieldOverride, APathThatCannotBeFollowedSaysWhy) {
  const std::string index = override_error_of({{"bodies.9.mass", "1"}});
  EXPECT_NE(index.find("has no item '9'"), std::string::npos) << index;
  EXPECT_NE(index.find("3 items"), std::string::npos) << index;
  const std::string name = override_error_of({{"bodies.ghost.mass", "1"}});
  EXPECT_NE(name.find("has no item 'ghost'"), std::string::npos) << name;
  const std::string into_value = override_error_of({{"world.dt.x", "1"}});
  EXPECT_NE(into_value.find("inside 'world.dt', which is a value"), std::string::npos)
      << into_value;
  const std::string empty = override_error_of({{"world..dt", "1"}});
  EXPECT_NE(empty.find("empty part"), std::string::npos) << empty;
  const std::string not_yaml = override_error_of({{"world.dt", "[1, 2"}});
  EXPECT_NE(not_yaml.find("is not YAML"), std::string::npos) << not_yaml;
}

}  // namespace
}  // namespace tumble
