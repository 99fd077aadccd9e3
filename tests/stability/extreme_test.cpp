// Extreme cases of scenes/stability/: Newton's cradle, the intermediate-axis flip, a tiny box
// on a huge one far from the origin, very large and very small time steps, under both solvers
// where they apply (docs/stability.md).
#include <gtest/gtest.h>

#include <numbers>

#include "tests/stability/stability_run.hpp"

namespace tumble::test {
namespace {

// Newton's cradle, five unit spheres, e = 1: the last ball leaves with at least 95% of the
// first one's speed and the others are nearly at rest (below 5% of it). Only the impulse
// solver models restitution; the penalty solver's bounce comes from its spring and its numbers
// are reported in docs/stability.md, not asserted.
TEST(Stability, NewtonsCradlePassesTheMomentumThrough) {
  for (SolverType solver : kBoth) {
    const auto scene = stability_scene("newtons_cradle.yaml", solver);
    Simulation world(scene);
    const StabilityRecord r = run_and_record(world, 3, {}, 0);
    report("newtons_cradle", solver, r);
    const Real first = scene->bodies[0].velocity.x();
    std::printf("[stability] newtons_cradle %s final vx:", solver_label(solver));
    for (const BodyState& b : world.state().bodies)
      std::printf(" %.4f", b.velocity.x());
    std::printf("\n");
    EXPECT_TRUE(r.finite);
    EXPECT_LE(r.max_energy_gain, 1e-9);
    if (solver != SolverType::impulse)
      continue;
    const auto& bodies = world.state().bodies;
    EXPECT_GE(bodies[4].velocity.x(), 0.95 * first);
    for (int i = 0; i < 4; ++i)
      EXPECT_LT(bodies[i].velocity.norm(), 0.05 * first) << "ball " << i;
  }
}

// Complete elliptic integral of the first kind, K(k) = pi / (2 AGM(1, sqrt(1 - k^2))).
Real elliptic_k(Real k) {
  Real a = 1;
  Real b = std::sqrt(1 - k * k);
  for (int i = 0; i < 60 && std::abs(a - b) > 1e-15 * a; ++i) {
    const Real m = (a + b) / 2;
    b = std::sqrt(a * b);
    a = m;
  }
  return std::numbers::pi_v<Real> / (2 * a);
}

// Time between sign changes of the body-frame angular velocity about the intermediate axis,
// from the closed-form solution of Euler's equations (Landau & Lifshitz, Mechanics, sec. 37):
// with moments I1 < I2 < I3 and L^2 > 2 E I2 that component is proportional to sn(tau),
// tau = t sqrt((I3 - I2)(L^2 - 2 E I1) / (I1 I2 I3)), modulus
// k^2 = (I2 - I1)(2 E I3 - L^2) / ((I3 - I2)(L^2 - 2 E I1)); sn changes sign every 2 K(k).
// For L^2 < 2 E I2, I1 and I3 swap roles.
Real flip_half_period(Vec3 moments, Vec3 w) {
  Real i1 = moments[0], i2 = moments[1], i3 = moments[2];
  const Real l2 = (moments.cwiseProduct(w)).squaredNorm();
  const Real e2 = w.dot(moments.cwiseProduct(w));
  if (l2 < e2 * i2)
    std::swap(i1, i3);
  const Real rate = std::sqrt((i3 - i2) * (l2 - e2 * i1) / (i1 * i2 * i3));
  const Real k2 = (i2 - i1) * (e2 * i3 - l2) / ((i3 - i2) * (l2 - e2 * i1));
  return 2 * elliptic_k(std::sqrt(k2)) / rate;
}

// A 1x2x3 box spun near its intermediate axis flips with the theoretical period (5%). The
// integrator is the same under both solvers (no contacts), so both are run and must agree.
TEST(Stability, IntermediateAxisFlipsWithTheTheoreticalPeriod) {
  for (SolverType solver : kBoth) {
    const auto scene = stability_scene("spin_intermediate.yaml", solver);
    const BodyDesc& box = scene->bodies[0];
    // Sorted moments, smallest first, with the matching components of the body-frame spin.
    const Vec3 w0 = box.orientation.conjugate() * box.angular_velocity;
    const Vec3 moments(box.inertia(2, 2), box.inertia(1, 1), box.inertia(0, 0));
    ASSERT_LT(moments[0], moments[1]);
    ASSERT_LT(moments[1], moments[2]);
    const Real expected = flip_half_period(moments, Vec3(w0.z(), w0.y(), w0.x()));
    Simulation world(scene);
    std::vector<Real> crossings;
    Real previous = w0.y();
    const StabilityRecord r = run_and_record(world, 60, {}, 0, [&](const Simulation& w) {
      const BodyState& b = w.state().bodies[0];
      const Real wy = (b.orientation.conjugate() * b.angular_velocity).y();
      if ((wy > 0) != (previous > 0)) {
        // Linear interpolation of the crossing within the step.
        const Real t = w.state().time - w.scene().world.dt * wy / (wy - previous);
        crossings.push_back(t);
      }
      previous = wy;
    });
    expect_sane(r);
    ASSERT_GE(crossings.size(), 3u) << "expected at least three flips in 60 s";
    const Real measured =
        (crossings.back() - crossings.front()) / static_cast<Real>(crossings.size() - 1);
    std::printf("[stability] spin_intermediate %s flips %zu half-period %.4f s theory %.4f s\n",
                solver_label(solver), crossings.size(), measured, expected);
    EXPECT_NEAR(measured, expected, 0.05 * expected) << solver_label(solver);
  }
}

// Spun about its major axis (x, the largest moment) the box stays: the body x axis never
// leaves the angular momentum direction by more than three times its initial angle.
TEST(Stability, MajorAxisSpinStays) {
  for (SolverType solver : kBoth) {
    const auto scene = stability_scene("spin_major.yaml", solver);
    Simulation world(scene);
    const BodyDesc& box = scene->bodies[0];
    const Vec3 momentum =
        box.orientation * (box.inertia * (box.orientation.conjugate() * box.angular_velocity));
    const auto angle_from_momentum = [&](const BodyState& b) {
      const Vec3 axis = b.orientation * Vec3::UnitX();
      return std::acos(std::clamp(axis.dot(momentum.normalized()), Real(-1), Real(1)));
    };
    const Real initial = angle_from_momentum(world.state().bodies[0]);
    Real worst = 0;
    const StabilityRecord r = run_and_record(world, 60, {}, 0, [&](const Simulation& w) {
      worst = std::max(worst, angle_from_momentum(w.state().bodies[0]));
    });
    std::printf("[stability] spin_major %s axis-to-L angle initial %.3g max %.3g rad\n",
                solver_label(solver), initial, worst);
    expect_sane(r);
    EXPECT_LT(worst, 3 * initial + 1e-6) << solver_label(solver);
  }
}

// A 1 mm box on a 100 m box behaves the same 1e5 m from the origin as at it: the tiny box's
// position relative to the base agrees to 1e-6 m at every step, and it stays on the base:
// its height above the base within 10 um (the soft contact sags 4 um at 240 Hz), and it
// moves less than a tenth of its size.
TEST(Stability, TinyOnHugeFarFromTheOriginAsAtTheOrigin) {
  for (SolverType solver : kBoth) {
    const auto near_scene = stability_scene("tiny_on_huge.yaml", solver);
    const auto far_scene = stability_scene("tiny_on_huge_far.yaml", solver);
    Simulation near_world(near_scene);
    Simulation far_world(far_scene);
    const int base = near_scene->find_body("base");
    const int tiny = near_scene->find_body("tiny");
    const Vec3 rest = near_scene->bodies[tiny].position - near_scene->bodies[base].position;
    Real worst_difference = 0;
    Real worst_sink = 0;
    Real worst_height = 0;
    std::vector<Vec3> near_relative;
    const StabilityRecord rn = run_and_record(near_world, 5, {}, 0, [&](const Simulation& w) {
      near_relative.push_back(w.state().bodies[tiny].position - w.state().bodies[base].position);
    });
    std::size_t k = 0;
    const StabilityRecord rf = run_and_record(far_world, 5, {}, 0, [&](const Simulation& w) {
      const Vec3 relative = w.state().bodies[tiny].position - w.state().bodies[base].position;
      worst_difference = std::max(worst_difference, (relative - near_relative[k++]).norm());
      worst_sink = std::max(worst_sink, (relative - rest).norm());
      worst_height = std::max(worst_height, std::abs(relative.z() - rest.z()));
    });
    report("tiny_on_huge (origin)", solver, rn);
    report("tiny_on_huge (1e5 m)", solver, rf);
    std::printf(
        "[stability] tiny_on_huge %s relative difference %.3g m, largest move %.3g m, height "
        "change %.3g m\n",
        solver_label(solver), worst_difference, worst_sink, worst_height);
    expect_sane(rn);
    expect_sane(rf);
    EXPECT_LT(worst_difference, 1e-6) << solver_label(solver);
    EXPECT_LT(worst_height, 1e-5) << solver_label(solver);
    EXPECT_LT(worst_sink, 1e-4) << solver_label(solver);
  }
}

// dt = 1/30 and dt = 1e-5 both give sane results on a five-box stack (stands: top drift
// < 1 cm, no overlap of 1 cm) ... The 1e-5 run (100,000 steps per second) is shortened under
// TUMBLE_PROPERTY_SCALE < 1 (the sanitizer run).
TEST(Stability, StackIsSaneAtLargeAndTinyTimeSteps) {
  for (const char* file : {"stack5_dt30.yaml", "stack5_dt1e-5.yaml"}) {
    for (SolverType solver : kBoth) {
      const auto scene = stability_scene(file, solver);
      Simulation world(scene);
      const Real seconds =
          scene->world.duration * (scene->world.dt < 1e-3 ? property_scale() : Real(1));
      const StabilityRecord r = run_and_record(world, seconds, {}, 0);
      const Real penetration = deepest_penetration(world);
      report(file, solver, r);
      expect_sane(r);
      EXPECT_LT(r.max_drift, 0.01) << file << " " << solver_label(solver);
      EXPECT_LT(penetration, 0.01) << file << " " << solver_label(solver);
    }
  }
}

// ... and on a bouncing ball (e = 0.8 dropped from 2 m): it never sinks 1 cm into the floor,
// never rises above its drop height, and under the impulse solver the first rebound reaches
// e^2 of the drop height within 10%.
TEST(Stability, BounceIsSaneAtLargeAndTinyTimeSteps) {
  for (const char* file : {"bounce_dt30.yaml", "bounce_dt1e-5.yaml"}) {
    for (SolverType solver : kBoth) {
      const auto scene = stability_scene(file, solver);
      Simulation world(scene);
      const int ball = scene->find_body("ball");
      const Real radius = scene->bodies[ball].shape.radius;
      const Real drop = scene->bodies[ball].position.z() - radius;
      Real lowest = drop;
      Real highest_after_bounce = 0;
      bool bounced = false;
      const StabilityRecord r =
          run_and_record(world, scene->world.duration, {}, 0, [&](const Simulation& w) {
            const BodyState& b = w.state().bodies[ball];
            const Real height = b.position.z() - radius;
            lowest = std::min(lowest, height);
            if (b.velocity.z() > 0)
              bounced = true;
            // The apex of the first rebound: highest point while rising or just after.
            if (bounced && height > highest_after_bounce && b.velocity.z() > -1)
              highest_after_bounce = height;
          });
      report(file, solver, r);
      std::printf("[stability] %s %s lowest %.4g m first rebound %.4f m (e^2 h = %.4f)\n", file,
                  solver_label(solver), lowest, highest_after_bounce, 0.64 * drop);
      expect_sane(r);
      EXPECT_GT(lowest, -0.01) << file << " " << solver_label(solver);
      EXPECT_LE(highest_after_bounce, drop) << file << " " << solver_label(solver);
      if (solver == SolverType::impulse) {
        EXPECT_NEAR(highest_after_bounce, 0.64 * drop, 0.1 * 0.64 * drop) << file;
      }
    }
  }
}

}  // namespace
}  // namespace tumble::test
