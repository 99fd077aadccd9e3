// Training geometry: in `train` mode a body collides with its train_shape and keeps the mass of its
// detailed shape; the loader places fitted and given training shapes in the body's frame; the
// randomization draws the training shape's size noise on its own stream.
#include <gtest/gtest.h>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/shape.hpp"
#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

using testing::scene_of;

std::shared_ptr<Scene> big_train_box(Geometry geometry) {
  BodyDesc box = dynamic_body("box", Shape::box(Vec3::Constant(0.25)));
  box.train_shape = Shape::box(Vec3::Constant(0.5));
  box.position = Vec3(0, 0, 1);
  auto scene = scene_of({static_body("floor", Shape::plane()), box});
  scene->world.geometry = geometry;
  return scene;
}

TEST(TrainGeometry, TrainModeCollidesWithTheTrainShapeAndKeepsTheMass) {
  World deploy(big_train_box(Geometry::deploy));
  World train(big_train_box(Geometry::train));
  deploy.step(120);
  train.step(120);
  const BodyId box = deploy.body("box");
  // Resting on the floor at the half height of the shape each collides with.
  EXPECT_NEAR(deploy.body_state(box).position.z(), 0.25, 2e-3);
  EXPECT_NEAR(train.body_state(box).position.z(), 0.5, 2e-3);
  // The same mass: the same speed after the same push, whatever the geometry.
  World a(big_train_box(Geometry::deploy)), b(big_train_box(Geometry::train));
  a.apply_impulse(box, Vec3(0, 0, 5), a.body_state(box).position);
  b.apply_impulse(box, Vec3(0, 0, 5), b.body_state(box).position);
  EXPECT_EQ(a.body_state(box).velocity, b.body_state(box).velocity);
}

TEST(TrainGeometry, LoaderPlacesTrainingShapesInTheBodyFrame) {
  // A compound whose centre of mass is off the origin of the frame its parts are given in.
  const std::string yaml = R"(
bodies:
  - {name: floor, static: true, shape: {type: plane}}
  - name: lump
    shape:
      type: compound
      parts:
        - {shape: {type: box, half_extents: [0.1, 0.1, 0.1]}, position: [0, 0, 0]}
        - {shape: {type: box, half_extents: [0.1, 0.1, 0.1]}, position: [0.4, 0, 0]}
    train_shape: {type: compound, parts: [{shape: {type: sphere, radius: 0.1}, position: [0.4, 0, 0]}]}
    position: [0, 0, 1]
  - name: fitted
    shape: {type: capsule, radius: 0.1, half_length: 0.3}
    orientation: [0.7071067811865476, 0, 0.7071067811865476, 0]
    train_shape: {fit: box}
    position: [3, 0, 1]
)";
  const auto scene = load_scene_text(yaml, "train.yaml");
  const BodyDesc& lump = scene->bodies[1];
  // The body sits at the compound's centre of mass, x = 0.2 in the file's frame; the training
  // sphere was given at x = 0.4 of that frame, so 0.2 from the body's origin.
  EXPECT_NEAR(lump.position.x(), 0.2, 1e-12);
  ASSERT_TRUE(lump.train_shape.has_value());
  const CompoundPart& sphere = lump.train_shape->compound->parts().front();
  EXPECT_NEAR((sphere.pose.translation - Vec3(0.2, 0, 0)).norm(), 0, 1e-12);
  // A fitted box around a capsule along local z: half extents r, r, h + r.
  const BodyDesc& fitted = scene->bodies[2];
  ASSERT_TRUE(fitted.train_shape.has_value());
  EXPECT_EQ(fitted.train_shape->type, ShapeType::box);
  EXPECT_NEAR((fitted.train_shape->half_extents - Vec3(0.1, 0.1, 0.4)).norm(), 0, 1e-12);
  // Bad training shapes are refused naming the field.
  try {
    load_scene_text(R"(
bodies:
  - {shape: {type: box, half_extents: [0.1, 0.1, 0.1]}, train_shape: {fit: cone}}
)",
                    "bad.yaml");
    FAIL() << "a cone fit was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field, "bodies[0].train_shape.fit");
    EXPECT_EQ(e.line, 3);
  }
  EXPECT_THROW(load_scene_text(R"(
bodies:
  - {shape: {type: box, half_extents: [0.1, 0.1, 0.1]}, train_shape: {type: plane}}
)",
                               "bad.yaml"),
               SceneError);
  EXPECT_THROW(load_scene_text(R"(
world: {geometry: simplified}
bodies:
  - {shape: {type: box, half_extents: [0.1, 0.1, 0.1]}}
)",
                               "bad.yaml"),
               SceneError);
}

TEST(TrainGeometry, SizeNoiseReachesTheTrainingShapeOnItsOwnStream) {
  auto scene = big_train_box(Geometry::train);
  scene->randomize.size_noise = 0.05;
  const Scene a = randomized(*scene, 3);
  const Vec3 detailed = a.bodies[1].shape.half_extents / 0.25;
  const Vec3 trained = a.bodies[1].train_shape->half_extents / 0.5;
  EXPECT_NE(detailed, Vec3::Ones());
  EXPECT_NE(trained, Vec3::Ones());
  EXPECT_NE(detailed, trained);  // two draws, not one
  // The detailed shape's draw is what it was without a training shape.
  auto plain = big_train_box(Geometry::train);
  plain->bodies[1].train_shape.reset();
  plain->randomize.size_noise = 0.05;
  EXPECT_EQ(randomized(*plain, 3).bodies[1].shape.half_extents, a.bodies[1].shape.half_extents);
}

}  // namespace
}  // namespace tumble
