// Bad calls throw tumble::Error with a message naming the body and the value; never undefined
// behaviour (the sanitizer build runs these).
#include <gtest/gtest.h>

#include <limits>

#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

using testing::box_at;
using testing::ground;
using testing::scene_of;

// Runs `call`, expects tumble::Error, and returns its message.
template <class Call>
std::string error_of(Call call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no tumble::Error was thrown";
  return {};
}

bool mentions(const std::string& message, const std::string& part) {
  return message.find(part) != std::string::npos;
}

TEST(ApiErrors, NameBodyAndValue) {
  BodyDesc paddle = kinematic_body("paddle", Shape::sphere(0.2));
  World world(scene_of({ground(), box_at("crate", Vec3(0, 0, 1)), paddle}));
  const BodyId crate = world.body("crate");
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Real inf = std::numeric_limits<Real>::infinity();

  EXPECT_TRUE(mentions(error_of([&] { world.body("nope"); }), "'nope'"));
  std::string m = error_of([&] { world.add_force(crate, Vec3(nan, 0, 0)); });
  EXPECT_TRUE(mentions(m, "'crate'") && mentions(m, "nan")) << m;
  m = error_of([&] { world.add_torque(crate, Vec3(0, inf, 0)); });
  EXPECT_TRUE(mentions(m, "'crate'") && mentions(m, "inf")) << m;
  m = error_of([&] { world.apply_impulse(crate, Vec3(0, 0, 1), Vec3(nan, 0, 0)); });
  EXPECT_TRUE(mentions(m, "'crate'") && mentions(m, "nan")) << m;
  m = error_of([&] { world.set_kinematic_target(crate, Vec3::Zero(), Quat::Identity()); });
  EXPECT_TRUE(mentions(m, "'crate'") && mentions(m, "dynamic")) << m;
  m = error_of([&] { world.add_force(world.body("ground"), Vec3(1, 0, 0)); });
  EXPECT_TRUE(mentions(m, "'ground'") && mentions(m, "static")) << m;
  m = error_of([&] { world.add_force(world.body("paddle"), Vec3(1, 0, 0)); });
  EXPECT_TRUE(mentions(m, "'paddle'") && mentions(m, "kinematic")) << m;
  m = error_of([&] { world.set_velocity(crate, Vec3(0, 0, 1e9), Vec3::Zero()); });
  EXPECT_TRUE(mentions(m, "'crate'") && mentions(m, "1e+09")) << m;
  m = error_of(
      [&] { world.set_kinematic_target(world.body("paddle"), Vec3(0, 0, nan), Quat::Identity()); });
  EXPECT_TRUE(mentions(m, "'paddle'") && mentions(m, "nan")) << m;
  EXPECT_TRUE(mentions(error_of([&] { world.body_state(BodyId{99, 0}); }), "99"));
  EXPECT_TRUE(mentions(error_of([&] { world.body_state(BodyId{-1, 0}); }), "-1"));
  EXPECT_TRUE(
      mentions(error_of([&] { world.ray_cast(Vec3::Zero(), Vec3::Zero(), 1); }), "direction"));
  EXPECT_TRUE(mentions(error_of([&] { world.step(-1); }), "-1"));
  // Nothing above changed the world.
  world.step();
  EXPECT_TRUE(world.body_state(crate).position.allFinite());
}

TEST(ApiErrors, ASceneBuiltInCodeGetsTheLoadersMessage) {
  auto scene = scene_of({ground(), box_at("crate", Vec3(0, 0, 1))});
  scene->bodies[1].shape.half_extents.x() = -1;
  try {
    World world(scene);
    FAIL() << "a negative half extent was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field, "bodies[1].shape.half_extents[0]");
    EXPECT_NE(std::string(e.what()).find("expected a positive number in metres (1e-9 to 1e9), "
                                         "got -1"),
              std::string::npos)
        << e.what();
  }
  scene = scene_of({ground()});
  scene->world.dt = 2;
  EXPECT_THROW(World{scene}, SceneError);
  scene = scene_of({ground()});
  scene->world.gravity.z() = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_THROW(World{scene}, SceneError);
  scene = scene_of({box_at("a", Vec3::Zero()), box_at("a", Vec3(3, 0, 0))});
  EXPECT_THROW(World{scene}, SceneError);
  EXPECT_THROW(World{std::shared_ptr<const Scene>()}, Error);
}

TEST(ApiErrors, TheSameValueGetsTheSameMessageFromAFile) {
  const std::string yaml = "bodies:\n  - {name: b, mass: 1, shape: {type: sphere, radius: -2}}\n";
  std::string from_file;
  try {
    load_scene_text(yaml, "bad.yaml");
  } catch (const SceneError& e) {
    from_file = e.reason;
  }
  auto scene = scene_of({dynamic_body("b", Shape::sphere(1))});
  scene->bodies[0].shape.radius = -2;
  std::string from_code;
  try {
    check_scene(*scene);
  } catch (const SceneError& e) {
    from_code = e.reason;
  }
  EXPECT_FALSE(from_file.empty());
  EXPECT_EQ(from_file, from_code);
}

TEST(ApiErrors, ShapeBuildersRejectBadData) {
  const std::vector<Vec3> flat{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  EXPECT_THROW(hull_from_points(flat), Error);
  EXPECT_THROW(mesh_from_triangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 3}}), Error);
  EXPECT_THROW(dynamic_body("p", Shape::plane()), Error);
  EXPECT_THROW(dynamic_body("s", Shape::sphere(1), -5), Error);
  // A field's mass is not assumed: it needs its density, as in a scene file.
  const Shape ring =
      load_shape_text("{type: sdf, sdf: {torus: {major_radius: 1, minor_radius: 0.25}}}");
  EXPECT_THROW(dynamic_body("ring", ring), Error);
  const BodyDesc given = dynamic_body("ring", ring, 500);
  EXPECT_NEAR(given.mass, 500 * 2 * M_PI * M_PI * 1 * 0.25 * 0.25, 0.01 * given.mass);
}

// Found by tests/fuzz/fuzz_short_scene: a density of -1.8e308 was written out in its 309 digits.
// A number in an error message reads as the shortest text that gives back the same double.
TEST(ApiErrors, AnExtremeDensityIsWrittenShortly) {
  try {
    dynamic_body("s", Shape::sphere(1), -std::numeric_limits<Real>::max());
    FAIL() << "a negative density was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "body 's': density must be positive and finite, got -1.7976931348623157e+308");
  }
}

}  // namespace
}  // namespace tumble
