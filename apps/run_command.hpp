// `tumble run`: load a scene, step it, write the trajectory CSV and the JSON summary.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>

namespace tumble::app {

struct RunOptions {
  std::optional<int> threads;  // overrides the scene's world.threads
  std::filesystem::path scene;
  std::filesystem::path output_dir;  // empty: out/<scene stem>
  std::optional<std::int64_t> steps;
  std::optional<double> duration;  // s
  std::optional<double> dt;        // s
  std::int64_t record_every = 1;   // write every k-th step (and the first and last)
  bool quiet = false;
};

// Returns the process exit code: 0 done, 1 user error (message on stderr), 130 interrupted.
int run_command(const RunOptions& options);

}  // namespace tumble::app
