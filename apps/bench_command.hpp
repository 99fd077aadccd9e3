// `tumble bench [SCENE...]`: times each scene in tumble and in Bullet in the same process,
// alternating the engines run by run, with sleeping off in both (tumble has none; Bullet gets
// DISABLE_DEACTIVATION). Prints min, median and max step time of each engine, their ratio and
// tumble's stage breakdown; writes CSV files. Not a test: timings vary with the machine.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace tumble::app {

struct BenchOptions {
  std::vector<std::filesystem::path> scenes;  // default scenes/bench/*.yaml
  std::filesystem::path output_dir = "docs/benchmarks";
  int repetitions = 3;
  std::optional<std::int64_t> steps;
};

int bench_command(const BenchOptions& options);

}  // namespace tumble::app
