// The separating-axis cache of box pairs (collision/narrow_phase/box_axis_cache.hpp), against
// independent truth, on thousands of random box pairs (fixed seed; TUMBLE_PROPERTY_SCALE scales the
// count):
//   - box_axis_separation equals the gap between the two boxes' corner projections on the axis,
//     built in the world frame from the poses (min over A's corners minus max over B's, the
//     larger of the two orientations), never the cache's own algebra;
//   - whenever an axis separates a pair by more than the margin, collide() finds no contact (the
//     cache may skip the query without changing an answer);
//   - best_separating_box_axis names an axis exactly when collide() finds no contact and some
//     axis separates by clearly more than the margin, and it names the most separated one.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "collision/narrow_phase/box_axis_cache.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"
#include "tests/collision/oracle.hpp"
#include "tests/property_scale.hpp"

namespace tumble::testing {
namespace {

std::array<Vec3, 8> corners(const Vec3& half, const Transform& pose) {
  std::array<Vec3, 8> out;
  for (int v = 0; v < 8; ++v) {
    const Vec3 local((v & 1) ? half.x() : -half.x(), (v & 2) ? half.y() : -half.y(),
                     (v & 4) ? half.z() : -half.z());
    out[std::size_t(v)] = pose.apply(local);
  }
  return out;
}

// The axis's direction in the world frame, or zero for a degenerate edge axis.
Vec3 world_axis(const Transform& pose_a, const Transform& pose_b, int axis) {
  const Mat3 ra = pose_a.rotation.toRotationMatrix();
  const Mat3 rb = pose_b.rotation.toRotationMatrix();
  if (axis < 3)
    return ra.col(axis);
  if (axis < 6)
    return rb.col(axis - 3);
  const Vec3 l = ra.col((axis - 6) / 3).cross(rb.col((axis - 6) % 3));
  return l.norm() > 1e-6 ? Vec3(l.normalized()) : Vec3::Zero();
}

Real projected_gap(const std::array<Vec3, 8>& a, const std::array<Vec3, 8>& b, const Vec3& l) {
  Real a_min = std::numeric_limits<Real>::infinity(), a_max = -a_min;
  Real b_min = a_min, b_max = -a_min;
  for (const Vec3& p : a) {
    a_min = std::min(a_min, p.dot(l));
    a_max = std::max(a_max, p.dot(l));
  }
  for (const Vec3& p : b) {
    b_min = std::min(b_min, p.dot(l));
    b_max = std::max(b_max, p.dot(l));
  }
  return std::max(a_min - b_max, b_min - a_max);
}

struct RandomPair {
  Vec3 half_a, half_b;
  Transform pose_a, pose_b;
  Real margin;
};

RandomPair random_pair(Rng& rng) {
  RandomPair p;
  p.half_a = Vec3(uniform(rng, 0.05, 1), uniform(rng, 0.05, 1), uniform(rng, 0.05, 1));
  p.half_b = Vec3(uniform(rng, 0.05, 1), uniform(rng, 0.05, 1), uniform(rng, 0.05, 1));
  p.pose_a.translation = random_vector_in_box(rng, 100);
  p.pose_a.rotation = random_rotation(rng);
  // Near each other: touching, apart within reach of the margin, or clearly apart; a share of
  // them aligned (face-to-face stacks, where edge axes degenerate).
  const Real reach = p.half_a.norm() + p.half_b.norm();
  p.pose_b.translation =
      p.pose_a.translation + random_unit_vector(rng) * uniform(rng, 0.2, 1.3) * reach;
  p.pose_b.rotation = uniform(rng, 0, 1) < 0.3 ? p.pose_a.rotation : random_rotation(rng);
  p.margin = uniform(rng, 0, 1) < 0.5 ? Real(0) : uniform(rng, 0, 0.1);
  return p;
}

Real reach_of(const RandomPair& p) {
  return p.half_a.norm() + p.half_b.norm() + p.pose_a.translation.norm();
}

TEST(BoxAxisCache, SeparationIsTheGapBetweenCornerProjections) {
  Rng rng(20261126);
  const int cases = scaled(4000);
  int checked = 0;
  for (int c = 0; c < cases; ++c) {
    const RandomPair p = random_pair(rng);
    const auto ca = corners(p.half_a, p.pose_a);
    const auto cb = corners(p.half_b, p.pose_b);
    for (int axis = 0; axis < 15; ++axis) {
      const Real s =
          box_axis_separation(p.half_a, p.pose_a, p.half_b, p.pose_b, std::uint8_t(axis));
      const Vec3 l = world_axis(p.pose_a, p.pose_b, axis);
      if (l.isZero()) {
        EXPECT_EQ(s, -std::numeric_limits<Real>::infinity());
        continue;
      }
      ++checked;
      ASSERT_NEAR(s, projected_gap(ca, cb, l), 1e-9 * (1 + reach_of(p)))
          << "case " << c << " axis " << axis;
    }
  }
  EXPECT_GT(checked, cases * 10);
}

TEST(BoxAxisCache, AnAxisThatSeparatesBeyondTheMarginMeansNoContact) {
  Rng rng(7);
  const int cases = scaled(20000);
  int separated = 0, best_named = 0;
  for (int c = 0; c < cases; ++c) {
    const RandomPair p = random_pair(rng);
    Manifold m;
    const int count =
        collide(Shape::box(p.half_a), p.pose_a, Shape::box(p.half_b), p.pose_b, p.margin, m);
    Real most = -std::numeric_limits<Real>::infinity();
    for (int axis = 0; axis < 15; ++axis) {
      const auto a = std::uint8_t(axis);
      most = std::max(most, box_axis_separation(p.half_a, p.pose_a, p.half_b, p.pose_b, a));
      if (box_axis_separates(p.half_a, p.pose_a, p.half_b, p.pose_b, a, p.margin)) {
        ++separated;
        ASSERT_EQ(count, 0) << "case " << c << " axis " << axis;
      }
    }
    const std::uint8_t best =
        best_separating_box_axis(p.half_a, p.pose_a, p.half_b, p.pose_b, p.margin);
    if (best != kNoBoxAxis) {
      ++best_named;
      EXPECT_EQ(count, 0) << "case " << c;
      EXPECT_EQ(box_axis_separation(p.half_a, p.pose_a, p.half_b, p.pose_b, best), most);
    } else {
      // No axis clears the margin (beyond the rounding band): the full test must run.
      EXPECT_LE(most, p.margin + 1e-6) << "case " << c;
    }
  }
  // Both outcomes occur often.
  EXPECT_GT(best_named, cases / 10);
  EXPECT_LT(best_named, cases - cases / 10);
  EXPECT_GT(separated, cases / 10);
}

}  // namespace
}  // namespace tumble::testing
