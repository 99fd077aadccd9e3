// Steps a scene twice, once as it is and once with a narrow-phase cache dropped from the state
// before every step (`drop` clears it), and checks that every body agrees bit for bit after every
// step: the caches that only skip queries whose answer they already prove must change nothing.
// Returns the cached run's axis-cache tries and hits.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <memory>

#include "engine/simulation.hpp"

namespace tumble::test {

struct AxisCacheUse {
  std::int64_t tries = 0;
  std::int64_t hits = 0;
};

// Field by field: BodyState has padding before its quaternion (Eigen aligns it), and the bytes of
// padding are whatever the copy left there.
inline bool same_bits(const BodyState& a, const BodyState& b) {
  const auto same = [](const Real* x, const Real* y, std::size_t n) {
    return std::memcmp(x, y, n * sizeof(Real)) == 0;
  };
  return same(a.position.data(), b.position.data(), 3) &&
         same(a.orientation.coeffs().data(), b.orientation.coeffs().data(), 4) &&
         same(a.velocity.data(), b.velocity.data(), 3) &&
         same(a.angular_velocity.data(), b.angular_velocity.data(), 3);
}

template <class Drop>
AxisCacheUse expect_same_bits_without_cache(const std::shared_ptr<const Scene>& scene, int steps,
                                            const Drop& drop) {
  Simulation cached(scene);
  Simulation uncached(scene);
  AxisCacheUse use;
  for (int step = 0; step < steps; ++step) {
    State s = uncached.state();
    drop(s);
    uncached.set_state(s);
    cached.step();
    uncached.step();
    use.tries += cached.last_step_statistics().axis_cache_tries;
    use.hits += cached.last_step_statistics().axis_cache_hits;
    EXPECT_EQ(uncached.last_step_statistics().axis_cache_tries, 0);
    const auto& a = cached.state().bodies;
    const auto& b = uncached.state().bodies;
    EXPECT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
      if (!same_bits(a[i], b[i])) {
        ADD_FAILURE() << "body " << i << " differs at step " << step;
        return use;
      }
    }
  }
  return use;
}

}  // namespace tumble::test
