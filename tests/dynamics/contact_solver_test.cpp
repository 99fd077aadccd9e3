// The contact solver on hand-built contacts, against what the constraints demand.
#include <gtest/gtest.h>

#include <numbers>
#include <vector>

#include "dynamics/contact_solver.hpp"

namespace tumble {
namespace {

struct TwoBodies {
  std::vector<BodyState> states{2};
  std::vector<BodyMass> masses{BodyMass::make(1.0, Mat3::Identity() * (1.0 / 6), false),
                               BodyMass::make(0, Mat3::Zero(), true)};
};

PairContact point_contact(const Vec3& p, Real depth, Real friction, Real restitution) {
  PairContact c;
  c.body_a = 0;
  c.body_b = 1;
  c.friction = friction;
  c.restitution = restitution;
  c.manifold.normal = Vec3::UnitZ();
  c.manifold.add(p, depth, {0, 0});
  return c;
}

// Rigid passes (the relax pass) until converged.
void solve_rigid(ContactSolver& solver, std::span<const PairContact> contacts, TwoBodies& w,
                 const ContactSolverSettings& settings, int passes = 30) {
  solver.prepare(contacts, {}, w.states, w.masses, settings);
  solver.warm_start(w.states);
  for (int i = 0; i < passes; ++i)
    solver.solve(w.states, /*use_bias=*/false);
}

TEST(ContactSolver, RestitutionReflectsApproachSpeed) {
  TwoBodies w;
  w.states[0].velocity = Vec3(0, 0, -5);
  const PairContact c = point_contact(Vec3::Zero(), 0.0, 0.0, 0.5);
  ContactSolver solver;
  solve_rigid(solver, std::span(&c, 1), w, {});
  EXPECT_NEAR(w.states[0].velocity.z(), 0.0, 1e-12);
  solver.apply_restitution(w.states);
  EXPECT_NEAR(w.states[0].velocity.z(), 2.5, 1e-12);
}

TEST(ContactSolver, SlowApproachDoesNotBounce) {
  TwoBodies w;
  w.states[0].velocity = Vec3(0, 0, -0.1);  // below the 0.2 m/s threshold
  const PairContact c = point_contact(Vec3::Zero(), 0.0, 0.0, 0.5);
  ContactSolver solver;
  solve_rigid(solver, std::span(&c, 1), w, {});
  solver.apply_restitution(w.states);
  EXPECT_NEAR(w.states[0].velocity.z(), 0.0, 1e-12);
}

// A gap may close within the substep but not be overshot; a speculative point that never
// pushes does not bounce.
TEST(ContactSolver, SpeculativeContactClosesGapExactly) {
  ContactSolverSettings settings;
  settings.substep = 0.01;
  for (Real approach : {-1.0, -20.0}) {
    TwoBodies w;
    w.states[0].velocity = Vec3(0, 0, approach);
    const PairContact c = point_contact(Vec3::Zero(), -0.1, 0.0, 0.9);  // 10 cm apart
    ContactSolver solver;
    solve_rigid(solver, std::span(&c, 1), w, settings);
    EXPECT_NEAR(w.states[0].velocity.z(), std::max(approach, -0.1 / settings.substep), 1e-12);
    solver.apply_restitution(w.states);
    if (approach == -1.0) {
      EXPECT_EQ(w.states[0].velocity.z(), -1.0) << "no contact, no bounce";
    }
  }
}

// Separation is tracked from the bodies' motion: after the body moves 6 cm closer, a 10 cm gap
// allows only 4 cm more.
TEST(ContactSolver, SeparationFollowsBodyMotion) {
  ContactSolverSettings settings;
  settings.substep = 0.01;
  TwoBodies w;
  w.states[0].position = Vec3(0, 0, 0.5);
  const PairContact c = point_contact(Vec3::Zero(), -0.1, 0.0, 0.0);
  ContactSolver solver;
  solver.prepare(std::span(&c, 1), {}, w.states, w.masses, settings);
  w.states[0].position.z() -= 0.06;
  w.states[0].velocity = Vec3(0, 0, -10);
  for (int i = 0; i < 30; ++i)
    solver.solve(w.states, false);
  EXPECT_NEAR(w.states[0].velocity.z(), -0.04 / settings.substep, 1e-9);
}

// Friction stops a slow slide within the cone, and only slows a fast one by mu * normal impulse.
TEST(ContactSolver, FrictionIsClampedToTheCone) {
  ContactSolverSettings settings;
  settings.substep = 0.01;
  for (Real slide : {0.01, 3.0}) {
    TwoBodies w;
    // A point mass (huge inertia) so the contact does not spin the body.
    w.masses[0] = BodyMass::make(1.0, Mat3::Identity() * 1e12, false);
    w.states[0].velocity = Vec3(slide * 0.6, slide * 0.8, -9.81 * settings.substep);
    const PairContact c = point_contact(Vec3::Zero(), 0.0, 0.5, 0.0);
    ContactSolver solver;
    solve_rigid(solver, std::span(&c, 1), w, settings);
    const Real normal_impulse = 9.81 * settings.substep;  // mass 1
    const Real max_change = 0.5 * normal_impulse;
    const Vec3 v = w.states[0].velocity;
    EXPECT_NEAR(v.z(), 0.0, 1e-12);
    if (slide < max_change) {
      EXPECT_NEAR(v.head<2>().norm(), 0.0, 1e-12);
    } else {
      EXPECT_NEAR(v.head<2>().norm(), slide - max_change, 1e-9);
      EXPECT_NEAR(v.x() / v.y(), 0.75, 1e-9) << "isotropic: the slide keeps its direction";
    }
  }
}

// One soft pass pushes a penetrating body out at the spring's bias velocity (scaled by the soft
// mass), never faster than max_push_velocity; the relax pass then removes that velocity. The
// expected values follow from the implicit spring-damper discretisation, written out here.
TEST(ContactSolver, SoftPushOutAndRelax) {
  ContactSolverSettings settings;
  settings.substep = 1.0 / 240;
  settings.penetration_slop = 0;
  const Real h = settings.substep;
  // Against a static body the spring is static_contact_hertz; against a moving one (here one so
  // heavy it does not move) contact_hertz.
  for (bool against_static : {true, false}) {
    const Real hertz = against_static ? settings.static_contact_hertz : settings.contact_hertz;
    const Real omega = 2 * std::numbers::pi * hertz;
    const Real zeta = settings.contact_damping_ratio;
    // x'' = -omega^2 x - 2 zeta omega x', backward Euler over h, solved for the velocity.
    const Real a1 = 2 * zeta + h * omega;
    const Real mass_scale = h * omega * a1 / (1 + h * omega * a1);
    for (Real depth : {0.001, 1.0}) {
      TwoBodies w;
      w.masses[0] = BodyMass::make(1.0, Mat3::Identity() * 1e12, false);
      if (!against_static)
        w.masses[1] = BodyMass::make(1e15, Mat3::Identity() * 1e15, false);
      const PairContact c = point_contact(Vec3::Zero(), depth, 0.0, 0.0);
      ContactSolver solver;
      solver.prepare(std::span(&c, 1), {}, w.states, w.masses, settings);
      solver.solve(w.states, true);
      const Real push = std::min(omega / a1 * depth, settings.max_push_velocity);
      EXPECT_NEAR(w.states[0].velocity.z(), mass_scale * push, 1e-12)
          << depth << (against_static ? " static" : " moving");
      for (int i = 0; i < 50; ++i)
        solver.solve(w.states, false);
      EXPECT_NEAR(w.states[0].velocity.z(), 0.0, 1e-12);
    }
  }
}

// A box resting on four points: gravity's velocity is cancelled and the four normal impulses
// carry the weight; the stored impulses alone support it on the next step (warm start).
TEST(ContactSolver, RestingBoxAndWarmStart) {
  ContactSolverSettings settings;
  settings.substep = 1.0 / 240;
  TwoBodies w;
  PairContact c;
  c.body_a = 0;
  c.body_b = 1;
  c.friction = 0.5;
  c.manifold.normal = Vec3::UnitZ();
  w.states[0].position = Vec3(0, 0, 0.5);
  for (int k = 0; k < 4; ++k) {
    const Vec3 corner((k & 1) ? 0.5 : -0.5, (k & 2) ? 0.5 : -0.5, 0);
    c.manifold.add(corner, 0.0, {static_cast<std::uint16_t>(k), 0});
  }
  w.states[0].velocity = Vec3(0, 0, -9.81 * settings.substep);
  ContactSolver solver;
  solve_rigid(solver, std::span(&c, 1), w, settings, 100);
  EXPECT_NEAR(w.states[0].velocity.norm(), 0.0, 1e-9);
  EXPECT_NEAR(w.states[0].angular_velocity.norm(), 0.0, 1e-9);
  std::vector<CachedManifold> cache;
  solver.store(cache);
  ASSERT_EQ(cache.size(), 1u);
  // The cache holds the impulse over the whole step: the substep's times the substeps.
  Real total = 0;
  for (int k = 0; k < 4; ++k)
    total += cache[0].points[k].normal_impulse;
  EXPECT_NEAR(total, 9.81 * settings.substep * settings.substeps, 1e-9);

  w.states[0].velocity = Vec3(0, 0, -9.81 * settings.substep);
  solver.prepare(std::span(&c, 1), cache, w.states, w.masses, settings);
  solver.warm_start(w.states);
  EXPECT_NEAR(w.states[0].velocity.norm(), 0.0, 1e-9);
}

// When feature ids change but a point stays put, the impulse follows it (nearest-point
// fallback), and one cached point never feeds two new ones.
TEST(ContactSolver, WarmStartFallsBackToNearestPoint) {
  ContactSolverSettings settings;
  TwoBodies w;
  std::vector<CachedManifold> cache(1);
  cache[0].body_a = 0;
  cache[0].body_b = 1;
  cache[0].count = 1;
  cache[0].points[0].feature = 99;
  cache[0].points[0].local_point = Vec3(0.1, 0, 0);
  cache[0].points[0].normal_impulse = 2.0;
  PairContact c = point_contact(Vec3(0.1, 0, 0), 0.0, 0.0, 0.0);
  c.manifold.add(Vec3(0.1005, 0, 0), 0.0, {1, 1});  // a second point just as close
  c.match_distance = 0.01;
  ContactSolver solver;
  solver.prepare(std::span(&c, 1), cache, w.states, w.masses, settings);
  solver.warm_start(w.states);
  // The cached impulse is the step's; a substep's warm start applies its share.
  EXPECT_NEAR(w.states[0].velocity.z(), 2.0 / settings.substeps, 1e-12)
      << "exactly one point inherits the impulse";
  c.match_distance = 0.0;
  TwoBodies fresh;
  solver.prepare(std::span(&c, 1), cache, fresh.states, fresh.masses, settings);
  solver.warm_start(fresh.states);
  EXPECT_EQ(fresh.states[0].velocity.z(), 0.0);
}

}  // namespace
}  // namespace tumble
