// The oracle commands from the command line: compare prints a JSON summary with the required
// keys, report writes its table and its tumble time-step family converges at first order
// against the analytic parabola, bench writes its CSV.
#include <gtest/gtest.h>

#include <algorithm>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace {

struct Result {
  int exit_code = -1;
  std::string output;
};

Result run_cli(const std::string& arguments) {
  const std::string command = std::string(TUMBLE_CLI) + " " + arguments + " 2>/dev/null";
  Result r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr)
    return r;
  std::array<char, 4096> buffer;
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    r.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("tumble_oracle_" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

const std::string kScenes = std::string(TUMBLE_SOURCE_DIR) + "/scenes/";

TEST(OracleCli, ComparePrintsJsonSummary) {
  const auto dir = fresh_dir("compare");
  const Result r = run_cli("compare " + kScenes + "free_flight.yaml -q -o " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j.at("mode"), "paths");
  EXPECT_LE(j.at("max_position_error").get<double>(), 1e-9);
  EXPECT_LE(j.at("max_orientation_error").get<double>(), 1e-12);
  EXPECT_FALSE(j.at("mismatches").empty());
  EXPECT_TRUE(std::filesystem::exists(dir / "errors.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir / "timeline.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir / "summary.json"));
}

TEST(OracleCli, CompareRejectsAMissingScene) {
  const Result r = run_cli("compare /nonexistent/scene.yaml");
  EXPECT_EQ(r.exit_code, 1);
}

TEST(OracleCli, ReportConvergesAtFirstOrderOnTheParabola) {
  const auto dir = fresh_dir("report");
  const Result r = run_cli("report " + kScenes + "free_flight.yaml --no-plot -o " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream csv(dir / "report.csv");
  std::string line;
  std::getline(csv, line);
  std::map<std::string, std::map<double, double>> tumble_dt;  // solver -> dt -> error
  int bullet_rows = 0;
  while (std::getline(csv, line)) {
    std::stringstream s(line);
    std::string engine, solver, family, dt, substeps, iterations, wall, error;
    std::getline(s, engine, ',');
    std::getline(s, solver, ',');
    std::getline(s, family, ',');
    std::getline(s, dt, ',');
    std::getline(s, substeps, ',');
    std::getline(s, iterations, ',');
    std::getline(s, wall, ',');
    std::getline(s, error, ',');
    if (engine == "bullet")
      ++bullet_rows;
    if (engine == "tumble" && family == "dt")
      tumble_dt[solver][std::stod(dt)] = std::stod(error);
  }
  EXPECT_GT(bullet_rows, 0);
  // Both solvers are swept.
  ASSERT_EQ(tumble_dt.size(), 2u);
  const auto& impulse = tumble_dt["impulse"];
  ASSERT_EQ(impulse.size(), 5u);
  // Semi-implicit Euler's error on a parabola is exactly proportional to the step.
  for (auto it = std::next(impulse.begin()); it != impulse.end(); ++it) {
    const double ratio = it->second / std::prev(it)->second;
    EXPECT_NEAR(ratio, it->first / std::prev(it)->first, 0.05);
  }
  // The penalty solver takes substeps no longer than its stiffest spring allows (Simulation sets
  // h omega < 2 for the lightest body), so its error stays at that substep's until the swept
  // one is finer: never larger for a finer step.
  const auto& penalty = tumble_dt["penalty"];
  ASSERT_EQ(penalty.size(), 5u);
  for (auto it = std::next(penalty.begin()); it != penalty.end(); ++it)
    EXPECT_GE(it->second, std::prev(it)->second * (1 - 1e-9));
  EXPECT_LT(penalty.begin()->second, std::prev(penalty.end())->second);
  EXPECT_TRUE(std::filesystem::exists(dir / "report.md"));
}

TEST(OracleCli, BenchWritesCsv) {
  const auto dir = fresh_dir("bench");
  const Result r =
      run_cli("bench " + kScenes + "free_flight.yaml --repetitions 2 --steps 5 -o " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ratio tumble / Bullet"), std::string::npos);
  EXPECT_NE(r.output.find("free_flight (sleeping on)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("ns per point per pass"), std::string::npos) << r.output;
  std::ifstream csv(dir / "oracle_bench.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_NE(header.find("tumble_solve_soft_passes_ms"), std::string::npos) << header;
  EXPECT_NE(header.find(",threads,"), std::string::npos) << header;
  EXPECT_NE(header.find("tumble_ns_per_recomputed_pair"), std::string::npos) << header;
  EXPECT_NE(r.output.find("ns per recycled or resting pair"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("% resting"), std::string::npos) << r.output;
  const auto fields = [](const std::string& row) {
    return std::count(row.begin(), row.end(), ',') + 1;
  };
  EXPECT_NE(r.output.find("tumble, 2 threads"), std::string::npos) << r.output;
  // Sleeping off, then on, each with tumble's rows at 1 and 2 threads and a Bullet row.
  for (const char* start : {"free_flight,off,1,5,2,tumble,1,", "free_flight,off,1,5,2,tumble,2,",
                            "free_flight,off,1,5,2,bullet,1,", "free_flight,on,1,5,2,tumble,1,",
                            "free_flight,on,1,5,2,tumble,2,", "free_flight,on,1,5,2,bullet,1,"}) {
    std::getline(csv, line);
    EXPECT_EQ(line.rfind(start, 0), 0u) << line;
    EXPECT_EQ(fields(line), fields(header)) << line;
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "free_flight_steps.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir / "free_flight_sleeping_steps.csv"));
}

}  // namespace
