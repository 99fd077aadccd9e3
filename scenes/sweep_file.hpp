// The input of `tumble sweep` (docs/scale-out.md): a base scene and the fields to vary,
//   scene: stack10.yaml              # relative to the sweep file's folder
//   duration: 2.0                    # s, each run (default: the scene's)
//   vary: {world.dt: [0.01, 0.005], materials.default.friction: {from: 0.2, to: 0.8, count: 4}}
//   seeds: 2                         # or a list of seeds; runs per combination
//   reference: {world.dt: 0.001}     # optional: each run's error is measured against it
//   trajectory: false                # write every run's trajectory.csv
// Errors are SceneError with the sweep file's name, line, column and field.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scenes/scene_loader.hpp"

namespace tumble {

// Where a value was written, for messages: "sweep.yaml:7:22".
struct SweepPlace {
  std::string file;
  int line = 0;
  int column = 0;
  std::string text() const;
};

struct SweepAxis {
  std::string field;                // dotted scene path, as FieldOverride::field
  std::vector<std::string> values;  // YAML of each value, in order
  std::vector<SweepPlace> places;   // where each value was written (a range: the range)
  SweepPlace place;                 // of the axis' key
};

struct SweepSpec {
  std::filesystem::path source;  // the sweep file
  std::filesystem::path scene;   // resolved against the sweep file's folder
  std::optional<double> duration;
  std::vector<SweepAxis> axes;  // in file order; the last varies fastest
  // Seeds per combination. Empty: the scene is run as written (no draw).
  std::vector<std::uint64_t> seeds;
  std::vector<FieldOverride> reference;  // empty: no reference runs
  SweepPlace reference_place;
  bool trajectory = false;
};

SweepSpec load_sweep_file(const std::filesystem::path& path);
SweepSpec load_sweep_string(std::string_view yaml, std::string_view source_name);

// The YAML of a value as the scene loader reads it back: numbers in the shortest form that
// reads back to the same double.
std::string sweep_number_text(double value);

}  // namespace tumble
