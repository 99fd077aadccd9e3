// A step that leaves a state non-finite stops the world with NonFiniteStateError naming the step,
// the body and where it was, instead of carrying NaN on. No input the checks accept reaches that
// any more (the inertia [1e-20, 1e20, 1e20] that once did is now refused: no mass within the
// shape has a moment above m R^2), so the guard is tested by putting a NaN into a simulation's
// state, as an engine fault would, and the impossible inertia by its refusal.
#include <gtest/gtest.h>

#include <limits>

#include "engine/simulation.hpp"
#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

std::shared_ptr<Scene> needle(const Vec3& moments) {
  BodyDesc b = dynamic_body("needle", Shape::box(Vec3::Constant(0.5)));
  b.mass = 1;
  b.inertia = moments.asDiagonal();
  b.position = Vec3(0, 0, 0.6);
  b.angular_velocity = Vec3(1, 2, 3);
  return testing::scene_of({static_body("floor", Shape::plane()), b});
}

TEST(NonFiniteState, StopsTheWorldNamingStepAndBody) {
  Simulation sim(needle(Vec3(0.1, 0.12, 0.15)));
  State faulty = sim.state();
  faulty.bodies[1].angular_velocity.y() = std::numeric_limits<Real>::quiet_NaN();
  sim.set_state(faulty);
  try {
    sim.step();
    FAIL() << "the world stepped on with a non-finite state";
  } catch (const NonFiniteStateError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("step 1: body 'needle' (index 1) has a non-finite"), std::string::npos) << m;
    EXPECT_NE(m.find("at the start of the step it was at position (0, 0, 0.6)"), std::string::npos)
        << m;
  }
  // The inertia that used to overflow is refused before any step, on the API's path too.
  EXPECT_THROW(World(needle(Vec3(1e-20, 1e20, 1e20))), Error);
}

TEST(NonFiniteState, AFiniteWorldIsNeverStopped) {
  World world(testing::scene_of({testing::ground(), testing::box_at("box", Vec3(0, 0, 2))}));
  EXPECT_NO_THROW(world.step(300));
}

}  // namespace
}  // namespace tumble
