// `tumble run`: load a scene, step it, write the trajectory (CSV and/or .npy), the contacts CSV if
// asked, and the JSON summary.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

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
  // Trajectory files: "csv" (trajectory.csv), "npy" (trajectory.npy) or "both".
  std::string format = "csv";
  bool contacts = false;  // also contacts.csv
  // Static bodies in the trajectory too (they never move; left out by default).
  bool static_bodies = false;
};

// Returns the process exit code: 0 done, 1 user error (message on stderr), 3 a step left the
// state non-finite (message naming the step and body), 130 interrupted.
inline constexpr int kExitNonFinite = 3;
int run_command(const RunOptions& options);

}  // namespace tumble::app
