// `tumble sim2real`: runs both geometries over randomized worlds and writes its table, CSV and
// plot; the gap is zero at the start and grows once shapes touch; a scene without training
// shapes is refused with a message that says why.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/apps/command_runner.hpp"

namespace tumble::test {
namespace {

namespace fs = std::filesystem;

TEST(Sim2Real, ReportsStepTimesGapAndCoverage) {
  const fs::path dir =
      fs::temp_directory_path() / ("tumble_sim2real_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const fs::path scene = fs::path(TUMBLE_SOURCE_DIR) / "scenes/rl/sim2real_mugs.yaml";
  const CommandOutput run =
      run_tumble_command("sim2real " + scene.string() +
                         " --worlds 6 --steps 40 --threads 2 --seed 4 -o " + dir.string());
  ASSERT_EQ(run.exit_code, 0) << run.text;
  EXPECT_NE(run.text.find("| deploy |"), std::string::npos) << run.text;
  EXPECT_NE(run.text.find("| train |"), std::string::npos) << run.text;
  EXPECT_NE(run.text.find("4 bodies with a train_shape"), std::string::npos) << run.text;
  std::ifstream csv(dir / "sim2real.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "time,gap_mean,gap_p95,spread_mean,spread_p95");
  std::vector<std::vector<double>> rows;
  while (std::getline(csv, line)) {
    std::stringstream fields(line);
    std::vector<double> row;
    for (std::string f; std::getline(fields, f, ',');)
      row.push_back(std::stod(f));
    rows.push_back(row);
  }
  ASSERT_EQ(rows.size(), 41u);
  EXPECT_EQ(rows.front()[1], 0);    // the same start in both geometries
  EXPECT_GT(rows.back()[1], 1e-3);  // and apart once the fitted shapes roll differently
  for (const auto& r : rows) {
    EXPECT_GE(r[1], 0);
    EXPECT_GE(r[3], 0);
  }
  EXPECT_TRUE(fs::exists(dir / "sim2real.md"));
  if (fs::exists(dir / "sim2real.png")) {
    std::ifstream png(dir / "sim2real.png", std::ios::binary);
    char magic[4] = {};
    png.read(magic, 4);
    EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  }
  fs::remove_all(dir);
}

TEST(Sim2Real, RefusesASceneWithoutTrainingShapes) {
  const fs::path scene = fs::path(TUMBLE_SOURCE_DIR) / "scenes/stack10.yaml";
  const CommandOutput run = run_tumble_command("sim2real " + scene.string() + " --worlds 2");
  EXPECT_EQ(run.exit_code, 1) << run.text;
  EXPECT_NE(run.text.find("no body has a train_shape"), std::string::npos) << run.text;
}

}  // namespace
}  // namespace tumble::test
