// The contract every entry of the dispatch table keeps (narrow_phase.hpp, contact.hpp):
// swapping A and B flips the normal and swaps feature ids and changes nothing else; a pair far
// from the origin gives the answer it gives at the origin; degenerate inputs give finite unit
// normals; feature ids do not change under small motions.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "tests/collision/oracle.hpp"
#include "tests/property_scale.hpp"

namespace tumble::testing {
namespace {

constexpr std::array<ShapeType, 6> kTypes = {ShapeType::sphere,   ShapeType::box,
                                             ShapeType::capsule,  ShapeType::plane,
                                             ShapeType::cylinder, ShapeType::hull};

std::string pair_name(ShapeType a, ShapeType b) {
  return std::string(shape_type_name(a)) + "-" + std::string(shape_type_name(b));
}

// Poses that put the two shapes near each other (about half of them touching).
void random_nearby_poses(Rng& rng, const Shape& a, const Shape& b, Transform& pose_a,
                         Transform& pose_b) {
  const auto reach = [](const Shape& s) { return s.is_bounded() ? bounding_radius(s) : 0.0; };
  pose_a = {random_vector_in_box(rng, 2), random_rotation(rng)};
  pose_b.rotation = random_rotation(rng);
  if (b.type == ShapeType::plane) {
    // B's plane passes near A: at a height up to A's size on either side.
    pose_b.translation = pose_a.translation -
                         pose_b.rotate(Vec3::UnitZ()) * uniform(rng, -0.7, 1.2) * reach(a) +
                         random_vector_in_box(rng, 1).cross(pose_b.rotate(Vec3::UnitZ()));
  } else if (a.type == ShapeType::plane) {
    pose_b.translation = pose_a.translation +
                         pose_a.rotate(Vec3::UnitZ()) * uniform(rng, -0.7, 1.2) * reach(b) +
                         random_vector_in_box(rng, 1).cross(pose_a.rotate(Vec3::UnitZ()));
  } else {
    pose_b.translation =
        pose_a.translation + random_unit_vector(rng) * uniform(rng, 0, 1.1) * (reach(a) + reach(b));
    if (uniform(rng, 0, 1) < 0.3)
      pose_b.rotation = pose_a.rotation;  // face-face, parallel
  }
}

TEST(NarrowPhaseContract, SwappingShapesFlipsNormalAndSwapsFeaturesExactly) {
  Rng rng(201);
  for (const ShapeType ta : kTypes) {
    for (const ShapeType tb : kTypes) {
      SCOPED_TRACE(pair_name(ta, tb));
      int with_contact = 0;
      const int poses = 600;
      for (int i = 0; i < poses; ++i) {
        const Shape a = random_shape(rng, ta);
        const Shape b = random_shape(rng, tb);
        Transform pose_a;
        Transform pose_b;
        random_nearby_poses(rng, a, b, pose_a, pose_b);
        const Real margin = uniform(rng, 0, 0.2);
        Manifold ab;
        Manifold ba;
        const int count_ab = collide(a, pose_a, b, pose_b, margin, ab);
        const int count_ba = collide(b, pose_b, a, pose_a, margin, ba);
        ASSERT_EQ(count_ab, count_ba) << "pose " << i;
        if (count_ab == 0)
          continue;
        ++with_contact;
        // By construction the two calls run the same arithmetic, so equality is exact.
        EXPECT_EQ(ab.normal, Vec3(-ba.normal)) << "pose " << i;
        for (int k = 0; k < count_ab; ++k) {
          EXPECT_EQ(ab.points[k].position, ba.points[k].position) << "pose " << i;
          EXPECT_EQ(ab.points[k].depth, ba.points[k].depth) << "pose " << i;
          EXPECT_EQ(ab.points[k].feature, ba.points[k].feature.swapped()) << "pose " << i;
        }
      }
      if (ta == ShapeType::plane && tb == ShapeType::plane) {
        EXPECT_EQ(with_contact, 0) << "planes never collide";
      } else {
        EXPECT_GT(with_contact, poses / 5) << "too few touching poses to test anything";
      }
    }
  }
}

// Two compounds of one volume and part count at one pose are not twins when their parts differ:
// the order of the pair comes from their parts, so either call gives the mirrored answer, points
// in the same order. Found by fuzz_narrow_phase: both calls took their own first argument first,
// and the four merged points came out in another order.
TEST(NarrowPhaseContract, EqualCompoundsAtOnePoseAreOrderedByTheirParts) {
  const Quat quarter_about_y(Eigen::AngleAxis<Real>(std::numbers::pi_v<Real> / 2, Vec3::UnitY()));
  const Shape a = compound_from_parts(
      {{Shape::box(Vec3(1, 1, 1)), Transform{}},
       {Shape::box(Vec3(1e-4, 1e-4, 1e-4)), Transform{Vec3(-1.75, -0.5, 0.5), Quat::Identity()}}});
  const Shape b = compound_from_parts(
      {{Shape::box(Vec3(1, 1, 1)), Transform{Vec3::Zero(), quarter_about_y}},
       {Shape::box(Vec3(1e-4, 1e-4, 1e-4)), Transform{Vec3(0, 0, -1.75), Quat::Identity()}}});
  ASSERT_EQ(a.compound->volume(), b.compound->volume());
  for (const Real margin : {0.0, 0.01}) {
    const Transform pose{Vec3(-4, -4, -4), Quat::Identity()};
    Manifold ab;
    Manifold ba;
    ASSERT_GT(collide(a, pose, b, pose, margin, ab), 0);
    ASSERT_EQ(collide(b, pose, a, pose, margin, ba), ab.count);
    EXPECT_EQ(ab.normal, Vec3(-ba.normal));
    for (int k = 0; k < ab.count; ++k) {
      EXPECT_EQ(ab.points[k].position, ba.points[k].position) << k;
      EXPECT_EQ(ab.points[k].depth, ba.points[k].depth) << k;
      EXPECT_EQ(ab.points[k].feature, ba.points[k].feature.swapped()) << k;
    }
  }
}

// Translations on a grid of 2^-20 m: adding the far offset (an integer) is then exact, so the
// pair-local inputs are bit-identical near and far, and a pair function that really runs in the
// pair-local frame must give bit-identical normals and depths and positions equal up to the
// final rounding (ulp(1e6) = 1.2e-10). A pair computed in world coordinates would differ there
// by about 1e-10 in depth.
Vec3 snapped(const Vec3& v) {
  const Real grid = std::ldexp(Real(1), -20);
  return (v / grid).array().round().matrix() * grid;
}

TEST(NarrowPhaseContract, FarFromOriginGivesTheSameAnswerAsAtTheOrigin) {
  Rng rng(202);
  // About 1e6 m from the origin in every coordinate; double's spacing there is 1.2e-10 m.
  const Vec3 far(1.0e6, -2.0e6, 1.5e6);
  Real worst_position = 0;
  Real worst_depth_unsnapped = 0;
  for (const ShapeType ta : kTypes) {
    for (const ShapeType tb : kTypes) {
      if (ta == ShapeType::plane && tb == ShapeType::plane)
        continue;
      SCOPED_TRACE(pair_name(ta, tb));
      int compared = 0;
      for (int i = 0; i < 400; ++i) {
        const Shape a = random_shape(rng, ta);
        const Shape b = random_shape(rng, tb);
        Transform pose_a;
        Transform pose_b;
        random_nearby_poses(rng, a, b, pose_a, pose_b);
        const bool snap = i % 2 == 0;
        if (snap) {
          pose_a.translation = snapped(pose_a.translation);
          pose_b.translation = snapped(pose_b.translation);
        }
        const Real margin = 0.1;
        Manifold near_origin;
        collide(a, pose_a, b, pose_b, margin, near_origin);
        Transform far_a = pose_a;
        Transform far_b = pose_b;
        far_a.translation += far;
        far_b.translation += far;
        Manifold far_away;
        collide(a, far_a, b, far_b, margin, far_away);
        if (snap) {
          ASSERT_EQ(near_origin.count, far_away.count) << "pose " << i;
          if (near_origin.count == 0)
            continue;
          ++compared;
          EXPECT_EQ(near_origin.normal, far_away.normal) << "pose " << i;
          for (int k = 0; k < near_origin.count; ++k) {
            const ContactPoint& p = near_origin.points[k];
            const ContactPoint& q = far_away.points[k];
            EXPECT_EQ(p.depth, q.depth) << "pose " << i;
            EXPECT_EQ(p.feature, q.feature) << "pose " << i;
            const Real position_error = (p.position - (q.position - far)).norm();
            EXPECT_LT(position_error, 1e-9) << "pose " << i;
            worst_position = std::max(worst_position, position_error);
          }
          continue;
        }
        // Off the grid the far inputs themselves are rounded by up to 1.2e-10 m; the deepest
        // depth is 1-Lipschitz in them, so it must agree to ~1e-9 of the shapes' size (~1 m).
        // A point right at the margin may come and go with the last bit: skip those poses.
        bool at_margin = false;
        for (int k = 0; k < near_origin.count; ++k) {
          at_margin |= std::abs(near_origin.points[k].depth + margin) < 1e-6;
        }
        if (at_margin)
          continue;
        ASSERT_EQ(near_origin.count > 0, far_away.count > 0) << "pose " << i;
        if (near_origin.count == 0)
          continue;
        const int deepest_near = deepest_point(near_origin);
        const int deepest_far = deepest_point(far_away);
        const Real depth_error =
            std::abs(near_origin.points[deepest_near].depth - far_away.points[deepest_far].depth);
        EXPECT_LT(depth_error, 1e-9) << "pose " << i;
        worst_depth_unsnapped = std::max(worst_depth_unsnapped, depth_error);
      }
      EXPECT_GT(compared, 50);
    }
  }
  std::printf(
      "[ stats    ] far from origin: on-grid position difference %.2e (normals, depths exact); "
      "off-grid depth difference %.2e\n",
      worst_position, worst_depth_unsnapped);
}

// ---- Degenerate inputs ----------------------------------------------------------------------

void expect_sane(const Manifold& m, int count) {
  ASSERT_EQ(m.count, count);
  ASSERT_TRUE(m.normal.allFinite());
  EXPECT_NEAR(m.normal.norm(), 1, 1e-12);
  for (int i = 0; i < m.count; ++i) {
    EXPECT_TRUE(m.points[i].position.allFinite());
    EXPECT_TRUE(std::isfinite(m.points[i].depth));
  }
}

Real max_depth(const Manifold& m) {
  Real d = -std::numeric_limits<Real>::infinity();
  for (int i = 0; i < m.count; ++i)
    d = std::max(d, m.points[i].depth);
  return d;
}

TEST(NarrowPhaseDegenerate, CoincidentSpheresPushTheSmallerAlongWorldZ) {
  const Transform pose{Vec3(3, -1, 2), Quat::Identity()};
  Manifold small_first;
  collide(Shape::sphere(0.25), pose, Shape::sphere(0.5), pose, 0, small_first);
  expect_sane(small_first, 1);
  EXPECT_EQ(small_first.normal, Vec3::UnitZ());
  EXPECT_DOUBLE_EQ(small_first.points[0].depth, 0.75);
  Manifold big_first;
  collide(Shape::sphere(0.5), pose, Shape::sphere(0.25), pose, 0, big_first);
  expect_sane(big_first, 1);
  EXPECT_EQ(big_first.normal, Vec3(-Vec3::UnitZ()));
}

// Equal spheres at one centre are one solid whatever their orientations: the same contact in both
// orders, whose normal cannot flip (nothing tells A from B). Found by fuzz_narrow_phase, whose
// twin test had asked orientations to be equal too.
TEST(NarrowPhaseDegenerate, EqualSpheresAtOneCentreAreTwinsWhateverTheirOrientation) {
  const Transform upright{Vec3(-4, -4, -4), Quat::Identity()};
  const Transform turned{upright.translation, Quat(0.5, 0.5, -0.5, 0.5)};
  Manifold ab;
  Manifold ba;
  collide(Shape::sphere(1e-4), upright, Shape::sphere(1e-4), turned, 0, ab);
  collide(Shape::sphere(1e-4), turned, Shape::sphere(1e-4), upright, 0, ba);
  expect_sane(ab, 1);
  expect_sane(ba, 1);
  EXPECT_EQ(ab.normal, ba.normal);
  EXPECT_EQ(ab.points[0].position, ba.points[0].position);
  EXPECT_EQ(ab.points[0].depth, Real(2e-4));
}

// Twins by content, not by object: two compounds built alike are twins at one pose, and not at
// another or with a part moved; spheres are twins at one centre whatever their orientation.
TEST(NarrowPhaseDegenerate, TwinsAreTheSameSolidInTheSamePlace) {
  const auto ball = [](const Vec3& where) {
    return compound_from_parts({{Shape::sphere(1e-4), Transform{where, Quat::Identity()}},
                                {Shape::box(Vec3(0.1, 0.2, 0.3)), Transform{}}});
  };
  const Transform here{Vec3(-4, -4, -4), Quat::Identity()};
  const Transform turned{here.translation, Quat(0.5, 0.5, -0.5, 0.5)};
  const Transform there{Vec3(-4, -4, -3), Quat::Identity()};
  EXPECT_TRUE(twins(ball(Vec3::Zero()), here, ball(Vec3::Zero()), here));
  EXPECT_FALSE(twins(ball(Vec3::Zero()), here, ball(Vec3::Zero()), turned));
  EXPECT_FALSE(twins(ball(Vec3::Zero()), here, ball(Vec3::Zero()), there));
  EXPECT_FALSE(twins(ball(Vec3::Zero()), here, ball(Vec3(0, 0, 1e-3)), here));
  EXPECT_TRUE(twins(Shape::sphere(0.5), here, Shape::sphere(0.5), turned));
  EXPECT_FALSE(twins(Shape::sphere(0.5), here, Shape::sphere(0.25), here));
  EXPECT_TRUE(twins(Shape::box(Vec3(1, 2, 3)), turned, Shape::box(Vec3(1, 2, 3)), turned));
  EXPECT_FALSE(twins(Shape::box(Vec3(1, 2, 3)), here, Shape::box(Vec3(1, 2, 3)), turned));
  EXPECT_FALSE(twins(Shape::box(Vec3(1, 2, 3)), here, Shape::box(Vec3(1, 3, 2)), here));
  // Twins give one answer either way: the same normal, the same points.
  Manifold ab;
  Manifold ba;
  ASSERT_EQ(collide(ball(Vec3::Zero()), here, ball(Vec3::Zero()), here, 0, ab), 4);
  ASSERT_EQ(collide(ball(Vec3::Zero()), here, ball(Vec3::Zero()), here, 0, ba), 4);
  EXPECT_EQ(ab.normal, ba.normal);
}

TEST(NarrowPhaseDegenerate, SphereCentreOnCapsuleCore) {
  const Shape capsule = Shape::capsule(0.3, 0.8);
  const Transform capsule_pose{Vec3(1, 2, 3),
                               Quat(Eigen::AngleAxis<Real>(0.7, Vec3(1, 1, 0).normalized()))};
  for (const Real along : {-0.8, -0.3, 0.0, 0.8}) {
    Manifold m;
    const Transform sphere_pose{capsule_pose.apply(Vec3(0, 0, along)), Quat::Identity()};
    collide(Shape::sphere(0.2), sphere_pose, capsule, capsule_pose, 0, m);
    expect_sane(m, 1);
    EXPECT_NEAR(m.points[0].depth, 0.5, 1e-12);
    // Any direction across the axis is a minimum translation; it must be across the axis.
    EXPECT_NEAR(m.normal.dot(capsule_pose.rotate(Vec3::UnitZ())), 0, 1e-12);
  }
}

TEST(NarrowPhaseDegenerate, SphereCentreAtBoxCentreEdgeAndVertex) {
  const Shape box = Shape::box({0.5, 0.3, 0.7});
  const Transform box_pose{Vec3(-1, 0.5, 2), Quat(Eigen::AngleAxis<Real>(0.4, Vec3::UnitY()))};
  const Shape sphere = Shape::sphere(0.25);
  struct Case {
    Vec3 local;
    Real depth;
  };
  // Centre inside: leave through the nearest face (y, 0.3 away). On an edge or a vertex the
  // centre is on the surface: depth equals the radius.
  for (const Case& c : {Case{Vec3::Zero(), 0.55}, Case{Vec3(0.5, 0.3, 0), 0.25},
                        Case{Vec3(-0.5, 0.3, 0.7), 0.25}, Case{Vec3(0.5, 0, 0), 0.25}}) {
    Manifold m;
    collide(sphere, {box_pose.apply(c.local), Quat::Identity()}, box, box_pose, 0, m);
    expect_sane(m, 1);
    EXPECT_NEAR(m.points[0].depth, c.depth, 1e-12);
    // The normal is one of the box's face normals.
    const Vec3 local_normal = box_pose.rotate_inverse(m.normal);
    EXPECT_NEAR(local_normal.cwiseAbs().maxCoeff(), 1, 1e-12);
  }
}

TEST(NarrowPhaseDegenerate, ZeroLengthCapsuleActsLikeASphere) {
  Rng rng(203);
  const Shape point_capsule = Shape::capsule(0.4, 0);
  const Shape sphere = Shape::sphere(0.4);
  for (const ShapeType other_type : kTypes) {
    SCOPED_TRACE(std::string(shape_type_name(other_type)));
    int compared = 0;
    for (int i = 0; i < 300; ++i) {
      const Shape other = random_shape(rng, other_type);
      Transform pose_capsule;
      Transform pose_other;
      random_nearby_poses(rng, point_capsule, other, pose_capsule, pose_other);
      Manifold as_capsule;
      Manifold as_sphere;
      const int n = collide(point_capsule, pose_capsule, other, pose_other, 0.1, as_capsule);
      collide(sphere, pose_capsule, other, pose_other, 0.1, as_sphere);
      ASSERT_EQ(n, as_sphere.count);
      if (n == 0)
        continue;
      ++compared;
      expect_sane(as_capsule, n);
      EXPECT_NEAR(max_depth(as_capsule), max_depth(as_sphere), 1e-9);
      if (other_type != ShapeType::capsule) {
        // A capsule-capsule pair may pick another, equally deep, direction when the cores meet.
        EXPECT_LT((as_capsule.normal - as_sphere.normal).norm(), 1e-9);
      }
    }
    EXPECT_GT(compared, 50);
  }
}

TEST(NarrowPhaseDegenerate, ParallelCollinearAndCrossingCapsules) {
  const Shape a = Shape::capsule(0.2, 1.0);
  const Shape b = Shape::capsule(0.3, 0.5);
  const Quat along_x(Eigen::AngleAxis<Real>(std::numbers::pi / 2, Vec3::UnitY()));
  {
    // Side by side, exactly parallel, B's core fully over A's: two points at B's ends.
    Manifold m;
    collide(a, {Vec3::Zero(), along_x}, b, {Vec3(0.2, 0, -0.45), along_x}, 0, m);
    expect_sane(m, 2);
    EXPECT_LT((m.normal - Vec3::UnitZ()).norm(), 1e-12);
    for (int i = 0; i < 2; ++i)
      EXPECT_NEAR(m.points[i].depth, 0.05, 1e-12);
    EXPECT_NEAR(std::abs(m.points[0].position.x() - m.points[1].position.x()), 1.0, 1e-12);
  }
  {
    // Same axis line (collinear, overlapping): any direction across the axis, depth rA + rB.
    Manifold m;
    collide(a, {Vec3::Zero(), along_x}, b, {Vec3(0.7, 0, 0), along_x}, 0, m);
    ASSERT_GE(m.count, 1);
    expect_sane(m, m.count);
    EXPECT_NEAR(m.normal.x(), 0, 1e-12);
    EXPECT_NEAR(max_depth(m), 0.5, 1e-12);
  }
  {
    // Cores crossing at their centres: the common perpendicular, depth rA + rB.
    Manifold m;
    collide(a, {Vec3::Zero(), along_x}, b, {Vec3::Zero(), Quat::Identity()}, 0, m);
    expect_sane(m, 1);
    EXPECT_NEAR(std::abs(m.normal.y()), 1, 1e-12);
    EXPECT_NEAR(m.points[0].depth, 0.5, 1e-12);
  }
  {
    // Coincident zero-length capsules.
    Manifold m;
    collide(Shape::capsule(0.2, 0), {}, Shape::capsule(0.1, 0), {}, 0, m);
    expect_sane(m, 1);
    EXPECT_NEAR(m.points[0].depth, 0.3, 1e-12);
  }
}

TEST(NarrowPhaseDegenerate, CapsuleCoreOnBoxFaceEdgeAndInside) {
  const Shape box = Shape::box({1, 0.5, 0.25});
  const Shape capsule = Shape::capsule(0.1, 0.3);
  const Quat along_x(Eigen::AngleAxis<Real>(std::numbers::pi / 2, Vec3::UnitY()));
  struct Case {
    Vec3 centre;
    Real depth;
  };
  // Core lying in the top face, along the top +y edge, and at the box centre (nearest face:
  // z, 0.25 away).
  for (const Case& c :
       {Case{Vec3(0, 0, 0.25), 0.1}, Case{Vec3(0, 0.5, 0.25), 0.1}, Case{Vec3::Zero(), 0.35}}) {
    Manifold m;
    collide(capsule, {c.centre, along_x}, box, {}, 0, m);
    ASSERT_GE(m.count, 1);
    expect_sane(m, m.count);
    EXPECT_NEAR(max_depth(m), c.depth, 1e-12);
  }
}

TEST(NarrowPhaseDegenerate, CoincidentBoxesAndZeroSizedShapesStayFinite) {
  {
    Manifold m;
    collide(Shape::box({0.5, 0.5, 0.5}), {}, Shape::box({0.5, 0.5, 0.5}), {}, 0, m);
    ASSERT_GE(m.count, 1);
    expect_sane(m, m.count);
    EXPECT_NEAR(max_depth(m), 1.0, 1e-12);  // translate by a full width along an axis
    EXPECT_NEAR(m.normal.cwiseAbs().maxCoeff(), 1, 1e-12);
  }
  // Zero radii, zero extents, every pair, random poses: never NaN.
  Rng rng(204);
  const std::array<Shape, 6> degenerate = {Shape::sphere(0),        Shape::capsule(0, 0.5),
                                           Shape::capsule(0, 0),    Shape::box({0, 0.5, 0.5}),
                                           Shape::box({0, 0, 0.5}), Shape::box({0, 0, 0})};
  const std::array<Shape, 4> regular = {Shape::sphere(0.5), Shape::box({0.4, 0.3, 0.2}),
                                        Shape::capsule(0.2, 0.4), Shape::plane()};
  int contacts = 0;
  for (const Shape& a : degenerate) {
    for (const Shape& b : regular) {
      for (int i = 0; i < 200; ++i) {
        Transform pose_a;
        Transform pose_b;
        random_nearby_poses(rng, a, b, pose_a, pose_b);
        if (i % 4 == 0)
          pose_b.translation = pose_a.translation;  // centred on each other
        for (const bool swap : {false, true}) {
          Manifold m;
          const int n =
              swap ? collide(b, pose_b, a, pose_a, 0.1, m) : collide(a, pose_a, b, pose_b, 0.1, m);
          if (n > 0) {
            ++contacts;
            expect_sane(m, n);
          }
        }
      }
    }
  }
  EXPECT_GT(contacts, 1000);
}

// ---- Feature ids under small motions ---------------------------------------------------------

std::set<std::uint32_t> feature_keys(const Manifold& m) {
  std::set<std::uint32_t> keys;
  for (int i = 0; i < m.count; ++i)
    keys.insert(m.points[i].feature.key());
  return keys;
}

TEST(NarrowPhaseContract, FeatureIdsAreStableUnderSmallMotions) {
  struct Setup {
    const char* name;
    Shape a;
    Transform pose_a;
    Shape b;
    Transform pose_b;
    int expected_points;
  };
  const Quat along_x(Eigen::AngleAxis<Real>(std::numbers::pi / 2, Vec3::UnitY()));
  const Quat turned(Eigen::AngleAxis<Real>(0.3, Vec3::UnitZ()));
  const std::array<Setup, 6> setups = {
      Setup{"box on plane",
            Shape::box({0.5, 0.4, 0.3}),
            {Vec3(0, 0, 0.29), turned},
            Shape::plane(),
            {},
            4},
      Setup{"box on box",
            Shape::box({0.5, 0.4, 0.3}),
            {Vec3(0.1, 0, 0.79), turned},
            Shape::box({2, 2, 0.5}),
            {},
            4},
      Setup{"box on offset box",
            Shape::box({0.5, 0.5, 0.5}),
            {Vec3(0.6, 0.3, 0.99), Quat::Identity()},
            Shape::box({0.5, 0.5, 0.5}),
            {},
            4},
      Setup{"capsule on box",
            Shape::capsule(0.2, 0.5),
            {Vec3(0, 0, 0.69), along_x},
            Shape::box({1, 1, 0.5}),
            {},
            2},
      Setup{"capsule on capsule",
            Shape::capsule(0.2, 0.5),
            {Vec3(0.1, 0, 0.39), along_x},
            Shape::capsule(0.2, 0.8),
            {Vec3::Zero(), along_x},
            2},
      Setup{"capsule on plane",
            Shape::capsule(0.2, 0.5),
            {Vec3(0, 0, 0.19), along_x},
            Shape::plane(),
            {},
            2},
  };
  Rng rng(205);
  for (const Setup& s : setups) {
    SCOPED_TRACE(s.name);
    Manifold reference;
    collide(s.a, s.pose_a, s.b, s.pose_b, 0.02, reference);
    ASSERT_EQ(reference.count, s.expected_points);
    const std::set<std::uint32_t> reference_keys = feature_keys(reference);
    ASSERT_EQ(int(reference_keys.size()), s.expected_points) << "feature ids must be distinct";
    for (int i = 0; i < 200; ++i) {
      // Jitter of the size a resting body sees between steps.
      Transform moved = s.pose_a;
      moved.translation += random_vector_in_box(rng, 1e-4);
      moved.rotation = moved.rotation * Quat(Eigen::AngleAxis<Real>(1e-4, random_unit_vector(rng)));
      Manifold m;
      collide(s.a, moved, s.b, s.pose_b, 0.02, m);
      EXPECT_EQ(feature_keys(m), reference_keys) << "jitter " << i;
    }
  }
}

// The margin near touching, for the pairs that reach GJK with a curved shape: a cylinder a hair
// (1e-9 to 1e-4 of its size) above a box's top face, a hull's (the same box as 8 points) or,
// crossed, another cylinder's side. Asked with a margin of twice the gap, the narrow phase finds
// the contact at the gap; with half of it, none. (Before GJK recovered from stalls, gjk.cpp, its
// distance near a face could be long by up to 5.5e-8 of the size, and contacts were dropped.)
TEST(NarrowPhaseContract, CylinderNearlyTouchingIsFoundWithinTwiceItsGap) {
  Rng rng(3107);
  const int poses = scaled(6000);
  const auto box_hull = [](const Vec3& half) {
    std::vector<Vec3> corners;
    for (int c = 0; c < 8; ++c)
      corners.emplace_back(c & 1 ? half.x() : -half.x(), c & 2 ? half.y() : -half.y(),
                           c & 4 ? half.z() : -half.z());
    return Shape::convex_hull(std::make_shared<const ConvexHull>(ConvexHull::from_points(corners)));
  };
  std::array<Real, 3> worst{};  // box, hull, crossed cylinder
  for (int i = 0; i < poses; ++i) {
    const Real size = std::pow(10, uniform(rng, -1, 0.5));
    const Shape cylinder =
        Shape::cylinder(size * uniform(rng, 0.2, 1), size * uniform(rng, 0.2, 1));
    const Real gap = size * std::pow(10, uniform(rng, -9, -4));
    const Transform base{random_unit_vector(rng) * uniform(rng, 0, 3), random_rotation(rng)};
    const Vec3 up = base.rotate(Vec3::UnitZ());
    const int other = i % 3;  // box, hull, crossed cylinder
    Shape below;
    Transform below_pose;
    Transform pose;
    if (other < 2) {
      const Vec3 half = Vec3(4, 4, 1) * size;
      below = other == 0 ? Shape::box(half) : box_hull(half);
      below_pose = {base.apply(Vec3(0, 0, -half.z())), base.rotation};
      // Tilted at random, or lying on its side (one in three).
      const Quat turn =
          i % 9 < 3
              ? base.rotation * Quat(Eigen::AngleAxis<Real>(std::numbers::pi / 2, Vec3::UnitX()))
              : random_rotation(rng);
      const Vec3 lowest = support(cylinder, turn.conjugate() * -up);
      const Vec3 inside = base.apply(Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), 0) * size);
      pose = {inside + up * gap - turn * lowest, turn};
    } else {
      // Crossed: both axes perpendicular to `up`, at an angle; the sides touch along `up`.
      below = Shape::cylinder(size * uniform(rng, 0.2, 1), size * uniform(rng, 0.5, 1));
      const Quat lying =
          base.rotation * Quat(Eigen::AngleAxis<Real>(std::numbers::pi / 2, Vec3::UnitX()));
      below_pose = {base.translation, lying};
      const Quat crossed = Quat(Eigen::AngleAxis<Real>(uniform(rng, 0.3, 1.5), up)) * lying;
      pose = {base.translation + up * (below.radius + cylinder.radius + gap), crossed};
    }
    Manifold m;
    const int found = collide(cylinder, pose, below, below_pose, 2 * gap, m);
    ASSERT_GT(found, 0) << "pose " << i << " other " << other << " gap " << gap;
    Real deepest = -std::numeric_limits<Real>::infinity();
    for (int k = 0; k < m.count; ++k)
      deepest = std::max(deepest, m.points[std::size_t(k)].depth);
    EXPECT_NEAR(deepest, -gap, 1e-10 * size) << "pose " << i << " other " << other;
    worst[std::size_t(other)] = std::max(worst[std::size_t(other)], std::abs(deepest + gap) / size);
    EXPECT_EQ(collide(cylinder, pose, below, below_pose, gap / 2, m), 0)
        << "pose " << i << " other " << other << " gap " << gap;
  }
  std::printf(
      "[ stats    ] cylinder a hair above a face or a crossed cylinder, %d poses: worst "
      "depth error / size %.2e box, %.2e hull, %.2e crossed cylinder\n",
      poses, worst[0], worst[1], worst[2]);
}

}  // namespace
}  // namespace tumble::testing
