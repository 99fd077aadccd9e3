// Chains of impacts within one step (engine/continuous_collision.hpp, "rounds of impacts"): both
// bodies of an impact move on through the rest of the step with their new velocities, swept
// again, so that momentum passed along a row of spheres arrives in the same step, and a ball
// that bounces into a corner meets the second wall too, tunnelling through neither. Checked
// against a one-dimensional event-driven reference (each impact in time order, exact) and the
// closed-form path of the ball between two walls; fixed seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "engine/simulation.hpp"
#include "tests/physics/body_builders.hpp"
#include "tests/property_scale.hpp"

namespace tumble::test {
namespace {

constexpr Real kRadius = 0.05;

Scene chain_scene(Real restitution) {
  return frictionless_space("ccd_impact_chain_test", restitution);
}

// Spheres on the x axis, each impact between neighbours taken exactly in time order, the
// impulse of the stepper's law (the approach reflected by e, shared by the inverse masses),
// until `duration`. The stepper resolves an impact `gap` before contact (a quarter of the
// contact margin), so the reference does too. Returns false if more than `max_impacts` happen,
// or two impacts of one body come too close in time to tell their order.
struct Line {
  std::vector<Real> x, v, m;
};
bool run_line(Line& l, Real restitution, Real duration, Real gap, int max_impacts, int& impacts) {
  Real t = 0;
  impacts = 0;
  const std::size_t n = l.x.size();
  // When each body was last hit: an impact that follows another of one of its bodies by less
  // than the stop's tolerance takes (a quarter of the margin at the closing speed) could come
  // in either order in the stepper; the case is not judged.
  std::vector<Real> last_hit(n, -1);
  for (;;) {
    Real first = duration - t;
    std::size_t at = n;
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const Real closing = l.v[i] - l.v[i + 1];
      if (closing <= 0)
        continue;
      const Real when = (l.x[i + 1] - l.x[i] - 2 * kRadius - gap) / closing;
      if (when < first) {
        first = when;
        at = i;
      }
    }
    for (std::size_t i = 0; i < n; ++i)
      l.x[i] += l.v[i] * first;
    t += first;
    if (at == n)
      return true;
    if (++impacts > max_impacts)
      return false;
    const Real window = gap / (l.v[at] - l.v[at + 1]);
    for (const std::size_t body : {at, at + 1}) {
      if (last_hit[body] >= 0 && t - last_hit[body] < window)
        return false;
      last_hit[body] = t;
    }
    const Real approach = l.v[at + 1] - l.v[at];  // of the right one towards the left, < 0
    const Real impulse = -(1 + restitution) * approach / (1 / l.m[at] + 1 / l.m[at + 1]);
    l.v[at + 1] += impulse / l.m[at + 1];
    l.v[at] -= impulse / l.m[at];
  }
}

TEST(CcdImpactChain, ARowOfTenSpheresStruckAt500MetresPerSecondPassesItOnInOneStep) {
  // Newton's cradle: equal spheres, elastic. In one step (1/60 s) the striker covers 8.3 m, so
  // the whole row's impacts fall in the first step; the last sphere must leave at 500 m/s in
  // it. Taking the rest of each step off at every impact, it left in the tenth.
  Scene s = chain_scene(1);
  s.bodies.push_back(
      dynamic_body("striker", Shape::sphere(kRadius), Vec3(-1, 0, 0), Vec3(500, 0, 0), 1));
  for (int k = 0; k < 10; ++k)
    s.bodies.push_back(
        dynamic_body("ball", Shape::sphere(kRadius), Vec3(0.2 * k, 0, 0), Vec3::Zero(), 1));
  Simulation world(std::make_shared<const Scene>(std::move(s)));
  const Real skin = world.scene().world.contact_margin;
  world.step();
  const auto& b = world.state().bodies;
  EXPECT_NEAR(b[10].velocity.x(), 500, 1e-9);
  for (int k = 0; k < 10; ++k) {
    EXPECT_LT(b[std::size_t(k)].velocity.norm(), 1e-9) << k;
    // In order, none through its neighbour.
    EXPECT_GT(b[std::size_t(k) + 1].position.x() - b[std::size_t(k)].position.x(), 2 * kRadius)
        << k;
  }
  // The last one where the exact chain puts it: 500 t past the row's 1.8 m of gaps, each impact
  // taken at most half the contact margin early.
  const Real exact = 1.8 + 500 * world.state().time - 1.8;
  EXPECT_GE(b[10].position.x(), exact - 1e-9);
  EXPECT_LE(b[10].position.x(), exact + 10 * 0.5 * skin);
  EXPECT_LE(world.last_step_statistics().impact_rounds, kMaxImpactRounds);
}

TEST(CcdImpactChain, RandomRowsEndTheStepAsTheExactSequenceOfImpacts) {
  // Rows of 3 to 6 spheres of random masses and gaps, struck at 500 m/s, restitution random:
  // after one step every velocity is the exact sequence's (to rounding) and every position
  // within the stop's tolerance (a quarter of the contact margin) per impact of it.
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<Real> unit(0, 1);
  const int cases = scaled(1000);
  int compared = 0, skipped = 0;
  for (int c = 0; c < cases; ++c) {
    const Real e = 0.5 + 0.5 * unit(rng);
    Scene s = chain_scene(e);
    Line line;
    const int count = 3 + int(rng() % 4);
    Real x = -1;
    for (int k = 0; k < count; ++k) {
      line.x.push_back(x);
      line.v.push_back(k == 0 ? 500 : 0);
      line.m.push_back(0.5 + 1.5 * unit(rng));
      x += 2 * kRadius + 0.05 + 0.25 * unit(rng);
    }
    for (int k = 0; k < count; ++k)
      s.bodies.push_back(dynamic_body("ball", Shape::sphere(kRadius),
                                      Vec3(line.x[std::size_t(k)], 0, 0),
                                      Vec3(line.v[std::size_t(k)], 0, 0), line.m[std::size_t(k)]));
    Simulation world(std::make_shared<const Scene>(std::move(s)));
    world.step();
    int impacts = 0;
    const Real skin = world.scene().world.contact_margin;
    // Beyond the stepper's rounds, or an order of impacts rounding decides: not a case this
    // test can judge. Nor one where two neighbours
    // end the step about to meet, within the stop's tolerance (a quarter of the margin) of the
    // distance at which the stepper resolves an impact: whether that impact falls in this step
    // is then a matter of rounding.
    bool judged =
        run_line(line, e, world.state().time, Real(0.25) * skin, kMaxImpactRounds - 2, impacts);
    for (int k = 0; judged && k + 1 < count; ++k) {
      const Real apart = line.x[std::size_t(k) + 1] - line.x[std::size_t(k)] - 2 * kRadius;
      judged = !(line.v[std::size_t(k)] > line.v[std::size_t(k) + 1] && apart < 0.75 * skin);
    }
    if (!judged) {
      ++skipped;
      continue;
    }
    ++compared;
    for (int k = 0; k < count; ++k) {
      const BodyState& b = world.state().bodies[std::size_t(k)];
      ASSERT_NEAR(b.velocity.x(), line.v[std::size_t(k)], 1e-9 * 500)
          << "case " << c << " body " << k;
      ASSERT_NEAR(b.position.x(), line.x[std::size_t(k)], impacts * 0.25 * skin + 1e-9)
          << "case " << c << " body " << k << " after " << impacts << " impacts";
      if (k + 1 < count) {
        ASSERT_GT(world.state().bodies[std::size_t(k) + 1].position.x() - b.position.x(),
                  2 * kRadius);
      }
    }
  }
  EXPECT_GT(compared, cases * 3 / 4) << skipped << " skipped";
}

TEST(CcdImpactChain, ABallAt1000MetresPerSecondIntoACornerBouncesOffBothWalls) {
  // Two walls 1 mm thick meet in a corner; a 1 cm ball flies at 1000 m/s into it from random
  // directions, meeting both walls within its first step (each 0.5 to 0.9 m away). Each bounce
  // reflects its speed across the wall by e; the ball ends the step where the closed form puts
  // it and never beyond either wall.
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<Real> unit(0, 1);
  const int cases = scaled(500);
  const Real e = 0.8, r = 0.01, speed = 1000;
  for (int c = 0; c < cases; ++c) {
    Scene s = chain_scene(e);
    s.bodies.push_back(static_body("wall_x", Shape::box(Vec3(0.0005, 2, 1)), Vec3(1, 0, 0)));
    s.bodies.push_back(static_body("wall_y", Shape::box(Vec3(2, 0.0005, 1)), Vec3(0, 1, 0)));
    const Real angle = 0.2 + 1.17 * unit(rng);  // 11 to 79 degrees
    const Vec3 v(speed * std::cos(angle), speed * std::sin(angle), 0);
    const Vec3 start(0.1 + 0.4 * unit(rng), 0.1 + 0.4 * unit(rng), 0);
    s.bodies.push_back(dynamic_body("ball", Shape::sphere(r), start, v, 0.01));
    Simulation world(std::make_shared<const Scene>(std::move(s)));
    const Real skin = world.scene().world.contact_margin;
    const Real face = 1 - 0.0005 - r;  // the centre's limit on each axis
    for (int step = 0; step < 3; ++step) {
      world.step();
      const BodyState& b = world.state().bodies[2];
      ASSERT_LT(b.position.x(), face) << "case " << c;
      ASSERT_LT(b.position.y(), face) << "case " << c;
      // Each axis independently: to the wall, back at e times the speed.
      const Real t = world.state().time;
      for (int axis = 0; axis < 2; ++axis) {
        const Real hit = (face - start[axis]) / v[axis];
        const Real exact = t < hit ? start[axis] + v[axis] * t : face - e * v[axis] * (t - hit);
        // The stop comes up to half the margin before the wall, and the ball leaves from there
        // a little earlier: up to (1 + e) times that short of the exact path.
        ASSERT_NEAR(b.position[axis], exact, (1 + e) * 0.5 * skin + 1e-9)
            << "case " << c << " axis " << axis;
        ASSERT_NEAR(b.velocity[axis], t < hit ? v[axis] : -e * v[axis], 1e-9 * speed);
      }
    }
  }
}

}  // namespace
}  // namespace tumble::test
