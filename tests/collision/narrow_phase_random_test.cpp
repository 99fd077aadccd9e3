// Every pair of the narrow phase against independent truth on thousands of random poses (fixed
// seeds): the brute-force signed distance of oracle.hpp (closed forms through an independent
// segment distance for spheres and capsules, a hull enumeration for anything with a box, the
// support map for planes). For each pose the test checks
//   - a contact exists exactly when the shapes are closer than the margin,
//   - the deepest point's depth equals the true signed depth (penetration or -distance),
//   - the normal realises it: the separation along the normal, computed from the support maps,
//     equals the depth, so translating A by (depth + 1e-9) * normal separates the shapes, and
//     (on a subset, with the brute force itself) by (depth - tol) * normal does not,
//   - every point's point_on_a lies in A and point_on_b in B, the deepest on both surfaces,
//   - depths are >= -margin, there are at most 4 points, and nothing is NaN.
// The largest errors seen are printed for the record.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "tests/collision/oracle.hpp"

namespace tumble::testing {
namespace {

struct Tolerances {
  Real absolute = 1e-9;  // times the pair's size
  // Box-box keeps a face axis unless an edge axis is clearly (2% of the face's own overlap plus
  // 1e-5 of the size) better, so the face's overlap may exceed the exact minimum translation,
  // which the reported depth is at least, by that much: by up to (2% of the depth + 1e-5 of the
  // size) / (1 - 2%).
  Real relative_to_depth = 0;
};

struct Stats {
  int poses = 0;
  int with_contact = 0;
  int penetrating = 0;
  int two_or_more_points = 0;
  int depth_error_above_1e9 = 0;  // poses whose depth differs from the truth by > 1e-9
  Real max_depth_error = 0;
  Real max_normal_error = 0;  // |separation along the normal + depth|
  Real max_surface_error = 0;
};

Real size_of(const Shape& s) {
  return s.type == ShapeType::plane ? Real(1) : bounding_radius(s);
}

// Spheres and capsules: the closed form, the distance between the core segments (a sphere's
// core is a segment of length zero) minus the radii; it must agree with the hull brute force.
// Anything else: the brute force.
Real true_signed_distance(const Shape& a, const Transform& pose_a, const Shape& b,
                          const Transform& pose_b) {
  // Sphere and cylinder: the exact distance function of the cylinder at the sphere's centre.
  if (a.type == ShapeType::sphere && b.type == ShapeType::cylinder)
    return signed_distance_to_shape(b, pose_b, pose_a.translation) - a.radius;
  if (a.type == ShapeType::cylinder && b.type == ShapeType::sphere)
    return signed_distance_to_shape(a, pose_a, pose_b.translation) - b.radius;
  const Real brute_force = brute_force_signed_distance(a, pose_a, b, pose_b);
  const auto is_round = [](const Shape& s) {
    return s.type == ShapeType::sphere || s.type == ShapeType::capsule;
  };
  if (!is_round(a) || !is_round(b))
    return brute_force;
  const auto core = [](const Shape& s, const Transform& pose, Real sign) {
    return pose.apply(Vec3(0, 0, sign * s.half_length));
  };
  const Real closed_form = segment_segment_distance(core(a, pose_a, -1), core(a, pose_a, 1),
                                                    core(b, pose_b, -1), core(b, pose_b, 1)) -
                           a.radius - b.radius;
  EXPECT_NEAR(closed_form, brute_force, 1e-12) << "the two oracles disagree";
  return closed_form;
}

void check_pose(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                Real margin, const Tolerances& tolerances, bool translate_with_brute_force,
                Stats& stats) {
  const Real scale = size_of(a) + size_of(b);
  Manifold m;
  const int count = collide(a, pose_a, b, pose_b, margin, m);
  const Real truth = true_signed_distance(a, pose_a, b, pose_b);
  ASSERT_GE(count, 0);
  ASSERT_LE(count, kMaxManifoldPoints);
  Real reported_depth = -truth;
  for (int i = 0; i < count; ++i)
    reported_depth = std::max(reported_depth, m.points[i].depth);
  const Real tolerance = (tolerances.absolute * scale +
                          tolerances.relative_to_depth * std::max(reported_depth, Real(0))) /
                         (1 - tolerances.relative_to_depth);
  ++stats.poses;
  ASSERT_EQ(count, m.count);
  if (count == 0) {
    EXPECT_GT(truth, margin - tolerance) << "no contact, yet the shapes are within the margin";
    return;
  }
  ++stats.with_contact;
  if (truth < 0)
    ++stats.penetrating;
  if (count >= 2)
    ++stats.two_or_more_points;
  EXPECT_LE(truth, margin + tolerance) << "a contact farther apart than the margin";

  const Vec3& n = m.normal;
  ASSERT_TRUE(n.allFinite());
  EXPECT_NEAR(n.norm(), 1, 1e-12);
  const int deepest = deepest_point(m);
  const Real depth = m.points[deepest].depth;
  const Real depth_error = std::abs(depth + truth);
  stats.max_depth_error = std::max(stats.max_depth_error, depth_error);
  if (depth_error > 1e-9)
    ++stats.depth_error_above_1e9;
  EXPECT_LE(depth_error, tolerance) << "depth " << depth << " truth " << -truth;

  // The normal realises the depth: moving A by `depth` along it makes them just touch.
  const Real separation = separation_along(a, pose_a, b, pose_b, n);
  const Real normal_error = std::abs(separation + depth);
  stats.max_normal_error = std::max(stats.max_normal_error, normal_error);
  EXPECT_LE(normal_error, tolerance) << "separation along the normal " << separation;

  // Two capsules lying nearly parallel get the two ends of their overlap, each with the depth
  // along the shared normal. When the cores are at an angle up to asin(0.02), an end's own
  // closest points are not along the shared normal: they are displaced sideways by up to 0.02
  // times (overlap length + core distance), l, so a reconstructed surface point may stick out
  // by l^2 / (2 r): that is the allowance, and neither end is then required to sit exactly on
  // both surfaces.
  Real allowance = tolerance;
  bool deepest_is_exact = true;
  if (a.type == ShapeType::capsule && b.type == ShapeType::capsule && count == 2) {
    const Real overlap = 2 * std::min(a.half_length, b.half_length);
    const Real sideways = Real(0.02) * (overlap + a.radius + b.radius + margin);
    allowance += sideways * sideways / (2 * std::min(a.radius, b.radius));
    deepest_is_exact = false;
  }
  for (int i = 0; i < count; ++i) {
    const ContactPoint& p = m.points[i];
    ASSERT_TRUE(p.position.allFinite());
    ASSERT_TRUE(std::isfinite(p.depth));
    EXPECT_GE(p.depth, -margin - 1e-12);
    const Real in_a = signed_distance_to_shape(a, pose_a, p.point_on_a(n));
    const Real in_b = signed_distance_to_shape(b, pose_b, p.point_on_b(n));
    EXPECT_LE(in_a, allowance) << "point_on_a outside A";
    EXPECT_LE(in_b, allowance) << "point_on_b outside B";
    if (i == deepest && deepest_is_exact) {
      stats.max_surface_error = std::max({stats.max_surface_error, std::abs(in_a), std::abs(in_b)});
      EXPECT_LE(std::abs(in_a), tolerance) << "deepest point_on_a not on A's surface";
      EXPECT_LE(std::abs(in_b), tolerance) << "deepest point_on_b not on B's surface";
    }
  }

  if (translate_with_brute_force) {
    Transform moved = pose_a;
    // Box-box may report a face axis up to its preference tolerance away from the minimum; the
    // tolerance then covers the difference (it is 0 for every other pair).
    const Real preference = tolerance - tolerances.absolute * scale;
    moved.translation = pose_a.translation + n * (depth + preference + 1e-9 * scale);
    EXPECT_GE(true_signed_distance(a, moved, b, pose_b), -1e-11 * scale)
        << "translating by depth + 1e-9 along the normal does not separate";
    const Real short_of = std::max(Real(1e-6) * scale, 2 * tolerance);
    moved.translation = pose_a.translation + n * (depth - short_of);
    EXPECT_LT(true_signed_distance(a, moved, b, pose_b), 0)
        << "translating by depth - tol along the normal already separates";
  }
}

void print(const char* pair, const Stats& s) {
  std::printf(
      "[ stats    ] %-16s poses %5d  contact %5d  penetrating %5d  >=2 points %5d  max |depth "
      "error| %.2e (%d above 1e-9)  max |normal error| %.2e  max surface error %.2e\n",
      pair, s.poses, s.with_contact, s.penetrating, s.two_or_more_points, s.max_depth_error,
      s.depth_error_above_1e9, s.max_normal_error, s.max_surface_error);
}

// B's pose near A's: a random offset up to 1.1 times the sum of their bounding radii, and with
// probability `aligned_fraction` a rotation equal to A's up to a small (or no) tilt, which makes
// the face-face and parallel cases that resting contact produces.
Transform pose_near(Rng& rng, const Shape& a, const Transform& pose_a, const Shape& b,
                    Real aligned_fraction) {
  Transform pose_b;
  pose_b.translation = pose_a.translation + random_unit_vector(rng) * uniform(rng, 0, 1.1) *
                                                (bounding_radius(a) + bounding_radius(b));
  const Real kind = uniform(rng, 0, 1);
  if (kind < aligned_fraction * 0.3) {
    pose_b.rotation = pose_a.rotation;
  } else if (kind < aligned_fraction) {
    const Quat tilt(Eigen::AngleAxis<Real>(uniform(rng, 0, 0.05), random_unit_vector(rng)));
    pose_b.rotation = pose_a.rotation * tilt;
  } else {
    pose_b.rotation = random_rotation(rng);
  }
  return pose_b;
}

void run_bounded_pair(ShapeType type_a, ShapeType type_b, int poses, std::uint64_t seed,
                      const Tolerances& tolerances, int brute_translation_every,
                      Real aligned_fraction) {
  Rng rng(seed);
  Stats stats;
  for (int i = 0; i < poses; ++i) {
    const Shape a = random_shape(rng, type_a);
    const Shape b = random_shape(rng, type_b);
    const Transform pose_a{random_vector_in_box(rng, 2), random_rotation(rng)};
    const Transform pose_b = pose_near(rng, a, pose_a, b, aligned_fraction);
    const Real margin = uniform(rng, 0, 0.3);
    SCOPED_TRACE("pose " + std::to_string(i));
    check_pose(a, pose_a, b, pose_b, margin, tolerances, i % brute_translation_every == 0, stats);
    if (::testing::Test::HasFatalFailure())
      return;
  }
  const std::string name =
      std::string(shape_type_name(type_a)) + "-" + std::string(shape_type_name(type_b));
  print(name.c_str(), stats);
  // The sample must exercise both penetrating and separated-within-margin poses.
  EXPECT_GT(stats.penetrating, poses / 10);
  EXPECT_GT(stats.with_contact - stats.penetrating, poses / 50);
}

void run_plane_pair(ShapeType type_a, int poses, std::uint64_t seed) {
  Rng rng(seed);
  Stats stats;
  const Shape plane = Shape::plane();
  for (int i = 0; i < poses; ++i) {
    const Shape a = random_shape(rng, type_a);
    const Transform pose_plane{random_vector_in_box(rng, 3), random_rotation(rng)};
    const Vec3 normal = pose_plane.rotate(Vec3::UnitZ());
    Transform pose_a{pose_plane.translation +
                         normal * uniform(rng, -0.8, 1.3) * bounding_radius(a) +
                         random_vector_in_box(rng, 2),
                     random_rotation(rng)};
    if (uniform(rng, 0, 1) < 0.3) {
      // Resting-like: A's frame aligned with the plane's, up to a small tilt.
      pose_a.rotation = pose_plane.rotation * Quat(Eigen::AngleAxis<Real>(uniform(rng, 0, 0.02),
                                                                          random_unit_vector(rng)));
    }
    const Real margin = uniform(rng, 0, 0.3);
    SCOPED_TRACE("pose " + std::to_string(i));
    check_pose(a, pose_a, plane, pose_plane, margin, {}, true, stats);
    if (::testing::Test::HasFatalFailure())
      return;
  }
  const std::string name = std::string(shape_type_name(type_a)) + "-plane";
  print(name.c_str(), stats);
  EXPECT_GT(stats.penetrating, poses / 10);
  EXPECT_GT(stats.with_contact - stats.penetrating, poses / 50);
}

TEST(NarrowPhaseRandom, SphereSphereMatchesClosedForm) {
  run_bounded_pair(ShapeType::sphere, ShapeType::sphere, 5000, 101, {}, 1, 0);
}

TEST(NarrowPhaseRandom, SphereCapsuleMatchesClosedForm) {
  run_bounded_pair(ShapeType::sphere, ShapeType::capsule, 5000, 102, {}, 1, 0);
}

TEST(NarrowPhaseRandom, CapsuleCapsuleMatchesClosedForm) {
  run_bounded_pair(ShapeType::capsule, ShapeType::capsule, 5000, 103, {}, 1, 0.4);
}

TEST(NarrowPhaseRandom, SphereBoxMatchesBruteForce) {
  run_bounded_pair(ShapeType::sphere, ShapeType::box, 4000, 104, {}, 1, 0);
}

TEST(NarrowPhaseRandom, CapsuleBoxMatchesBruteForce) {
  run_bounded_pair(ShapeType::capsule, ShapeType::box, 4000, 105, {}, 2, 0.4);
}

TEST(NarrowPhaseRandom, BoxBoxMatchesBruteForce) {
  run_bounded_pair(ShapeType::box, ShapeType::box, 2000, 106, {1e-5, 0.02}, 10, 0.4);
}

TEST(NarrowPhaseRandom, SpherePlaneMatchesSupportMap) {
  run_plane_pair(ShapeType::sphere, 3000, 107);
}

TEST(NarrowPhaseRandom, CapsulePlaneMatchesSupportMap) {
  run_plane_pair(ShapeType::capsule, 3000, 108);
}

TEST(NarrowPhaseRandom, BoxPlaneMatchesSupportMap) {
  run_plane_pair(ShapeType::box, 3000, 109);
}

// The hull and cylinder shapes: hulls against every shape the brute force covers, the exact
// sphere-cylinder pair, and the plane pairs of cylinder and hull.
TEST(NarrowPhaseRandom, SphereHullMatchesBruteForce) {
  run_bounded_pair(ShapeType::sphere, ShapeType::hull, 1500, 110, {}, 3, 0);
}

TEST(NarrowPhaseRandom, CapsuleHullMatchesBruteForce) {
  run_bounded_pair(ShapeType::capsule, ShapeType::hull, 1500, 111, {}, 3, 0.4);
}

TEST(NarrowPhaseRandom, BoxHullMatchesBruteForce) {
  run_bounded_pair(ShapeType::box, ShapeType::hull, 1500, 112, {}, 3, 0.4);
}

// Hull-hull runs the separating-axis pair (hull_hull_sat.cpp), which keeps a face axis unless an
// edge axis is clearly better, with the same preference as box-box; the query under it matches
// brute force to 1e-9 (tests/collision/hull_hull_sat_test.cpp).
TEST(NarrowPhaseRandom, HullHullMatchesBruteForce) {
  run_bounded_pair(ShapeType::hull, ShapeType::hull, 1500, 113, {1e-5, 0.02}, 3, 0.4);
}

TEST(NarrowPhaseRandom, SphereCylinderMatchesDistanceFunction) {
  run_bounded_pair(ShapeType::sphere, ShapeType::cylinder, 4000, 114, {}, 1, 0);
}

TEST(NarrowPhaseRandom, CylinderPlaneMatchesSupportMap) {
  run_plane_pair(ShapeType::cylinder, 3000, 115);
}

TEST(NarrowPhaseRandom, HullPlaneMatchesSupportMap) {
  run_plane_pair(ShapeType::hull, 3000, 116);
}

}  // namespace
}  // namespace tumble::testing
