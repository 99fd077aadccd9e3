// `tumble bench [SCENE...]`: times each scene in tumble and in Bullet in the same process,
// alternating the engines run by run, tumble at each thread count asked for (1 and 2 by
// default; Bullet on one), twice: with sleeping off in both (Bullet gets
// DISABLE_DEACTIVATION), then on in both (tumble's world.sleeping, Bullet's default
// deactivation). Prints min, median and max step time of each engine, their ratio, tumble's
// stage and solve-phase breakdown, ns per contact point per solver pass, ns per narrow-phase
// pair, and bytes per body and per contact point; writes CSV files. Not a test: timings vary
// with the machine.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace tumble::app {

struct BenchOptions {
  std::vector<std::filesystem::path> scenes;  // default scenes/bench/*.yaml
  std::filesystem::path output_dir = "out/bench";
  int repetitions = 3;
  std::optional<std::int64_t> steps;
  // tumble runs at each of these thread counts; the first is the one the others' speed-ups are
  // measured against.
  std::vector<int> threads = {1, 2};
};

int bench_command(const BenchOptions& options);

}  // namespace tumble::app
