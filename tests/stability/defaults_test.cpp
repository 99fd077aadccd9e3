// Scenes that set nothing but gravity, dt, duration and the bodies (scenes/stability/defaults_*):
// the engine's default solver settings must hold them, as a new user would write them.
#include <gtest/gtest.h>

#include "tests/stability/stability_run.hpp"

namespace tumble::test {
namespace {

std::shared_ptr<Scene> defaults_scene(const std::string& name) {
  return stability_scene(name, SolverType::impulse);
}

// Twelve 0.5 m cubes at 60 Hz stand 10 s; the top box moves less than 1 cm.
TEST(DefaultSettings, TowerOfTwelveStandsTenSeconds) {
  const auto scene = defaults_scene("defaults_tower12.yaml");
  Simulation world(scene);
  const int top = scene->find_body("box11");
  const StabilityRecord r = run_and_record(world, 10, {top}, 30);
  report("defaults_tower12 (top)", SolverType::impulse, r);
  EXPECT_TRUE(r.finite);
  EXPECT_LT(r.max_drift, 0.01);
  EXPECT_LT(r.max_penetration, 0.01);
}

// A 100 kg box on a 0.2 kg box: the heavy one sinks less than 1 cm into the light one, which
// sinks less than 1 cm into the floor, and neither tilts.
TEST(DefaultSettings, HeavyOnLightOneToFiveHundredStaysApart) {
  const auto scene = defaults_scene("defaults_heavy_on_light.yaml");
  Simulation world(scene);
  const StabilityRecord r = run_and_record(world, 10, {}, 1);
  report("defaults_heavy_on_light", SolverType::impulse, r);
  EXPECT_TRUE(r.finite);
  EXPECT_LT(r.max_penetration, 0.01);
  EXPECT_LT(r.max_tilt, 0.0175);
}

// Eight 0.4 m cubes at 120 Hz: in 5 s the top box sinks less than 5 mm and moves less than 5 mm
// sideways.
TEST(DefaultSettings, StackOfEightAt120HzNeitherSagsNorDrifts) {
  const auto scene = defaults_scene("defaults_stack8_120hz.yaml");
  Simulation world(scene);
  const int top = scene->find_body("box7");
  const Vec3 start = scene->bodies[std::size_t(top)].position;
  Real sag = 0;
  Real sideways = 0;
  const StabilityRecord r = run_and_record(world, 5, {top}, 60, [&](const Simulation& w) {
    const Vec3 p = w.state().bodies[std::size_t(top)].position;
    sag = std::max(sag, start.z() - p.z());
    sideways = std::max(sideways, std::hypot(p.x() - start.x(), p.y() - start.y()));
  });
  report("defaults_stack8_120hz (top)", SolverType::impulse, r);
  std::printf("[stability] defaults_stack8_120hz sag %.3g m sideways %.3g m\n", sag, sideways);
  EXPECT_TRUE(r.finite);
  EXPECT_LT(sag, 0.005);
  EXPECT_LT(sideways, 0.005);
}

// The same stack 1e5 m from the origin and at the origin: shifted back by the offset, every body
// is within 1e-6 m of its twin at every step (pair-local collision frames keep the precision).
TEST(DefaultSettings, StackFarFromTheOriginMatchesTheStackAtIt) {
  Simulation near(defaults_scene("defaults_stack5_origin.yaml"));
  Simulation far(defaults_scene("defaults_stack5_far.yaml"));
  const Vec3 offset(1e5, 1e5, 0);
  Real worst = 0;
  const int steps = 300;
  for (int k = 0; k < steps; ++k) {
    near.step();
    far.step();
    for (std::size_t i = 0; i < near.state().bodies.size(); ++i) {
      const Vec3 d = far.state().bodies[i].position - offset - near.state().bodies[i].position;
      worst = std::max(worst, d.norm());
    }
  }
  std::printf("[stability] defaults_stack5 far vs origin: largest difference %.3g m\n", worst);
  EXPECT_LT(worst, 1e-6);
}

}  // namespace
}  // namespace tumble::test
