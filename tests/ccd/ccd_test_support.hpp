// Shared helpers of the CCD tests: the random-case scale and random poses.
#pragma once

#include <cstdlib>
#include <random>

#include "collision/math.hpp"

namespace tumble::testing {

// TUMBLE_PROPERTY_SCALE (default 1) scales the number of random cases (the sanitizer run sets
// 0.25), as in tests/broad_phase/broad_phase_property.hpp.
inline int scaled(int cases) {
  const char* text = std::getenv("TUMBLE_PROPERTY_SCALE");
  double scale = 1.0;
  if (text != nullptr) {
    const double s = std::strtod(text, nullptr);
    if (s > 0 && s <= 1)
      scale = s;
  }
  return std::max(1, static_cast<int>(cases * scale));
}

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
