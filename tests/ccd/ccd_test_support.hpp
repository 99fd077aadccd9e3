// Shared helpers of the CCD tests: the random-case scale and random poses.
#pragma once

#include <cstdlib>
#include <random>

#include "collision/math.hpp"
#include "tests/property_scale.hpp"

namespace tumble::testing {

inline Vec3 random_vector(std::mt19937_64& rng, Real lo, Real hi) {
  std::uniform_real_distribution<Real> u(lo, hi);
  return Vec3(u(rng), u(rng), u(rng));
}

inline Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<Real> n(0, 1);
  Vec3 v(n(rng), n(rng), n(rng));
  while (v.norm() < 1e-6)
    v = Vec3(n(rng), n(rng), n(rng));
  return v.normalized();
}

inline Quat random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<Real> n(0, 1);
  Quat q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized();
}

}  // namespace tumble::testing
