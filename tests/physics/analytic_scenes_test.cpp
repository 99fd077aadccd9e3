// Acceptance tests of the shipped scenes against analytic answers.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "tests/physics/scene_fixture.hpp"

namespace tumble::test {
namespace {

// Bounce: the k-th apex above the resting height is e^(2k) h_0.
TEST(ShippedScenes, BounceApexesFollowRestitutionLaw) {
  const auto scene = shipped_scene("bounce.yaml");
  Simulation world(scene);
  const int ball = body_index(*scene, "ball");
  const Real radius = scene->bodies[ball].shape.radius;
  const Real e = scene->materials[scene->bodies[ball].material].restitution;
  const Real h0 = world.state().bodies[ball].position.z() - radius;

  std::vector<Real> apexes;
  Real previous_vz = world.state().bodies[ball].velocity.z();
  Real previous_z = world.state().bodies[ball].position.z();
  bool bounced = false;
  const std::int64_t steps = static_cast<std::int64_t>(std::llround(5.0 / scene->world.dt));
  for (std::int64_t k = 0; k < steps && apexes.size() < 5; ++k) {
    world.step();
    const BodyState& b = world.state().bodies[ball];
    if (previous_vz < 0 && b.velocity.z() > 0)
      bounced = true;
    if (bounced && previous_vz > 0 && b.velocity.z() <= 0) {
      // The discrete apex is the highest of the two neighbouring samples; one step of
      // 1 ms at the apex changes height by g dt^2 / 2 = 5 um, far below the tolerance.
      apexes.push_back(std::max(previous_z, b.position.z()) - radius);
      bounced = false;
    }
    previous_vz = b.velocity.z();
    previous_z = b.position.z();
  }
  ASSERT_EQ(apexes.size(), 5u) << "the ball must bounce five times in 5 s";
  for (int k = 1; k <= 5; ++k) {
    const Real expected = std::pow(e, 2 * k) * h0;
    EXPECT_NEAR(apexes[k - 1], expected, 0.01 * expected) << "apex " << k;
  }
}

struct InclineGeometry {
  Vec3 downhill;
  Real angle;
};

InclineGeometry incline_of(const Scene& scene) {
  const BodyDesc& plane = scene.bodies[body_index(scene, "incline")];
  const Vec3 n = plane.orientation * Vec3::UnitZ();
  const Vec3 g = scene.world.gravity;
  const Vec3 tangential = g - g.dot(n) * n;
  return {tangential.normalized(), std::acos(n.dot(-g.normalized()))};
}

Real combined_friction(const Scene& scene, int a, int b) {
  return std::sqrt(scene.materials[scene.bodies[a].material].friction *
                   scene.materials[scene.bodies[b].material].friction);
}

// Above the friction angle: s = a t^2 / 2, v = a t with a = g (sin theta - mu cos theta).
TEST(ShippedScenes, InclineSlideMatchesCoulomb) {
  const auto scene = shipped_scene("incline_slide.yaml");
  Simulation world(scene);
  const int box = body_index(*scene, "box");
  const int incline = body_index(*scene, "incline");
  const auto geometry = incline_of(*scene);
  const Real mu = combined_friction(*scene, box, incline);
  const Real g = scene->world.gravity.norm();
  const Real a = g * (std::sin(geometry.angle) - mu * std::cos(geometry.angle));
  ASSERT_GT(a, 0.5) << "the scene must be above the friction angle";

  const Vec3 start = world.state().bodies[box].position;
  const std::int64_t steps = std::llround(1.0 / scene->world.dt);
  for (std::int64_t k = 0; k < steps; ++k)
    world.step();
  const BodyState& b = world.state().bodies[box];
  const Real t = world.state().time;
  const Real distance = (b.position - start).dot(geometry.downhill);
  const Real speed = b.velocity.dot(geometry.downhill);
  EXPECT_NEAR(distance, a * t * t / 2, 0.01 * a * t * t / 2);
  EXPECT_NEAR(speed, a * t, 0.01 * a * t);
  // It slides straight down, neither sideways nor off the surface, and does not tumble.
  EXPECT_LT((b.position - start - distance * geometry.downhill).norm(), 1e-3);
  EXPECT_LT(b.angular_velocity.norm(), 1e-3);
}

// Below the friction angle the box stays put.
TEST(ShippedScenes, InclineStickHolds) {
  const auto scene = shipped_scene("incline_stick.yaml");
  Simulation world(scene);
  const int box = body_index(*scene, "box");
  const auto geometry = incline_of(*scene);
  ASSERT_GT(combined_friction(*scene, box, body_index(*scene, "incline")),
            std::tan(geometry.angle));
  const Vec3 start = world.state().bodies[box].position;
  const std::int64_t steps = std::llround(2.0 / scene->world.dt);
  for (std::int64_t k = 0; k < steps; ++k)
    world.step();
  const Vec3 moved = world.state().bodies[box].position - start;
  EXPECT_LT(moved.norm(), 1e-3);
  // Most of that is the contact settling along the normal (slop plus the soft contact's sag);
  // along the slope the box must not creep at all.
  const Vec3 normal = scene->bodies[body_index(*scene, "incline")].orientation * Vec3::UnitZ();
  EXPECT_LT((moved - moved.dot(normal) * normal).norm(), 1e-4);
}

// Free flight follows the exact discrete-time parabola of semi-implicit Euler.
TEST(ShippedScenes, FreeFlightIsTheDiscreteParabola) {
  const auto scene = shipped_scene("free_flight.yaml");
  Simulation world(scene);
  const int ball = body_index(*scene, "ball");
  const Vec3 x0 = scene->bodies[ball].position;
  const Vec3 v0 = scene->bodies[ball].velocity;
  const Vec3 g = scene->world.gravity;
  // The integrator runs substeps of h = dt / substeps.
  const int substeps = scene->world.substeps;
  const Real h = scene->world.dt / substeps;
  Real worst = 0;
  for (int step = 1; step <= 120; ++step) {
    world.step();
    const Real nn = step * substeps;
    const Vec3 x_exact = x0 + nn * h * v0 + h * h * g * (nn * (nn + 1) / 2);
    const Vec3 v_exact = v0 + nn * h * g;
    const BodyState& b = world.state().bodies[ball];
    worst = std::max(worst, (b.position - x_exact).norm() / x_exact.norm());
    worst = std::max(worst, (b.velocity - v_exact).norm() / v_exact.norm());
  }
  EXPECT_LT(worst, 1e-9);
}

// A torque-free body keeps its angular momentum and never gains kinetic energy.
TEST(ShippedScenes, TorqueFreeBodyConservesMomentumAndEnergy) {
  const auto scene = shipped_scene("spinning_box.yaml");
  Simulation world(scene);
  const int box = body_index(*scene, "box");
  const Vec3 l0 = angular_momentum(world.state().bodies[box], world.mass(box));
  const Real e0 = world.kinetic_energy();
  Real worst_momentum = 0;
  Real worst_energy_gain = 0;
  Real min_axis_alignment = 1;
  const std::int64_t steps = std::llround(10.0 / scene->world.dt);
  for (std::int64_t k = 0; k < steps; ++k) {
    world.step();
    const BodyState& b = world.state().bodies[box];
    worst_momentum = std::max(worst_momentum, (angular_momentum(b, world.mass(box)) - l0).norm());
    worst_energy_gain = std::max(worst_energy_gain, world.kinetic_energy() - e0);
    // The intermediate (body y) axis starts along L; the tennis-racket flip turns it over.
    min_axis_alignment =
        std::min(min_axis_alignment, (b.orientation * Vec3::UnitY()).dot(l0.normalized()));
  }
  EXPECT_LT(worst_momentum / l0.norm(), 1e-9);
  // Rounding may move the last bits either way; anything larger would be the integrator.
  EXPECT_LE(worst_energy_gain, 1e-12 * e0);
  EXPECT_LT(min_axis_alignment, -0.9) << "the box must flip about its intermediate axis";
}

}  // namespace
}  // namespace tumble::test
