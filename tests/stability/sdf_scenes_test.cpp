// Bodies of signed distance fields in whole simulations, at default settings, against closed
// forms: a torus settles on its tube and stays, and a ball rolls inside a bowl carved by CSG with
// the period of a ball rolling in a spherical bowl.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "tumble/load_scene.hpp"
#include "tumble/world.hpp"

namespace tumble {
namespace {

std::shared_ptr<const Scene> sdf_scene(const char* file) {
  return load_scene(std::string(TUMBLE_SOURCE_DIR) + "/scenes/sdf/" + file);
}

TEST(SdfScenes, TorusRestsOnItsTubeForTenSeconds) {
  World world(sdf_scene("torus_on_plane.yaml"));
  const BodyId ring = world.body("ring");
  world.step(60);  // lands and settles within a second
  const BodyState settled = world.body_state(ring);
  Real lowest = settled.position.z(), highest = settled.position.z(), drift = 0, tilt = 0;
  for (int i = 0; i < 540; ++i) {
    world.step();
    const BodyState s = world.body_state(ring);
    lowest = std::min(lowest, s.position.z());
    highest = std::max(highest, s.position.z());
    const Vec3 moved = s.position - settled.position;
    drift = std::max(drift, std::hypot(moved.x(), moved.y()));
    tilt = std::max(tilt, std::acos(std::min(Real(1), (s.orientation * Vec3::UnitZ()).z())));
  }
  const BodyState end = world.body_state(ring);
  // Its centre a tube's radius (0.1 m) above the floor, to the soft contact's sag and slop.
  EXPECT_NEAR(lowest, 0.1, 1e-3);
  EXPECT_NEAR(highest, 0.1, 1e-3);
  EXPECT_LT(drift, 1e-3);
  EXPECT_LT(tilt, 1e-3);
  EXPECT_LT(end.velocity.norm(), 1e-3);
  EXPECT_LT(end.angular_velocity.norm(), 1e-2);
}

TEST(SdfScenes, BallRollsInTheBowlWithTheClosedFormPeriod) {
  // A solid ball of radius r rolling without slipping in a spherical bowl of radius R swings
  // with period 2 pi sqrt(7 (R - r) / (5 g)) for small amplitudes (the rolling ball's kinetic
  // energy is 7/10 m v^2). The bowl's sphere (0.6 m) has its centre at z = 0.8.
  World world(sdf_scene("sphere_in_bowl.yaml"));
  const BodyId ball = world.body("ball");
  const Vec3 bowl_centre(0, 0, 0.8);
  const Real big = 0.6, small = 0.1, g = 9.81;
  const Real dt = world.scene().world.dt;
  const auto energy = [&](const BodyState& s) {
    // Kinetic of translation and rotation (I = 2/5 m r^2) plus potential, per unit mass.
    return 0.5 * s.velocity.squaredNorm() +
           0.5 * 0.4 * small * small * s.angular_velocity.squaredNorm() + g * s.position.z();
  };
  const Real start_energy = energy(world.body_state(ball));
  std::vector<Real> crossings;  // times x goes from - to +
  Real previous_x = world.body_state(ball).position.x();
  Real worst_radius = 0, highest_energy = start_energy;
  const int steps = int(std::lround(10.0 / dt));
  for (int i = 0; i < steps; ++i) {
    world.step();
    const BodyState s = world.body_state(ball);
    if (world.time() > 0.1)  // after it has landed (it starts 1 cm above the bowl)
      worst_radius =
          std::max(worst_radius, std::abs((s.position - bowl_centre).norm() - (big - small)));
    highest_energy = std::max(highest_energy, energy(s));
    if (previous_x < 0 && s.position.x() >= 0)
      crossings.push_back(world.time() - dt * s.position.x() / (s.position.x() - previous_x));
    previous_x = s.position.x();
  }
  ASSERT_GE(crossings.size(), 4u);
  const Real period = (crossings.back() - crossings.front()) / Real(crossings.size() - 1);
  const Real expected = 2 * std::numbers::pi * std::sqrt(7 * (big - small) / (5 * g));
  // The amplitude (0.3 m on a 0.5 m radius, 37 degrees) lengthens the period by about 2.7%
  // over the small-swing value.
  EXPECT_NEAR(period, expected, 0.04 * expected) << "period " << period << " s";
  EXPECT_GT(period, expected);
  // On the bowl, to a millimetre.
  EXPECT_LT(worst_radius, 1e-3);
  // A known defect, guarded here so that it cannot grow unseen: on this concave surface the
  // ball gains energy, about 0.015 J/kg per second at 240 Hz (3.8% of its total in 10 s;
  // docs/sdf.md, "Contacts", has the measurements). A convex contact does not.
  EXPECT_LT(highest_energy, start_energy * 1.05);
}

}  // namespace
}  // namespace tumble
