// The step's stage timers, read from a cheap clock. A small world's step times its stages and
// phases about sixty times (six timers a substep); steady_clock costs about 19 ns a read on the
// development machine, the x86 time-stamp counter 8.5 ns, which is 1.5-2% of a 20-box world's
// step. The counter's rate is not known in seconds, so each step measures it against
// steady_clock from its first read to its last and converts the ticks with that ratio: no
// calibration, and the stages add up to the step's own time (Intel SDM vol. 3, 18.17, "Time-Stamp
// Counter": constant and invariant on current processors).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>

#include "engine/step_statistics.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace tumble {

inline std::uint64_t read_ticks() {
#if defined(__x86_64__) || defined(__i386__)
  return __rdtsc();
#else
  return static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
#endif
}

// Ticks counted per stage and phase over one step, turned into seconds at its end.
struct StepTicks {
  std::array<std::uint64_t, kStageCount> stage{};
  std::array<std::uint64_t, kSolvePhaseCount> phase{};
  std::uint64_t recycle = 0;
  std::uint64_t recompute = 0;

  void begin() {
    stage.fill(0);
    phase.fill(0);
    recycle = 0;
    recompute = 0;
    // The counter, then the clock, at both ends: the two intervals then differ by rounding only.
    start_ticks_ = read_ticks();
    start_time_ = std::chrono::steady_clock::now();
  }

  // Writes the step's times into `stats` (adding to what is there).
  void finish_into(StepStatistics& stats) const {
    const std::uint64_t end_ticks = read_ticks();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time_).count();
    // A counter that went back (not kept in step across cores, as on some virtual machines)
    // gives no times rather than wrapped ones.
    const double seconds_per_tick =
        end_ticks > start_ticks_ ? seconds / static_cast<double>(end_ticks - start_ticks_) : 0.0;
    for (int s = 0; s < kStageCount; ++s)
      stats.seconds[std::size_t(s)] +=
          static_cast<double>(stage[std::size_t(s)]) * seconds_per_tick;
    for (int p = 0; p < kSolvePhaseCount; ++p)
      stats.solve_phase_seconds[std::size_t(p)] +=
          static_cast<double>(phase[std::size_t(p)]) * seconds_per_tick;
    stats.recycle_seconds += static_cast<double>(recycle) * seconds_per_tick;
    stats.recompute_seconds += static_cast<double>(recompute) * seconds_per_tick;
  }

 private:
  std::chrono::steady_clock::time_point start_time_{};
  std::uint64_t start_ticks_ = 0;
};

}  // namespace tumble
