// Rigid motion over a step against closed forms: both kinds reach both end poses; the linear
// kind moves the centre on a line; the screw kind of a body turning about a fixed axis line
// while sliding along it matches the helix written by hand, and its intermediate poses form a
// one-parameter group (T(s) T0^-1 composed twice is T(2s) T0^-1).
#include <gtest/gtest.h>

#include <cmath>

#include "collision/ccd/rigid_motion.hpp"
#include "tests/ccd/ccd_test_support.hpp"

namespace tumble::testing {
namespace {

Real pose_error(const Transform& a, const Transform& b) {
  return std::max((a.translation - b.translation).norm(), a.rotation.angularDistance(b.rotation));
}

TEST(RigidMotion, BothKindsReachBothEnds) {
  std::mt19937_64 rng(11);
  for (int i = 0; i < scaled(2000); ++i) {
    Transform t0{random_vector(rng, -10, 10), random_rotation(rng)};
    Transform t1{random_vector(rng, -10, 10), random_rotation(rng)};
    for (MotionKind kind : {MotionKind::linear, MotionKind::screw}) {
      const RigidMotion m(t0, t1, kind);
      EXPECT_LT(pose_error(m.at(0), t0), 1e-12);
      EXPECT_LT(pose_error(m.at(1), t1), 1e-11) << "kind " << int(kind) << " case " << i;
    }
  }
}

TEST(RigidMotion, LinearMovesTheCentreOnALineAndTurnsAtAConstantRate) {
  std::mt19937_64 rng(12);
  for (int i = 0; i < scaled(1000); ++i) {
    Transform t0{random_vector(rng, -10, 10), random_rotation(rng)};
    Transform t1{random_vector(rng, -10, 10), random_rotation(rng)};
    const RigidMotion m(t0, t1);
    const Real s = std::uniform_real_distribution<Real>(0, 1)(rng);
    const Transform p = m.at(s);
    EXPECT_LT((p.translation - ((1 - s) * t0.translation + s * t1.translation)).norm(), 1e-12);
    // Constant rate: the angle turned so far is s times the whole angle.
    const Real total = t0.rotation.angularDistance(t1.rotation);
    EXPECT_NEAR(t0.rotation.angularDistance(p.rotation), s * total, 1e-9);
  }
}

TEST(RigidMotion, ScrewMatchesAHelixAboutAFixedAxisLine) {
  std::mt19937_64 rng(13);
  for (int i = 0; i < scaled(1000); ++i) {
    const Vec3 axis = random_unit(rng);
    const Vec3 point_on_axis = random_vector(rng, -5, 5);
    const Real angle = std::uniform_real_distribution<Real>(-3.0, 3.0)(rng);
    const Real slide = std::uniform_real_distribution<Real>(-2.0, 2.0)(rng);
    const Transform t0{random_vector(rng, -5, 5), random_rotation(rng)};
    // The screw about the line (point_on_axis, axis) by `angle` and `slide`, closed form.
    auto helix = [&](Real s) {
      const Quat r(Eigen::AngleAxis<Real>(s * angle, axis));
      Transform out;
      out.rotation = r * t0.rotation;
      out.translation = r * (t0.translation - point_on_axis) + point_on_axis + s * slide * axis;
      return out;
    };
    const RigidMotion m(t0, helix(1), MotionKind::screw);
    for (Real s : {0.1, 0.25, 0.5, 0.8, 0.97}) {
      EXPECT_LT(pose_error(m.at(s), helix(s)), 1e-10) << "case " << i << " s " << s;
    }
    // Every point moves at a constant speed: the centre's speed is the helix's.
    const Real radius =
        (t0.translation - point_on_axis - axis.dot(t0.translation - point_on_axis) * axis).norm();
    EXPECT_NEAR(m.centre_speed(), std::hypot(angle * radius, slide), 1e-9);
  }
}

TEST(RigidMotion, ScrewIsAOneParameterGroup) {
  std::mt19937_64 rng(14);
  for (int i = 0; i < scaled(1000); ++i) {
    const Transform t0{random_vector(rng, -5, 5), random_rotation(rng)};
    const Transform t1{random_vector(rng, -5, 5), random_rotation(rng)};
    const RigidMotion m(t0, t1, MotionKind::screw);
    // D(s) = T(s) T0^-1 satisfies D(s) D(s) = D(2s).
    auto relative = [&](Real s) {
      const Transform p = m.at(s);
      Transform d;
      d.rotation = p.rotation * t0.rotation.conjugate();
      d.translation = p.translation - d.rotation * t0.translation;
      return d;
    };
    const Transform half = relative(0.3);
    Transform twice;
    twice.rotation = half.rotation * half.rotation;
    twice.translation = half.rotation * half.translation + half.translation;
    EXPECT_LT(pose_error(twice, relative(0.6)), 1e-10) << "case " << i;
  }
}

TEST(RigidMotion, SmallAnglesStayExact) {
  const Transform t0{Vec3(1, 2, 3), Quat::Identity()};
  for (Real angle : {1e-14, 1e-9, 1e-6, 1e-4}) {
    Transform t1{Vec3(1.5, 2, 3), Quat(Eigen::AngleAxis<Real>(angle, Vec3::UnitZ()))};
    const RigidMotion m(t0, t1, MotionKind::screw);
    EXPECT_LT(pose_error(m.at(1), t1), 1e-13);
    EXPECT_TRUE(m.at(0.5).translation.allFinite());
  }
}

}  // namespace
}  // namespace tumble::testing
