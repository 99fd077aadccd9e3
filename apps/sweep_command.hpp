// `tumble sweep SPEC.yaml -o DIR`: the runs of a parameter study (scenes/sweep_file.hpp), in one
// process or spread over MPI ranks (apps/work_pool.hpp; docs/scale-out.md). Every run writes
// DIR/runs/NNNN/ (summary.json last, so a run is complete exactly when its summary is there);
// rank 0 then writes DIR/sweep.csv (one row per run in run order: the varied values, energy
// drift, final state hash, error against the reference run) and DIR/timings.csv (wall times,
// kept apart so that sweep.csv depends on the inputs alone). Run again, the same command skips
// every complete run and does the rest.
#pragma once

#include <filesystem>

namespace tumble::app {

struct SweepOptions {
  std::filesystem::path spec;
  std::filesystem::path output_dir;
  int threads = 1;  // each run's world.threads (every run records it in its summary)
  bool quiet = false;
};

int sweep_command(const SweepOptions& options);

}  // namespace tumble::app
