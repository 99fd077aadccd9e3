// The time-extended SAT for boxes and hulls (collision/ccd/swept_hull_sat.hpp) against
// independent truths:
//   - the static axis set (Gauss-map pruned) against a brute-force SAT over every face normal
//     and every edge-pair cross product with full support scans (test code below): same sign
//     always, same value when overlapping, never above it, never above the GJK distance;
//   - translating hulls against conservative advancement with GJK distances
//     (collision/ccd/conservative_advancement.hpp) and against brute-force sampling; boxes
//     against swept_box_sat;
//   - closed forms: a cube translating face-first onto a cube (gap / speed), a box turning about
//     one of its axes (edge first) and about a random horizontal axis (corner first) into a slab;
//   - turning boxes and hulls (linear and screw motion) against conservative advancement and
//     brute-force sampling: never later than the first contact, never a miss where CA hits;
//   - degenerate input: no motion, touching at s = 0, parallel edges, a hull a hair thick,
//     NaN, unsupported shapes, the iteration cap: each gives a status, never NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "collision/ccd/conservative_advancement.hpp"
#include "collision/ccd/swept_box_sat.hpp"
#include "collision/ccd/swept_hull_sat.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/gjk_epa/gjk_internal.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "tests/ccd/ccd_test_support.hpp"

namespace tumble::testing {
namespace {

std::shared_ptr<const ConvexHull> make_hull(const std::vector<Vec3>& points) {
  return std::make_shared<const ConvexHull>(ConvexHull::from_points(points));
}

// A random hull of 5 to 30 points in an ellipsoid of semi-axes 0.1 to 0.7.
std::shared_ptr<const ConvexHull> random_hull(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> count(5, 30);
  const Vec3 radii = random_vector(rng, 0.1, 0.7);
  std::vector<Vec3> points;
  const int n = count(rng);
  for (int i = 0; i < n; ++i) {
    const Vec3 u = random_unit(rng) * std::cbrt(std::uniform_real_distribution<Real>(0.3, 1)(rng));
    points.push_back(u.cwiseProduct(radii));
  }
  return make_hull(points);
}

std::shared_ptr<const ConvexHull> box_hull(const Vec3& h) {
  std::vector<Vec3> corners;
  for (int k = 0; k < 8; ++k)
    corners.emplace_back(k & 1 ? h.x() : -h.x(), k & 2 ? h.y() : -h.y(), k & 4 ? h.z() : -h.z());
  return make_hull(corners);
}

// The brute-force SAT: every face normal of both and every cross product of an edge of A with
// an edge of B, both signs, each with a full scan of both vertex sets (world frame).
Real brute_gap(const ConvexHull& a, const Transform& pa, const ConvexHull& b, const Transform& pb) {
  std::vector<Vec3> va, vb, axes, ea, eb;
  for (const Vec3& v : a.vertices())
    va.push_back(pa.apply(v));
  for (const Vec3& v : b.vertices())
    vb.push_back(pb.apply(v));
  for (const HullFace& f : a.faces())
    axes.push_back(pa.rotate(f.normal));
  for (const HullFace& f : b.faces())
    axes.push_back(pb.rotate(f.normal));
  for (const HullEdge& e : a.edges())
    ea.push_back(va[std::size_t(e.vertex[1])] - va[std::size_t(e.vertex[0])]);
  for (const HullEdge& e : b.edges())
    eb.push_back(vb[std::size_t(e.vertex[1])] - vb[std::size_t(e.vertex[0])]);
  for (const Vec3& x : ea) {
    for (const Vec3& y : eb) {
      const Vec3 c = x.cross(y);
      if (c.norm() > 1e-9 * x.norm() * y.norm())
        axes.push_back(c.normalized());
    }
  }
  Real best = -1e300;
  for (const Vec3& n0 : axes) {
    for (const Real sign : {Real(1), Real(-1)}) {
      const Vec3 n = sign * n0;
      Real min_a = 1e300, max_b = -1e300;
      for (const Vec3& v : va)
        min_a = std::min(min_a, n.dot(v));
      for (const Vec3& v : vb)
        max_b = std::max(max_b, n.dot(v));
      best = std::max(best, min_a - max_b);
    }
  }
  return best;
}

Real gjk_distance(const Shape& a, const Transform& pa, const Shape& b, const Transform& pb) {
  return gjk(ConvexSupport::of(a, pa), ConvexSupport::of(b, pb)).distance;
}

TEST(SweptHullSat, PrunedAxesMatchTheBruteForceSat) {
  std::mt19937_64 rng(61);
  std::vector<std::shared_ptr<const ConvexHull>> hulls;
  for (int i = 0; i < 40; ++i)
    hulls.push_back(random_hull(rng));
  int apart = 0, overlapping = 0, exact = 0;
  for (int i = 0; i < scaled(3000); ++i) {
    const auto& ha = hulls[std::size_t(i) % hulls.size()];
    const auto& hb = hulls[std::size_t(i / 7) % hulls.size()];
    const Transform pa{random_vector(rng, -0.6, 0.6), random_rotation(rng)};
    const Transform pb{random_vector(rng, -0.6, 0.6), random_rotation(rng)};
    const Shape sa = Shape::convex_hull(ha), sb = Shape::convex_hull(hb);
    const DistanceBound pruned = polytope_separation(sa, pa, sb, pb);
    const Real brute = brute_gap(*ha, pa, *hb, pb);
    ASSERT_TRUE(std::isfinite(pruned.distance));
    ASSERT_EQ(pruned.distance > 1e-12, brute > 1e-12) << "case " << i;
    EXPECT_LE(pruned.distance, brute + 1e-12) << "case " << i;
    // The reported axis has the reported gap.
    Real min_a = 1e300, max_b = -1e300;
    for (const Vec3& v : ha->vertices())
      min_a = std::min(min_a, pruned.normal.dot(pa.apply(v)));
    for (const Vec3& v : hb->vertices())
      max_b = std::max(max_b, pruned.normal.dot(pb.apply(v)));
    EXPECT_NEAR(min_a - max_b, pruned.distance, 1e-12) << "case " << i;
    if (brute <= 0) {
      ++overlapping;
      EXPECT_NEAR(pruned.distance, brute, 1e-12) << "case " << i;  // the penetration depth
    } else {
      ++apart;
      EXPECT_LE(pruned.distance, gjk_distance(sa, pa, sb, pb) + 1e-9) << "case " << i;
      exact += std::abs(pruned.distance - brute) < 1e-12 ? 1 : 0;
    }
  }
  EXPECT_GT(apart, scaled(3000) / 10);
  EXPECT_GT(overlapping, scaled(3000) / 10);
  std::printf("pruned SAT: %d apart (%d equal to brute force), %d overlapping\n", apart, exact,
              overlapping);
}

// Conservative advancement with the GJK distance (the project's time_of_impact), tight.
ToiResult ca(const Shape& a, const RigidMotion& ma, const Shape& b, const RigidMotion& mb,
             Real target = 0) {
  ToiSettings settings;
  settings.tolerance = 1e-12;
  settings.max_iterations = 5000;
  settings.target_distance = target;
  return time_of_impact(a, ma, b, mb, settings);
}

TEST(SweptHullSat, TranslatingHullsAgreeWithConservativeAdvancement) {
  std::mt19937_64 rng(62);
  std::vector<std::shared_ptr<const ConvexHull>> hulls;
  for (int i = 0; i < 40; ++i)
    hulls.push_back(random_hull(rng));
  int hits = 0, misses = 0;
  Real worst = 0;
  for (int i = 0; i < scaled(3000); ++i) {
    const auto& ha = hulls[std::size_t(i) % hulls.size()];
    const auto& hb = hulls[std::size_t(i / 3) % hulls.size()];
    const Transform pa{random_vector(rng, -2, 2), random_rotation(rng)};
    const Transform pb{random_vector(rng, -2, 2), random_rotation(rng)};
    if (brute_gap(*ha, pa, *hb, pb) <= 1e-3)
      continue;
    const Vec3 va = (pb.translation - pa.translation) * 1.3 + random_vector(rng, -1, 1);
    const Vec3 vb = random_vector(rng, -0.5, 0.5);
    const ToiResult sat = swept_hull_sat(*ha, pa, va, *hb, pb, vb);
    ASSERT_NE(sat.status, ToiStatus::invalid_input);
    ASSERT_TRUE(std::isfinite(sat.time_of_impact) && sat.normal.allFinite());
    const Shape sa = Shape::convex_hull(ha), sb = Shape::convex_hull(hb);
    const RigidMotion ma = RigidMotion::from_velocity(pa, va, Vec3::Zero());
    const RigidMotion mb = RigidMotion::from_velocity(pb, vb, Vec3::Zero());
    const ToiResult reference = ca(sa, ma, sb, mb);
    ASSERT_EQ(reference.status == ToiStatus::max_iterations, false) << "case " << i;
    auto gap = [&](Real s) { return brute_gap(*ha, ma.at(s), *hb, mb.at(s)); };
    if (sat.hit() != reference.hit()) {
      // Only a graze can split them: conservative advancement stops within its tolerance of
      // touching; the path must then come that close and no closer than rounding.
      ASSERT_TRUE(reference.hit() && !sat.hit()) << "case " << i;
      EXPECT_GT(gap(reference.time_of_impact), -1e-12) << "case " << i;
      continue;
    }
    if (!sat.hit()) {
      ++misses;
      // Sampling: no overlap anywhere on the path.
      for (int k = 0; k <= 5; ++k)
        ASSERT_GT(gap(k / 5.0), 0) << "case " << i << " s " << k / 5.0;
      continue;
    }
    ++hits;
    EXPECT_NEAR(sat.time_of_impact, reference.time_of_impact, 1e-9) << "case " << i;
    worst = std::max(worst, std::abs(sat.time_of_impact - reference.time_of_impact));
    // Apart just before, touching or overlapping just after; the normal points from B to A.
    EXPECT_GT(gap(sat.time_of_impact - 1e-7), 0) << "case " << i;
    EXPECT_LE(gap(std::min(Real(1), sat.time_of_impact + 1e-7)), 1e-12) << "case " << i;
    EXPECT_NEAR(sat.normal.norm(), 1, 1e-12);
    EXPECT_GT(sat.normal.dot(reference.normal), 0.9) << "case " << i;
  }
  EXPECT_GT(hits, scaled(3000) / 4);
  EXPECT_GT(misses, scaled(3000) / 20);
  std::printf("translating hulls: %d hits, %d misses, largest |t - t_CA| %.3g\n", hits, misses,
              worst);
}

TEST(SweptHullSat, BoxesAreTheSpecialCaseOfSweptBoxSat) {
  std::mt19937_64 rng(63);
  int hits = 0;
  Real worst = 0;
  for (int i = 0; i < scaled(3000); ++i) {
    const Vec3 ha = random_vector(rng, 0.05, 0.6), hb = random_vector(rng, 0.05, 0.6);
    const Transform pa{random_vector(rng, -2, 2), random_rotation(rng)};
    const Transform pb{random_vector(rng, -2, 2), random_rotation(rng)};
    const Vec3 va = (pb.translation - pa.translation) * 1.3 + random_vector(rng, -1, 1);
    const Vec3 vb = random_vector(rng, -0.5, 0.5);
    const ToiResult box = swept_box_sat(ha, pa, va, hb, pb, vb);
    const ToiResult as_boxes =
        time_extended_sat(Shape::box(ha), RigidMotion::from_velocity(pa, va, Vec3::Zero()),
                          Shape::box(hb), RigidMotion::from_velocity(pb, vb, Vec3::Zero()));
    ASSERT_EQ(box.status, as_boxes.status) << "case " << i;
    if (!box.hit())
      continue;
    ++hits;
    EXPECT_NEAR(as_boxes.time_of_impact, box.time_of_impact, 1e-12) << "case " << i;
    worst = std::max(worst, std::abs(as_boxes.time_of_impact - box.time_of_impact));
    if (box.status == ToiStatus::hit) {
      EXPECT_GT(as_boxes.normal.dot(box.normal), 1 - 1e-9) << "case " << i;
    }
    // The same boxes as Qhull hulls (every third case: Qhull is the slow part).
    if (i % 3 == 0) {
      const ToiResult hull = swept_hull_sat(*box_hull(ha), pa, va, *box_hull(hb), pb, vb);
      ASSERT_EQ(hull.status, box.status) << "case " << i;
      EXPECT_NEAR(hull.time_of_impact, box.time_of_impact, 1e-12) << "case " << i;
    }
  }
  EXPECT_GT(hits, scaled(3000) / 3);
  std::printf("boxes: %d hits, largest |t - t_swept_box_sat| %.3g\n", hits, worst);
}

TEST(SweptHullSat, CubeTranslatingFaceFirstOntoACube) {
  std::mt19937_64 rng(64);
  std::uniform_real_distribution<Real> unit(0, 1);
  Real worst = 0;
  for (int i = 0; i < scaled(2000); ++i) {
    const Real size_a = 0.1 + unit(rng), size_b = 0.1 + unit(rng);
    const Real gap = 0.01 + 2 * unit(rng), speed = 0.1 + 5 * unit(rng);
    // A above B, shifted sideways within the face, falling along -z of a random frame; B moves
    // sideways only.
    const Transform frame{random_vector(rng, -5, 5), random_rotation(rng)};
    const Real shift = 0.9 * std::min(size_a, size_b);
    const Vec3 offset(shift * (2 * unit(rng) - 1), shift * (2 * unit(rng) - 1),
                      size_a + size_b + gap);
    const Transform pa{frame.apply(offset), frame.rotation};
    const Transform pb{frame.translation, frame.rotation};
    const Vec3 va = frame.rotate(Vec3(0, 0, -speed));
    const Vec3 vb = frame.rotate(Vec3(0.05 * unit(rng), 0.05 * unit(rng), 0));
    const ToiResult r = time_extended_sat(
        Shape::box(Vec3::Constant(size_a)), RigidMotion::from_velocity(pa, va, Vec3::Zero()),
        Shape::box(Vec3::Constant(size_b)), RigidMotion::from_velocity(pb, vb, Vec3::Zero()));
    const Real exact = gap / speed;
    if (exact > 1) {
      EXPECT_EQ(r.status, ToiStatus::separated) << "case " << i;
      continue;
    }
    ASSERT_EQ(r.status, ToiStatus::hit) << "case " << i;
    EXPECT_NEAR(r.time_of_impact, exact, 1e-12) << "case " << i;
    EXPECT_LT((r.normal - frame.rotate(Vec3::UnitZ())).norm(), 1e-12) << "case " << i;
    worst = std::max(worst, std::abs(r.time_of_impact - exact));
  }
  std::printf("cube onto cube: worst time error %.3g\n", worst);
}

// A slab below z = 0 of the frame (a box 10 x 10 x 1 or its hull) and a box of half extents h
// whose centre stays at height z0 while it turns at a constant rate about the horizontal unit
// axis u. A vertex r (box frame at s = 0) is at height z0 + e_z . R(theta) r with
// R(theta) r = (u.r) u + cos(theta) (r - (u.r) u) + sin(theta) u x r; it touches the slab at the
// first root of z0 + P + Q cos(theta) + S sin(theta) = 0.
Real first_touch_angle(const Vec3& h, const Quat& start, const Vec3& u, Real z0) {
  Real best = 1e300;
  for (int k = 0; k < 8; ++k) {
    const Vec3 r =
        start * Vec3(k & 1 ? h.x() : -h.x(), k & 2 ? h.y() : -h.y(), k & 4 ? h.z() : -h.z());
    const Vec3 along = u.dot(r) * u;
    const Real p = along.z(), q = (r - along).z(), s = u.cross(r).z();
    // q cos + s sin = rho cos(theta - phi) = -(z0 + p)
    const Real rho = std::hypot(q, s), phi = std::atan2(s, q);
    const Real c = -(z0 + p) / rho;
    if (!(c >= -1 && c <= 1))
      continue;
    const Real half = std::acos(c);
    for (const Real root : {phi - half, phi + half}) {
      Real t = std::remainder(root, 2 * M_PI);
      if (t < 0)
        t += 2 * M_PI;
      best = std::min(best, t);
    }
  }
  return best;
}

TEST(SweptHullSat, BoxTurningIntoASlabMatchesTheClosedForm) {
  std::mt19937_64 rng(65);
  std::uniform_real_distribution<Real> unit(0, 1);
  const Vec3 slab_half(10, 10, 1);
  const Shape slab_box = Shape::box(slab_half);
  const Shape slab_hull = Shape::convex_hull(box_hull(slab_half));
  Real worst = 0;
  int cases = 0, capped = 0;
  ToiSettings settings;
  settings.tolerance = 1e-13;
  settings.max_iterations = 20000;
  for (int i = 0; i < scaled(2000); ++i) {
    const Vec3 h(0.1 + unit(rng), 0.1 + unit(rng), 0.1 + unit(rng));
    // Even cases: about the box's own x axis from upright (an edge lands first, the closed form
    // of time_of_impact_test.cpp); odd cases: a random start and a random horizontal axis (a
    // corner lands first).
    const bool edge = i % 2 == 0;
    const Quat start = edge ? Quat::Identity() : random_rotation(rng);
    Vec3 u =
        edge ? Vec3::UnitX() : Vec3(random_unit(rng).x(), random_unit(rng).y(), 0).normalized();
    // Lowest point now and over a half turn: put the slab between them.
    Real lowest_now = 0;
    for (int k = 0; k < 8; ++k)
      lowest_now = std::min(
          lowest_now,
          (start * Vec3(k & 1 ? h.x() : -h.x(), k & 2 ? h.y() : -h.y(), k & 4 ? h.z() : -h.z()))
              .z());
    const Real reach = h.norm();
    const Real z0 = -lowest_now + (reach + lowest_now) * (0.05 + 0.9 * unit(rng));
    const Real theta = first_touch_angle(h, start, u, z0);
    if (!(theta < 2 * M_PI) || theta < 1e-3)
      continue;
    const Real w = theta / (0.05 + 0.9 * unit(rng));
    const Transform frame{random_vector(rng, -5, 5), random_rotation(rng)};
    const Transform box_start{frame.apply(Vec3(0, 0, z0)), frame.rotation * start};
    const RigidMotion box =
        RigidMotion::from_velocity(box_start, Vec3::Zero(), frame.rotate(u * w));
    const Transform slab_pose{frame.apply(Vec3(0, 0, -slab_half.z())), frame.rotation};
    const Shape& slab = i % 4 < 2 ? slab_box : slab_hull;
    const ToiResult r =
        time_extended_sat(Shape::box(h), box, slab, RigidMotion::stationary(slab_pose), settings);
    if (r.status == ToiStatus::max_iterations) {
      ++capped;
      EXPECT_LE(r.time_of_impact, theta / w) << "case " << i;
      continue;
    }
    ASSERT_EQ(r.status, ToiStatus::hit) << "case " << i;
    const Real exact = theta / w;
    EXPECT_LE(r.time_of_impact, exact + 1e-12) << "case " << i;  // never after the contact
    EXPECT_NEAR(r.time_of_impact, exact, 1e-9) << "case " << i;
    EXPECT_LT((r.normal - frame.rotate(Vec3::UnitZ())).norm(), 1e-6) << "case " << i;
    worst = std::max(worst, std::abs(r.time_of_impact - exact));
    ++cases;
  }
  EXPECT_GT(cases, scaled(2000) / 2);
  EXPECT_LE(capped, scaled(2000) / 100);
  std::printf("box turning into a slab: %d cases, %d capped, worst time error %.3g\n", cases,
              capped, worst);
}

}  // namespace
}  // namespace tumble::testing

namespace tumble::testing {
namespace {

// Turning boxes and hulls, linear and screw motion, against conservative advancement with the
// project's distances (box-box SAT bound, GJK for hulls) and brute-force sampling.
TEST(SweptHullSat, TurningBodiesNeverLaterThanTheContact) {
  std::mt19937_64 rng(66);
  std::vector<std::shared_ptr<const ConvexHull>> hulls;
  for (int i = 0; i < 30; ++i)
    hulls.push_back(random_hull(rng));
  int hits = 0, misses = 0, capped = 0, ca_capped = 0, grazes = 0;
  Real worst = 0;
  int worst_case = -1;
  ToiSettings settings;
  settings.tolerance = 1e-12;
  settings.max_iterations = 5000;
  for (int i = 0; i < scaled(1500); ++i) {
    const int kind = i % 3;  // box-box, hull-hull, box-hull
    const Shape a = kind == 1 ? Shape::convex_hull(hulls[std::size_t(i) % hulls.size()])
                              : Shape::box(random_vector(rng, 0.05, 0.6));
    const Shape b = kind == 0 ? Shape::box(random_vector(rng, 0.05, 0.6))
                              : Shape::convex_hull(hulls[std::size_t(i / 3) % hulls.size()]);
    const std::shared_ptr<const ConvexHull> ha =
        a.type == ShapeType::hull ? a.hull : box_hull(a.half_extents);
    const std::shared_ptr<const ConvexHull> hb =
        b.type == ShapeType::hull ? b.hull : box_hull(b.half_extents);
    const Transform pa{random_vector(rng, -2, 2), random_rotation(rng)};
    const Transform pb{random_vector(rng, -2, 2), random_rotation(rng)};
    if (brute_gap(*ha, pa, *hb, pb) <= 1e-3)
      continue;
    const Vec3 va = (pb.translation - pa.translation) * 1.2 + random_vector(rng, -1, 1);
    const RigidMotion linear_a = RigidMotion::from_velocity(pa, va, random_vector(rng, -3, 3));
    const RigidMotion ma =
        i % 2 == 0 ? linear_a : RigidMotion(pa, linear_a.end(), MotionKind::screw);
    const RigidMotion mb =
        RigidMotion::from_velocity(pb, random_vector(rng, -0.5, 0.5), random_vector(rng, -3, 3));
    const ToiResult r = time_extended_sat(a, ma, b, mb, settings);
    ASSERT_NE(r.status, ToiStatus::invalid_input) << "case " << i;
    ASSERT_TRUE(std::isfinite(r.time_of_impact) && std::isfinite(r.distance) &&
                r.normal.allFinite());
    const ToiResult reference = ca(a, ma, b, mb);
    auto gap = [&](Real s) { return brute_gap(*ha, ma.at(s), *hb, mb.at(s)); };
    // Never later than the contact: apart at every sample before the reported time (for a
    // capped search: before the time it reached).
    const Real end = r.hit() || r.status == ToiStatus::max_iterations ? r.time_of_impact : 1;
    for (int k = 0; k < 12; ++k)
      ASSERT_GT(gap(end * k / 12.0), 0) << "case " << i << " sample " << k;
    if (r.status == ToiStatus::max_iterations) {
      ++capped;
      continue;
    }
    if (reference.status == ToiStatus::max_iterations) {
      ++ca_capped;
      continue;
    }
    // No false negative.
    if (reference.hit()) {
      ASSERT_TRUE(r.hit()) << "case " << i << " CA time " << reference.time_of_impact;
    }
    if (!r.hit()) {
      ++misses;
      continue;
    }
    // At the reported time the bodies are within the tolerance of touching, and not past it
    // (up to the rounding of the world-frame brute force).
    EXPECT_LE(gap(r.time_of_impact), 1e-12 + 1e-13) << "case " << i;
    EXPECT_GE(gap(r.time_of_impact), -1e-14) << "case " << i;
    if (!reference.hit()) {
      ++grazes;  // a pass closer than the tolerance that CA's distance does not resolve
      continue;
    }
    ++hits;
    const Real difference = std::abs(r.time_of_impact - reference.time_of_impact);
    if (difference > worst) {
      worst = difference;
      worst_case = i;
    }
    EXPECT_LT(difference, 1e-9) << "case " << i;
  }
  EXPECT_GT(hits, scaled(1500) / 5);
  EXPECT_GT(misses, scaled(1500) / 20);
  EXPECT_LE(capped, scaled(1500) / 100);
  std::printf(
      "turning bodies: %d hits, %d misses, %d grazes, %d capped (CA capped %d), largest |t - "
      "t_CA| %.3g (case %d)\n",
      hits, misses, grazes, capped, ca_capped, worst, worst_case);
}

}  // namespace
}  // namespace tumble::testing

namespace tumble::testing {
namespace {

RigidMotion moving(const Vec3& position, const Quat& rotation, const Vec3& velocity,
                   const Vec3& spin = Vec3::Zero()) {
  return RigidMotion::from_velocity({position, rotation}, velocity, spin);
}

void expect_clean(const ToiResult& r) {
  EXPECT_NE(r.status, ToiStatus::invalid_input);
  EXPECT_TRUE(std::isfinite(r.time_of_impact));
  EXPECT_TRUE(std::isfinite(r.distance));
  EXPECT_TRUE(r.normal.allFinite());
  EXPECT_GE(r.time_of_impact, 0);
  EXPECT_LE(r.time_of_impact, 1);
}

TEST(SweptHullSat, NoMotionGivesSeparatedOrOverlapping) {
  const Shape cube = Shape::box(Vec3::Constant(0.5));
  const RigidMotion still = RigidMotion::stationary({});
  ToiResult r = time_extended_sat(cube, RigidMotion::stationary({Vec3(3, 0, 0), Quat::Identity()}),
                                  cube, still);
  expect_clean(r);
  EXPECT_EQ(r.status, ToiStatus::separated);
  r = time_extended_sat(cube, RigidMotion::stationary({Vec3(0.5, 0.2, 0), Quat::Identity()}), cube,
                        still);
  expect_clean(r);
  EXPECT_EQ(r.status, ToiStatus::overlapping);
  // The same through the screw kind between equal poses.
  const Transform apart{Vec3(0, 0, 2), Quat::Identity()};
  r = time_extended_sat(cube, RigidMotion(apart, apart, MotionKind::screw), cube, still);
  expect_clean(r);
  EXPECT_EQ(r.status, ToiStatus::separated);
  // Spinning in place, far enough that no corner reaches: separated by the advancement.
  r = time_extended_sat(cube, moving(Vec3(2, 0, 0), Quat::Identity(), Vec3::Zero(), Vec3(5, 3, 1)),
                        cube, still);
  expect_clean(r);
  EXPECT_EQ(r.status, ToiStatus::separated);
}

TEST(SweptHullSat, TouchingAtTheStartIsOverlappingAsForConservativeAdvancement) {
  const Shape cube = Shape::box(Vec3::Constant(0.5));
  const RigidMotion below = RigidMotion::stationary({});
  for (const Vec3& velocity : {Vec3(0, 0, -1), Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 0, 0)}) {
    for (const Vec3& spin : {Vec3(0, 0, 0), Vec3(0, 0, 2)}) {
      const RigidMotion above = moving(Vec3(0.3, 0.1, 1), Quat::Identity(), velocity, spin);
      const ToiResult r = time_extended_sat(cube, above, cube, below);
      expect_clean(r);
      EXPECT_EQ(r.status, ToiStatus::overlapping) << velocity.transpose() << " " << spin.z();
      EXPECT_EQ(r.status, time_of_impact(cube, above, cube, below).status);
      EXPECT_LT((r.normal - Vec3::UnitZ()).norm(), 1e-12);
    }
  }
}

// Cube A (half size a) falling at speed 2 onto cube B (half size b), each either upright or
// turned 45 degrees about x so that it shows an edge parallel to x: face on edge, edge on face
// and parallel edges on each other all land at (height - reach_a - reach_b) / speed.
TEST(SweptHullSat, ParallelEdgesAndFacesLandAtTheClosedForm) {
  const Real a = 0.4, b = 0.3, height = 2, speed = 2;
  const Quat turned(Eigen::AngleAxis<Real>(M_PI / 4, Vec3::UnitX()));
  for (int ta = 0; ta < 2; ++ta) {
    for (int tb = 0; tb < 2; ++tb) {
      const Real reach_a = ta == 1 ? a * std::sqrt(Real(2)) : a;
      const Real reach_b = tb == 1 ? b * std::sqrt(Real(2)) : b;
      const Real exact = (height - reach_a - reach_b) / speed;
      const RigidMotion ma =
          moving(Vec3(0.05, 0, height), ta == 1 ? turned : Quat::Identity(), Vec3(0, 0, -speed));
      const RigidMotion mb =
          RigidMotion::stationary({Vec3::Zero(), tb == 1 ? turned : Quat::Identity()});
      const ToiResult boxes =
          time_extended_sat(Shape::box(Vec3::Constant(a)), ma, Shape::box(Vec3::Constant(b)), mb);
      expect_clean(boxes);
      ASSERT_EQ(boxes.status, ToiStatus::hit) << ta << tb;
      EXPECT_NEAR(boxes.time_of_impact, exact, 1e-12) << ta << tb;
      // Parallel edges on each other meet at a corner of the Minkowski difference (in the yz
      // section, the sum of two squares turned 45 degrees is such a square): both of its faces
      // at 45 degrees close at that moment and either is a fair normal.
      const bool edge_on_edge = ta == 1 && tb == 1;
      if (edge_on_edge) {
        EXPECT_NEAR(boxes.normal.z(), std::sqrt(0.5), 1e-12) << ta << tb;
      } else {
        EXPECT_LT((boxes.normal - Vec3::UnitZ()).norm(), 1e-9) << ta << tb;
      }
      const ToiResult hulls =
          swept_hull_sat(*box_hull(Vec3::Constant(a)), ma.start(), ma.linear_velocity(),
                         *box_hull(Vec3::Constant(b)), mb.start(), Vec3::Zero());
      ASSERT_EQ(hulls.status, ToiStatus::hit) << ta << tb;
      EXPECT_NEAR(hulls.time_of_impact, exact, 1e-12) << ta << tb;
      // A stop 0.1 m short along the axis lands 0.1 / speed earlier (edge on edge: the gap
      // along the 45 degree axes is the height over sqrt 2, so 0.1 sqrt 2 / speed).
      const Real early = edge_on_edge ? 0.1 * std::sqrt(Real(2)) / speed : 0.1 / speed;
      const ToiResult short_of =
          swept_hull_sat(*box_hull(Vec3::Constant(a)), ma.start(), ma.linear_velocity(),
                         *box_hull(Vec3::Constant(b)), mb.start(), Vec3::Zero(), 0.1);
      EXPECT_NEAR(short_of.time_of_impact, exact - early, 1e-12) << ta << tb;
    }
  }
}

TEST(SweptHullSat, AHullAHairThickGivesAStatus) {
  // A square plate 1e-6 m thick (Qhull still builds it) falling onto a cube, translating and
  // turning about its normal.
  std::vector<Vec3> plate;
  for (int k = 0; k < 8; ++k)
    plate.emplace_back(k & 1 ? 0.5 : -0.5, k & 2 ? 0.5 : -0.5, k & 4 ? 5e-7 : -5e-7);
  const Shape thin = Shape::convex_hull(make_hull(plate));
  const Shape cube = Shape::box(Vec3::Constant(0.5));
  for (const Real spin : {0.0, 1.0}) {
    const RigidMotion falling =
        moving(Vec3(0.2, 0, 1.5), Quat::Identity(), Vec3(0, 0, -2), Vec3(0, 0, spin));
    ToiSettings settings;
    settings.tolerance = 1e-12;
    const ToiResult r =
        time_extended_sat(thin, falling, cube, RigidMotion::stationary({}), settings);
    expect_clean(r);
    ASSERT_EQ(r.status, ToiStatus::hit);
    EXPECT_NEAR(r.time_of_impact, (1.5 - 5e-7 - 0.5) / 2, 1e-9);
    // Edge on: the plate turned on its side, sliding sideways into the cube.
    const Quat side(Eigen::AngleAxis<Real>(M_PI / 2, Vec3::UnitY()));
    const RigidMotion sliding = moving(Vec3(-2, 0.1, 0.2), side, Vec3(2, 0, 0), Vec3(spin, 0, 0));
    const ToiResult e =
        time_extended_sat(thin, sliding, cube, RigidMotion::stationary({}), settings);
    expect_clean(e);
    ASSERT_EQ(e.status, ToiStatus::hit);
    EXPECT_NEAR(e.time_of_impact, (2 - 5e-7 - 0.5) / 2, 1e-9);
  }
}

TEST(SweptHullSat, BadInputUnsupportedShapesAndTheCapGiveTheirStatus) {
  const Shape cube = Shape::box(Vec3::Constant(0.5));
  const RigidMotion still = RigidMotion::stationary({});
  const RigidMotion nan_motion = moving(Vec3(0, 0, 3), Quat::Identity(), Vec3(0, 0, std::nan("")));
  EXPECT_EQ(time_extended_sat(cube, nan_motion, cube, still).status, ToiStatus::invalid_input);
  const RigidMotion nan_spin =
      moving(Vec3(0, 0, 3), Quat::Identity(), Vec3(0, 0, -3), Vec3(std::nan(""), 0, 0));
  EXPECT_EQ(time_extended_sat(cube, nan_spin, cube, still).status, ToiStatus::invalid_input);
  const RigidMotion falling = moving(Vec3(0, 0, 3), Quat::Identity(), Vec3(0, 0, -3));
  EXPECT_EQ(time_extended_sat(Shape::sphere(0.5), falling, cube, still).status,
            ToiStatus::invalid_input);
  EXPECT_FALSE(time_extended_sat_applies(cube, Shape::plane()));
  EXPECT_TRUE(time_extended_sat_applies(cube, Shape::convex_hull(box_hull(Vec3::Ones()))));
  EXPECT_EQ(polytope_separation(Shape::sphere(1), {}, cube, {}).separating_normal, false);
  // One evaluation cannot settle a fast spin: the cap, with a safe time below the contact.
  ToiSettings one;
  one.max_iterations = 1;
  const RigidMotion spinning =
      moving(Vec3(0, 0, 3), Quat::Identity(), Vec3(0, 0, -3), Vec3(20, 0, 0));
  const ToiResult capped = time_extended_sat(cube, spinning, cube, still, one);
  EXPECT_EQ(capped.status, ToiStatus::max_iterations);
  EXPECT_LT(capped.time_of_impact, 1);
  const ToiResult full = time_extended_sat(cube, spinning, cube, still);
  ASSERT_EQ(full.status, ToiStatus::hit);
  EXPECT_LE(capped.time_of_impact, full.time_of_impact);
}

}  // namespace
}  // namespace tumble::testing
