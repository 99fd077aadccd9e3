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
      if (std::memcmp(&a[i], &b[i], sizeof(BodyState)) != 0) {
        ADD_FAILURE() << "body " << i << " differs at step " << step;
        return use;
      }
    }
  }
  return use;
}

}  // namespace tumble::test
