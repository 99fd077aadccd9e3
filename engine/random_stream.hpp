// A small seeded random stream for domain randomization (engine/randomization.cpp): SplitMix64
// (Steele, Lea and Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014), which
// passes BigCrush, needs one 64-bit word of state and, unlike the standard library's
// distributions, gives the same numbers with every compiler and library.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>

#include "tumble/math.hpp"

namespace tumble {

class RandomStream {
 public:
  // Streams for different (seed, kind, index) are independent: the three words are mixed through
  // the generator's finaliser before the first draw.
  RandomStream(std::uint64_t seed, std::uint64_t kind, std::uint64_t index)
      : state_(mix(mix(mix(seed) ^ kind) ^ index)) {}

  std::uint64_t next() {
    state_ += kGamma;
    return mix(state_);
  }

  // Uniform in [0, 1), 53 bits.
  Real uniform() { return static_cast<Real>(next() >> 11) * 0x1.0p-53; }
  Real uniform(Real low, Real high) { return low + (high - low) * uniform(); }

  // Standard normal by the Box-Muller transform (one of the pair is used: simpler, and the draws
  // are few).
  Real normal() {
    const Real u = 1 - uniform();  // (0, 1]: the logarithm stays finite
    const Real v = uniform();
    return std::sqrt(-2 * std::log(u)) * std::cos(2 * std::numbers::pi_v<Real> * v);
  }

  // The SplitMix64 finaliser (a variant of MurmurHash3's).
  static std::uint64_t mix(std::uint64_t z) {
    z += kGamma;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

 private:
  static constexpr std::uint64_t kGamma = 0x9e3779b97f4a7c15ULL;
  std::uint64_t state_;
};

}  // namespace tumble
