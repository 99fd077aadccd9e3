// Conservative advancement against closed forms and brute force:
//   - sphere-sphere, sphere-plane and a box corner turning into a plane: the time of impact
//     within 1e-9 of the analytic root (thousands of random cases);
//   - every pair of current shapes under random linear and screw motion with rotation: they never
//     overlap at any of 2000 sampled times before the reported time of impact (no tunneling),
//     and at a hit they are within the target distance; a reported miss has no overlapping
//     sample at all;
//   - the time-extended SAT of translating boxes against conservative advancement and against
//     sampling;
//   - the iteration cap and invalid input give their status.
#include <gtest/gtest.h>

#include <cmath>

#include "collision/ccd/conservative_advancement.hpp"
#include "collision/ccd/swept_box_sat.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"
#include "tests/ccd/ccd_test_support.hpp"

namespace tumble::testing {
namespace {

ToiSettings precise() {
  ToiSettings s;
  s.tolerance = 1e-13;
  s.max_iterations = 1000;
  return s;
}

TEST(TimeOfImpact, SphereSphereMatchesTheQuadraticRoot) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<Real> radius(0.05, 1.0);
  Real worst = 0;
  int hits = 0;
  for (int i = 0; i < scaled(3000); ++i) {
    const Real ra = radius(rng), rb = radius(rng);
    const Vec3 pa = random_vector(rng, -5, 5), pb = random_vector(rng, -5, 5);
    if ((pa - pb).norm() <= ra + rb + 1e-3)
      continue;
    // Aim roughly at the other sphere so that most cases hit, some graze, some miss.
    const Vec3 va =
        (pb - pa) * std::uniform_real_distribution<Real>(0.2, 1.5)(rng) + random_vector(rng, -1, 1);
    const Vec3 vb = random_vector(rng, -1, 1);
    const RigidMotion ma =
        RigidMotion::from_velocity({pa, random_rotation(rng)}, va, random_vector(rng, -3, 3));
    const RigidMotion mb = RigidMotion::from_velocity({pb, random_rotation(rng)}, vb, Vec3::Zero());
    // |d + s w| = R, first root.
    const Vec3 d = pa - pb, w = va - vb;
    const Real big_r = ra + rb;
    const Real a = w.squaredNorm(), b = d.dot(w), c = d.squaredNorm() - big_r * big_r;
    const Real disc = b * b - a * c;
    const bool analytic_hit = disc > 0 && b < 0 && c / (-b + std::sqrt(disc)) <= 1;
    const ToiResult r = time_of_impact(Shape::sphere(ra), ma, Shape::sphere(rb), mb, precise());
    // Grazing cases whose root is within 1e-7 of the closest approach are ambiguous at the
    // target distance: skip them rather than loosen the tolerance.
    if (disc > 0 && disc < 1e-7 * a)
      continue;
    ASSERT_EQ(r.hit(), analytic_hit) << "case " << i;
    if (analytic_hit) {
      ++hits;
      const Real exact = c / (-b + std::sqrt(disc));
      EXPECT_NEAR(r.time_of_impact, exact, 1e-9) << "case " << i;
      // Conservative: asked to stop 1e-12 short, it never reports a time after the contact.
      ToiSettings short_of_contact = precise();
      short_of_contact.target_distance = 1e-12;
      EXPECT_LE(time_of_impact(Shape::sphere(ra), ma, Shape::sphere(rb), mb, short_of_contact)
                    .time_of_impact,
                exact);
      worst = std::max(worst, std::abs(r.time_of_impact - exact));
    }
  }
  EXPECT_GT(hits, scaled(3000) / 4);
  std::printf("sphere-sphere: %d hits, worst time error %.3g\n", hits, worst);
}

TEST(TimeOfImpact, SpherePlaneMatchesTheLinearRoot) {
  std::mt19937_64 rng(32);
  Real worst = 0;
  for (int i = 0; i < scaled(3000); ++i) {
    const Transform plane_pose{random_vector(rng, -3, 3), random_rotation(rng)};
    const Vec3 n = plane_pose.rotate(Vec3::UnitZ());
    const Real r = std::uniform_real_distribution<Real>(0.01, 1)(rng);
    const Real height = std::uniform_real_distribution<Real>(r + 0.01, 5)(rng);
    const Vec3 p = plane_pose.translation + height * n + random_vector(rng, -3, 3).cross(n);
    const Vec3 v = -std::uniform_real_distribution<Real>(0.1, 10)(rng) * n +
                   random_vector(rng, -2, 2).cross(n);
    const ToiResult res = time_of_impact(
        Shape::sphere(r), RigidMotion::from_velocity({p, random_rotation(rng)}, v, Vec3::Zero()),
        Shape::plane(), RigidMotion::stationary(plane_pose), precise());
    const Real exact = (height - r) / -v.dot(n);
    if (exact > 1) {
      EXPECT_FALSE(res.hit());
      continue;
    }
    ASSERT_EQ(res.status, ToiStatus::hit) << "case " << i;
    EXPECT_NEAR(res.time_of_impact, exact, 1e-9);
    EXPECT_LT((res.normal - n).norm(), 1e-9);
    worst = std::max(worst, std::abs(res.time_of_impact - exact));
  }
  std::printf("sphere-plane: worst time error %.3g\n", worst);
}

// A box of half extents h turning about its local x axis at rate w, centre fixed at height z0
// above a plane. Its lowest point lies hy sin(theta) + hz cos(theta) = rho cos(theta - phi)
// below the centre (theta in [0, pi/2]), so the corner touches at theta = phi - acos(z0 / rho).
TEST(TimeOfImpact, BoxCornerTurningIntoAPlaneMatchesTheClosedForm) {
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<Real> unit(0, 1);
  Real worst = 0;
  int cases = 0;
  for (int i = 0; i < scaled(2000); ++i) {
    const Vec3 h(0.1 + unit(rng), 0.1 + unit(rng), 0.1 + unit(rng));
    const Real rho = std::hypot(h.y(), h.z());
    const Real phi = std::atan2(h.y(), h.z());
    const Real z0 = h.z() + (rho - h.z()) * (0.05 + 0.9 * unit(rng));
    const Real theta = phi - std::acos(z0 / rho);
    const Real w = theta / (0.05 + 0.9 * unit(rng));  // so that the hit is inside the step
    // The whole set-up in a random frame.
    const Transform frame{random_vector(rng, -5, 5), random_rotation(rng)};
    const Transform box_start{frame.apply(Vec3(0, 0, z0)), frame.rotation};
    const RigidMotion box =
        RigidMotion::from_velocity(box_start, Vec3::Zero(), frame.rotate(Vec3(w, 0, 0)));
    const ToiResult res = time_of_impact(Shape::box(h), box, Shape::plane(),
                                         RigidMotion::stationary(frame), precise());
    ASSERT_EQ(res.status, ToiStatus::hit) << "case " << i;
    const Real exact = theta / w;
    EXPECT_NEAR(res.time_of_impact, exact, 1e-9) << "case " << i;
    worst = std::max(worst, std::abs(res.time_of_impact - exact));
    ++cases;
  }
  std::printf("box corner into plane: %d cases, worst time error %.3g\n", cases, worst);
}

Shape random_shape(std::mt19937_64& rng, int type) {
  std::uniform_real_distribution<Real> size(0.05, 0.8);
  switch (type) {
    case 0:
      return Shape::sphere(size(rng));
    case 1:
      return Shape::box(Vec3(size(rng), size(rng), size(rng)));
    default:
      return Shape::capsule(size(rng), size(rng));
  }
}

Real true_distance(const Shape& a, const Transform& pa, const Shape& b, const Transform& pb) {
  // The narrow phase's deepest point is the exact signed distance for every pair but box-box;
  // for box-box the SAT separation is exact whenever the boxes overlap (its sign is exact).
  if (a.type == ShapeType::box && b.type == ShapeType::box)
    return box_box_separation(a.half_extents, pa, b.half_extents, pb).distance;
  Manifold m;
  if (collide(a, pa, b, pb, 100, m) == 0)
    return 100;
  Real deepest = m.points[0].depth;
  for (int k = 1; k < m.count; ++k)
    deepest = std::max(deepest, m.points[k].depth);
  return -deepest;
}

TEST(TimeOfImpact, NeverTunnelsThroughAnyPairOfShapes) {
  std::mt19937_64 rng(34);
  int hits = 0, misses = 0, capped = 0;
  for (int i = 0; i < scaled(1500); ++i) {
    const int ta = i % 3, tb = (i / 3) % 4;  // tb == 3: a plane
    const Shape a = random_shape(rng, ta);
    const Shape b = tb == 3 ? Shape::plane() : random_shape(rng, tb);
    const Transform pa{random_vector(rng, -2, 2), random_rotation(rng)};
    const Transform pb{tb == 3 ? Vec3(pa.translation - Vec3(0, 0, 2.5)) : random_vector(rng, -2, 2),
                       tb == 3 ? Quat::Identity() : random_rotation(rng)};
    if (true_distance(a, pa, b, pb) <= 1e-3)
      continue;
    const Vec3 va = (pb.translation - pa.translation) * 1.2 + random_vector(rng, -1.5, 1.5);
    // Every other case moves A along the screw motion between the same two poses.
    const RigidMotion linear_a = RigidMotion::from_velocity(pa, va, random_vector(rng, -3, 3));
    const RigidMotion ma =
        i % 2 == 0 ? linear_a : RigidMotion(pa, linear_a.end(), MotionKind::screw);
    const RigidMotion mb = tb == 3 ? RigidMotion::stationary(pb)
                                   : RigidMotion::from_velocity(pb, random_vector(rng, -1, 1),
                                                                random_vector(rng, -8, 8));
    ToiSettings settings;
    settings.tolerance = 1e-6;
    settings.max_iterations = 500;
    const ToiResult r = time_of_impact(a, ma, b, mb, settings);
    ASSERT_NE(r.status, ToiStatus::invalid_input) << "case " << i;
    // A capped search is safe up to the time it reached (grazing motions with fast spin
    // converge slowly): check that span, and that capping stays rare.
    capped += r.status == ToiStatus::max_iterations ? 1 : 0;
    const Real end = r.hit() || r.status == ToiStatus::max_iterations ? r.time_of_impact : 1;
    for (int k = 0; k <= 2000; ++k) {
      const Real s = end * k / 2000.0;
      ASSERT_GT(true_distance(a, ma.at(s), b, mb.at(s)), 0)
          << "tunneled: case " << i << " types " << ta << "," << tb << " s " << s << " toi "
          << r.time_of_impact;
    }
    if (r.status == ToiStatus::max_iterations)
      continue;
    if (r.hit()) {
      ++hits;
      EXPECT_LE(true_distance(a, ma.at(r.time_of_impact), b, mb.at(r.time_of_impact)), 1e-6);
    } else {
      ++misses;
    }
  }
  EXPECT_GT(hits, 100);
  EXPECT_GT(misses, 100);
  EXPECT_LE(capped, scaled(1500) / 100);
  std::printf("any pair: %d hits, %d misses, %d capped at 500 iterations\n", hits, misses, capped);
}

TEST(SweptBoxSat, AgreesWithConservativeAdvancementAndSampling) {
  std::mt19937_64 rng(35);
  int hits = 0;
  Real worst = 0;
  for (int i = 0; i < scaled(2000); ++i) {
    const Vec3 ha(0.1 + 0.5 * std::abs(random_vector(rng, -1, 1).x()), 0.3, 0.2);
    const Vec3 hb = random_vector(rng, 0.05, 0.6);
    const Transform pa{random_vector(rng, -2, 2), random_rotation(rng)};
    const Transform pb{random_vector(rng, -2, 2), random_rotation(rng)};
    if (box_box_separation(ha, pa, hb, pb).distance <= 1e-3)
      continue;
    const Vec3 va = (pb.translation - pa.translation) * 1.3 + random_vector(rng, -1, 1);
    const Vec3 vb = random_vector(rng, -0.5, 0.5);
    const ToiResult sat = swept_box_sat(ha, pa, va, hb, pb, vb);
    ToiSettings settings;
    settings.tolerance = 1e-10;
    settings.max_iterations = 2000;
    Transform ea = pa, eb = pb;
    ea.translation += va;
    eb.translation += vb;
    const ToiResult ca = time_of_impact(Shape::box(ha), RigidMotion(pa, ea), Shape::box(hb),
                                        RigidMotion(pb, eb), settings);
    ASSERT_NE(ca.status, ToiStatus::max_iterations);
    ASSERT_EQ(sat.hit(), ca.hit()) << "case " << i;
    if (!sat.hit())
      continue;
    ++hits;
    EXPECT_NEAR(sat.time_of_impact, ca.time_of_impact, 1e-6) << "case " << i;
    worst = std::max(worst, std::abs(sat.time_of_impact - ca.time_of_impact));
    // Sampling: apart just before, overlapping just after.
    auto gap = [&](Real s) {
      Transform a = pa, b = pb;
      a.translation += s * va;
      b.translation += s * vb;
      return box_box_separation(ha, a, hb, b).distance;
    };
    EXPECT_GT(gap(sat.time_of_impact - 1e-7), 0);
    EXPECT_LE(gap(std::min(Real(1), sat.time_of_impact + 1e-7)), 1e-12);
  }
  EXPECT_GT(hits, 200);
  std::printf("swept SAT vs CA: %d hits, largest time difference %.3g\n", hits, worst);
}

TEST(TimeOfImpact, StatusesForCapsAndBadInput) {
  const RigidMotion a =
      RigidMotion::from_velocity({Vec3(0, 0, 5), Quat::Identity()}, Vec3(0, 0, -10), Vec3(0, 0, 0));
  ToiSettings one;
  one.max_iterations = 1;
  one.tolerance = 1e-12;
  // A box spinning fast: one step of advancement cannot reach a verdict.
  const RigidMotion spinning = RigidMotion::from_velocity({Vec3(0, 0, 5), Quat::Identity()},
                                                          Vec3(0, 0, -10), Vec3(50, 0, 0));
  const ToiResult capped = time_of_impact(Shape::box(Vec3(1, 1, 1)), spinning, Shape::plane(),
                                          RigidMotion::stationary({}), one);
  EXPECT_EQ(capped.status, ToiStatus::max_iterations);
  EXPECT_LT(capped.time_of_impact, 1);
  const RigidMotion bad = RigidMotion::from_velocity({Vec3(0, 0, 5), Quat::Identity()},
                                                     Vec3(0, 0, std::nan("")), Vec3::Zero());
  EXPECT_EQ(
      time_of_impact(Shape::sphere(1), bad, Shape::plane(), RigidMotion::stationary({})).status,
      ToiStatus::invalid_input);
  // Already overlapping.
  EXPECT_EQ(
      time_of_impact(Shape::sphere(1), RigidMotion::stationary({Vec3(0, 0, 0.5), Quat::Identity()}),
                     Shape::plane(), RigidMotion::stationary({}))
          .status,
      ToiStatus::overlapping);
  // Shape cast: a sphere swept 10 m down onto a plane 4 m below its surface.
  const ToiResult cast = shape_cast(Shape::sphere(1), {Vec3(0, 0, 5), Quat::Identity()},
                                    Vec3(0, 0, -10), Shape::plane(), {});
  ASSERT_EQ(cast.status, ToiStatus::hit);
  EXPECT_NEAR(cast.time_of_impact, 0.4, 1e-6);
  (void)a;
}

}  // namespace
}  // namespace tumble::testing
