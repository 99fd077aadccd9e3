// `tumble bench-batch [SCENE]`: the reinforcement-learning metrics of a batch of worlds
// (docs/rl.md, "The batch benchmark"): throughput (env-steps/s, narrow-phase pairs/s), latency
// (p50 and p99 of one batch step), scaling over world and thread counts, memory per world and the
// bandwidth that implies, and the per-stage split of a batch step; with MuJoCo 2.2.2 and Bullet
// 3.24 stepping the same worlds in the same process, run by run in turn. Not a test: timings vary
// with the machine.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tumble::app {

struct BenchBatchOptions {
  std::filesystem::path scene = "scenes/rl/boxes20.yaml";
  std::vector<int> worlds = {1, 16, 256, 1024, 4096};
  std::vector<int> threads = {1, 2};
  int steps = 60;  // batch steps per run, from the scene's initial state
  int repetitions = 3;
  std::vector<std::string> peers = {"mujoco", "bullet"};
  // Peers are not run above this many worlds (Bullet's worlds are large; see docs/rl.md).
  int peer_max_worlds = 1024;
  std::filesystem::path output;  // a CSV file, written atomically; empty: none
};

int bench_batch_command(const BenchBatchOptions& options);

}  // namespace tumble::app
