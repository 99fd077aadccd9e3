// A step that leaves a state non-finite stops the world with NonFiniteStateError naming the step,
// the body and where it was, instead of carrying NaN on: here an inertia inside the documented
// bounds (1e-20 against 1e20, which passes the triangle inequality) whose gyroscopic step
// overflows.
#include <gtest/gtest.h>

#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

std::shared_ptr<Scene> needle() {
  BodyDesc b = dynamic_body("needle", Shape::box(Vec3::Constant(0.5)));
  b.mass = 1;
  b.inertia = Vec3(1e-20, 1e20, 1e20).asDiagonal();
  b.position = Vec3(0, 0, 0.6);
  b.angular_velocity = Vec3(1, 2, 3);
  return testing::scene_of({static_body("floor", Shape::plane()), b});
}

TEST(NonFiniteState, StopsTheWorldNamingStepAndBody) {
  World world(needle());
  try {
    world.step(10);
    FAIL() << "the world stepped on with a non-finite state";
  } catch (const NonFiniteStateError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("step 1: body 'needle' (index 1) has a non-finite"), std::string::npos) << m;
    EXPECT_NE(m.find("at the start of the step it was at position (0, 0, 0.6)"), std::string::npos)
        << m;
  }
  // A batch stops the same way, and says so as a tumble::Error.
  BatchWorld batch(needle(), 3, 2);
  EXPECT_THROW(batch.step(), Error);
}

TEST(NonFiniteState, AFiniteWorldIsNeverStopped) {
  World world(testing::scene_of({testing::ground(), testing::box_at("box", Vec3(0, 0, 2))}));
  EXPECT_NO_THROW(world.step(300));
}

}  // namespace
}  // namespace tumble
