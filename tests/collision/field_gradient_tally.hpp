// distance_between's gradients against central differences of the distance, shared by the
// tests of fields (tests/collision/sdf_distance_test.cpp; the committed neural field in
// tests/scenes/neural_sdf_file_test.cpp): random pose pairs of a shape and a field, each of the
// 12 gradient entries compared, the disagreements sorted into kinks (the two one-sided
// differences disagree), entries near a ridge, and the unexplained rest.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "collision/sdf/sdf_tree.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "tumble/distance.hpp"
#include "tumble/shape.hpp"

namespace tumble {

inline Transform field_pose_moved(const Transform& pose, int k, Real h) {
  Transform out = pose;
  if (k < 3)
    out.translation[k] += h;
  else
    out.rotation = (Eigen::AngleAxis<Real>(h, Vec3::Unit(k - 3)) * pose.rotation).normalized();
  return out;
}

inline Quat field_random_turn(std::mt19937_64& rng) {
  std::normal_distribution<Real> n(0, 1);
  Quat q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q;
}

struct FieldCase {
  const char* name;
  SdfNode field;
  Shape round;
};

struct GradientTally {
  int penetrating = 0;
  int kinks = 0;       // the two one-sided slopes differ: a kink inside the step
  int near_ridge = 0;  // a disagreement with the distance below `ridge`
  int unexplained = 0;
};

// distance_between's gradients against central differences of step h on `count` random pose
// pairs of the case, each of the 12 entries (both poses, translation then rotation).
inline GradientTally tally_gradients(const FieldCase& c, std::mt19937_64& rng, int count, Real h,
                                     Real ridge = -std::numeric_limits<Real>::infinity()) {
  std::uniform_real_distribution<Real> u(-1, 1);
  const Shape field = sdf_shape(c.field);
  GradientTally tally;
  for (int i = 0; i < count; ++i) {
    const Transform pose_b{Vec3(u(rng), u(rng), u(rng)) * 0.5, field_random_turn(rng)};
    const Transform pose_a{pose_b.translation + Vec3(u(rng), u(rng), u(rng)) * 0.9,
                           field_random_turn(rng)};
    const ShapeDistance d = distance_between(c.round, pose_a, field, pose_b);
    tally.penetrating += d.distance < 0 ? 1 : 0;
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < 6; ++k) {
        const auto at = [&](Real step) {
          return side == 0 ? distance_between(c.round, field_pose_moved(pose_a, k, step), field,
                                              pose_b, false)
                                 .distance
                           : distance_between(c.round, pose_a, field,
                                              field_pose_moved(pose_b, k, step), false)
                                 .distance;
        };
        const Real plus = at(h), minus = at(-h);
        const Real central = (plus - minus) / (2 * h);
        const Real analytic = side == 0 ? d.gradient_a[k] : d.gradient_b[k];
        if (std::abs(central - analytic) < 1e-5)
          continue;
        const Real forward = (plus - d.distance) / h, backward = (d.distance - minus) / h;
        if (std::abs(forward - backward) > 1e-4)
          ++tally.kinks;
        else if (d.distance < ridge)
          ++tally.near_ridge;
        else
          ++tally.unexplained;
      }
  }
  return tally;
}

// A ball or capsule against a field (gradients exact wherever phi is differentiable): `count`
// configurations with differences of step 1e-6; no unexplained disagreement, kinks in fewer than
// one configuration in fifty, and enough penetrating ones to have tested the inside.
inline void expect_round_gradients_match(const FieldCase& c, std::mt19937_64& rng, int count) {
  const auto [penetrating, kinks, near_ridge, unexplained] = tally_gradients(c, rng, count, 1e-6);
  std::printf("%s: %d configurations, %d penetrating, %d kinks\n", c.name, count, penetrating,
              kinks);
  EXPECT_EQ(unexplained, 0) << c.name;
  EXPECT_LT(kinks, count / 50) << c.name;
  EXPECT_GT(penetrating, count / 20) << c.name;
}

}  // namespace tumble
