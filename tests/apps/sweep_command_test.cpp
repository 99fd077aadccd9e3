// `tumble sweep` in one process: one row per run in run order, each run the same world as
// `tumble run` with those settings, errors against the reference, restarts that redo only what
// is missing, and bad sweeps refused before any run.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/apps/command_runner.hpp"

namespace tumble::test {
namespace {

namespace fs = std::filesystem;

std::string file_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::vector<std::string>> csv_rows(const fs::path& path) {
  std::istringstream in(file_text(path));
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::stringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');)
      row.push_back(field);
    if (line.back() == ',')
      row.emplace_back();
    rows.push_back(row);
  }
  return rows;
}

// Two boxes falling onto one, with a randomize block so that seeds change the world.
constexpr const char* kScene = R"(world: {dt: 0.01, duration: 0.4}
randomize: {friction: [0.3, 0.9], position_noise: 0.01}
bodies:
  - {name: floor, shape: {type: plane}, static: true}
  - {name: base, shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [0, 0, 0.5], mass: 1}
  - {name: top, shape: {type: box, half_extents: [0.3, 0.3, 0.3]}, position: [0.1, 0, 1.6], mass: 1}
)";

struct SweepDir {
  fs::path root;
  explicit SweepDir(const std::string& name) : root(fs::temp_directory_path() / name) {
    fs::remove_all(root);
    fs::create_directories(root);
    std::ofstream(root / "scene.yaml") << kScene;
  }
  ~SweepDir() { fs::remove_all(root); }
  fs::path write_spec(const std::string& yaml) const {
    std::ofstream(root / "sweep.yaml") << yaml;
    return root / "sweep.yaml";
  }
};

constexpr const char* kSpec = R"(scene: scene.yaml
vary:
  world.dt: [0.01, 0.0025]
  world.substeps: [2, 4]
reference: {world.dt: 0.0025}
)";

std::size_t column(const std::vector<std::string>& header, const std::string& name) {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name)
      return i;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

TEST(SweepCommand, OneRowPerRunEachTheWorldTumbleRunMakes) {
  const SweepDir d("tumble_sweep_rows");
  const fs::path spec = d.write_spec(kSpec);
  const CommandOutput out =
      run_tumble_command("sweep " + spec.string() + " -o " + (d.root / "out").string());
  ASSERT_EQ(out.exit_code, 0) << out.text;
  const auto rows = csv_rows(d.root / "out" / "sweep.csv");
  ASSERT_EQ(rows.size(), 5u);  // header and 2 x 2 runs
  const auto& h = rows[0];
  const std::vector<std::pair<std::string, std::string>> settings{
      {"0.01", "2"}, {"0.01", "4"}, {"0.0025", "2"}, {"0.0025", "4"}};  // the last axis fastest
  for (std::size_t r = 0; r < settings.size(); ++r) {
    const auto& row = rows[r + 1];
    ASSERT_EQ(row.size(), h.size()) << r;
    EXPECT_EQ(row[column(h, "world.dt")], settings[r].first);
    EXPECT_EQ(row[column(h, "world.substeps")], settings[r].second);
    EXPECT_EQ(row[column(h, "status")], "ok");
    // The same world as `tumble run` given those settings on the command line or in the file.
    const fs::path run_dir = d.root / ("run" + std::to_string(r));
    std::ofstream(d.root / "edited.yaml") << std::string(kScene).replace(
        std::string(kScene).find("dt: 0.01"), 8,
        "dt: " + settings[r].first + ", substeps: " + settings[r].second);
    ASSERT_EQ(run_tumble_command("run " + (d.root / "edited.yaml").string() +
                                 " --threads 1 -q -o " + run_dir.string())
                  .exit_code,
              0);
    const auto summary = nlohmann::json::parse(file_text(run_dir / "summary.json"));
    EXPECT_EQ(row[column(h, "final_state_hash")], summary["final_state_hash"].get<std::string>());
    EXPECT_EQ(std::stod(row[column(h, "energy_drift")]),
              summary["energy"]["final"]["total"].get<double>() -
                  summary["energy"]["initial"]["total"].get<double>());
  }
  // The reference of a run with dt 0.0025 differs from it only where the run's own settings
  // differ: the run at the reference's dt and substeps is the reference (error exactly 0).
  const std::size_t error = column(h, "error_m");
  EXPECT_GT(std::stod(rows[1][error]), 0.0);
  EXPECT_EQ(std::stod(rows[3][error]), 0.0);
  EXPECT_EQ(rows[1][column(h, "reference")], rows[3][column(h, "reference")]);
  EXPECT_NE(rows[3][column(h, "reference")], rows[4][column(h, "reference")]);  // 2 vs 4 substeps
  const auto timings = csv_rows(d.root / "out" / "timings.csv");
  EXPECT_EQ(timings.size(), 1u + 4u + 2u);  // the runs and the two references
}

TEST(SweepCommand, ARestartRedoesOnlyWhatIsMissingAndEndsTheSame) {
  const SweepDir d("tumble_sweep_restart");
  const fs::path spec = d.write_spec(std::string(kSpec) + "seeds: 2\n");
  const std::string out_dir = (d.root / "out").string();
  ASSERT_EQ(run_tumble_command("sweep " + spec.string() + " -o " + out_dir).exit_code, 0);
  const std::string table = file_text(d.root / "out" / "sweep.csv");
  const std::string kept_summary = file_text(d.root / "out/runs/0003/summary.json");
  // A run killed before its summary, one whose directory is gone, and a stale temporary file.
  fs::remove(d.root / "out/runs/0001/summary.json");
  fs::remove_all(d.root / "out/runs/0006");
  std::ofstream(d.root / "out/runs/0001/checkpoints.csv.tmp.99999") << "half";
  const CommandOutput again = run_tumble_command("sweep " + spec.string() + " -o " + out_dir);
  ASSERT_EQ(again.exit_code, 0) << again.text;
  EXPECT_NE(again.text.find("8 runs and 4 references; 10 already complete, 2 to run"),
            std::string::npos)
      << again.text;
  EXPECT_EQ(file_text(d.root / "out" / "sweep.csv"), table);
  EXPECT_EQ(file_text(d.root / "out/runs/0003/summary.json"), kept_summary);
  EXPECT_FALSE(fs::exists(d.root / "out/runs/0001/checkpoints.csv.tmp.99999"));
  // Seeds draw different worlds, the same seed the same one.
  const auto rows = csv_rows(d.root / "out" / "sweep.csv");
  const std::size_t hash = column(rows[0], "final_state_hash");
  EXPECT_EQ(rows[1][column(rows[0], "seed")], "0");
  EXPECT_EQ(rows[2][column(rows[0], "seed")], "1");
  EXPECT_NE(rows[1][hash], rows[2][hash]);
  // An edited scene runs again: the summaries record the scene file's digest.
  std::ofstream(d.root / "scene.yaml") << kScene << "# edited\n";
  const CommandOutput edited = run_tumble_command("sweep " + spec.string() + " -o " + out_dir);
  ASSERT_EQ(edited.exit_code, 0) << edited.text;
  EXPECT_NE(edited.text.find("0 already complete, 12 to run"), std::string::npos) << edited.text;
  // A changed sweep in the same directory runs again: the summaries record their inputs.
  d.write_spec(std::string(kSpec) + "seeds: 2\nduration: 0.2\n");
  const CommandOutput changed = run_tumble_command("sweep " + spec.string() + " -o " + out_dir);
  ASSERT_EQ(changed.exit_code, 0) << changed.text;
  EXPECT_NE(changed.text.find("0 already complete, 12 to run"), std::string::npos) << changed.text;
}

// The shipped example (README.md, docs/scale-out.md) runs: one row per combination, each with an
// error against its reference.
TEST(SweepCommand, TheShippedStudyRuns) {
  const fs::path out = fs::temp_directory_path() / "tumble_sweep_shipped";
  fs::remove_all(out);
  const CommandOutput r =
      run_tumble_command(std::string("sweep ") + TUMBLE_SOURCE_DIR +
                         "/scenes/sweeps/stack10_study.yaml -q -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const auto rows = csv_rows(out / "sweep.csv");
  ASSERT_EQ(rows.size(), 1u + 2 * 2 * 3);
  const std::size_t error = column(rows[0], "error_m");
  for (std::size_t i = 1; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i][column(rows[0], "status")], "ok");
    EXPECT_GT(std::stod(rows[i][error]), 0.0);  // none of them is its reference
  }
  fs::remove_all(out);
}

TEST(SweepCommand, TrajectoriesWhenAsked) {
  const SweepDir d("tumble_sweep_trajectory");
  const fs::path spec = d.write_spec(
      "scene: scene.yaml\nduration: 0.2\ntrajectory: true\nvary:\n  world.dt: [0.01, 0.02]\n");
  const CommandOutput r =
      run_tumble_command("sweep " + spec.string() + " -q -o " + (d.root / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.text;
  // The initial state and every step, for the two moving boxes.
  EXPECT_EQ(csv_rows(d.root / "out/runs/0000/trajectory.csv").size(), 1u + 21 * 2);
  EXPECT_EQ(csv_rows(d.root / "out/runs/0001/trajectory.csv").size(), 1u + 11 * 2);
}

TEST(SweepCommand, BadSweepsAreRefusedBeforeAnyRun) {
  const SweepDir d("tumble_sweep_errors");
  const auto refused = [&](const std::string& yaml, const std::string& expected) {
    const fs::path spec = d.write_spec(yaml);
    const fs::path out = d.root / "out";
    fs::remove_all(out);
    const CommandOutput r = run_tumble_command("sweep " + spec.string() + " -o " + out.string());
    EXPECT_EQ(r.exit_code, 1) << yaml;
    EXPECT_NE(r.text.find(expected), std::string::npos) << yaml << "\n-> " << r.text;
    EXPECT_FALSE(fs::exists(out / "runs")) << yaml;
  };
  refused("scene: scene.yaml\nvary:\n  world.dtt: [0.01]\n",
          "sweep.yaml:3:15: field 'vary.world.dtt'");
  refused("scene: scene.yaml\nvary:\n  world.dtt: [0.01]\n", "unknown field 'dtt'");
  refused("scene: scene.yaml\nvary:\n  world.dt: [0.01, 0]\n", "sweep.yaml:3:20");
  refused("scene: scene.yaml\nvary:\n  world.dt: {from: 0.01, to: 0.02, count: 0}\n",
          "an empty range");
  refused("scene: missing.yaml\nvary:\n  world.dt: [0.01]\n", "missing.yaml: cannot open");
  refused("scene: scene.yaml\nvary:\n  world.dt: [0.01]\nreference: {world.substeps: 0}\n",
          "sweep.yaml:4:12: field 'references/0000'");
  // An output directory that cannot be made.
  const fs::path spec = d.write_spec("scene: scene.yaml\nvary:\n  world.dt: [0.01]\n");
  std::ofstream(d.root / "file") << "x";
  const CommandOutput r =
      run_tumble_command("sweep " + spec.string() + " -o " + (d.root / "file" / "out").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.text.find("cannot create the output directory"), std::string::npos) << r.text;
}

}  // namespace
}  // namespace tumble::test
