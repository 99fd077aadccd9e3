// `tumble sim2real SCENE`: the scene's randomized worlds in training geometry (bodies collide
// with their train_shape) against deployment geometry (their detailed shape), with the same
// draws: the step time of each, how far the trajectories part (position error against time, mean
// and 95th percentile, plotted), and whether the size noise the training worlds draw spans that
// gap (docs/rl.md, "Training geometry").
#pragma once

#include <cstdint>
#include <filesystem>

namespace tumble::app {

struct Sim2RealOptions {
  std::filesystem::path scene;
  int worlds = 64;
  std::int64_t steps = 0;  // 0: the scene's duration
  int threads = 0;         // 0: the machine's cores
  std::uint64_t seed = 0;
  std::filesystem::path output;  // a directory for sim2real.csv, .md and .png; empty: none
};

int sim2real_command(const Sim2RealOptions& options);

}  // namespace tumble::app
