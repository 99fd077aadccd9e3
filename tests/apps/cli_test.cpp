// The `tumble` command line, run as a user runs it: exit codes, messages, outputs.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "apps/trajectory_writer.hpp"
#include "collision/sdf/vdb_level_set.hpp"
#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"

extern char** environ;

namespace tumble::test {
namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// A shell command, its output and exit code.
Result run_shell(const std::string& command) {
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

Result run_cli(const std::string& arguments) {
  // Built with append: GCC 12 warns falsely (-Warray-bounds) about std::string + "..." inlined.
  std::string command(TUMBLE_CLI);
  command.append(" ").append(arguments).append(" 2>&1");
  return run_shell(command);
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path scratch_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("tumble_cli_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

const std::string kScenes = std::string(TUMBLE_SOURCE_DIR) + "/scenes/";

// OpenVDB's code is a module loaded when a scene first has a level set
// (collision/sdf/openvdb_module.hpp): the command line does not link OpenVDB, a scene with a
// level set still loads, and without the module that scene's field gets the reason.
TEST(Cli, OpenVdbIsLoadedOnlyForScenesWithLevelSets) {
  const Result linked = run_shell(std::string("ldd ") + TUMBLE_CLI + " 2>&1");
  ASSERT_EQ(linked.exit_code, 0) << linked.output;
  EXPECT_NE(linked.output.find("libstdc++"), std::string::npos) << linked.output;
  EXPECT_EQ(linked.output.find("libopenvdb"), std::string::npos) << linked.output;
  if (!VdbLevelSet::available())
    GTEST_SKIP() << "this build has no OpenVDB";
  const std::string scene = kScenes + "sdf/things_in_level_set_bowls.yaml";
  const Result loaded = run_cli("validate " + scene);
  EXPECT_EQ(loaded.exit_code, 0) << loaded.output;
  const fs::path missing = scratch_dir("no_openvdb_module") / "libtumble_openvdb.so";
  const Result refused = run_shell("TUMBLE_OPENVDB_MODULE='" + missing.string() + "' " +
                                   TUMBLE_CLI + " validate " + scene + " 2>&1");
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("things_in_level_set_bowls.yaml:"), std::string::npos)
      << refused.output;
  EXPECT_NE(refused.output.find("OpenVDB module"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find(missing.string()), std::string::npos) << refused.output;
}

TEST(Cli, HelpForEveryVerb) {
  for (const std::string verb : {"", "run ", "validate "}) {
    const Result r = run_cli(verb + "--help");
    EXPECT_EQ(r.exit_code, 0) << verb;
    EXPECT_NE(r.output.find("Usage"), std::string::npos) << r.output;
  }
  EXPECT_NE(run_cli("run --help").output.find("--dt"), std::string::npos);
}

// Every option that takes a value and is not required states its default in --help, and no
// option shows an internal encoding (an enum's numbers, a negated flag's {false}).
TEST(Cli, HelpShowsEveryDefaultAndNoEncoding) {
  for (const std::string verb : {"run", "validate", "ccd", "compare", "report", "bench",
                                 "bench-batch", "sim2real", "sweep", "render", "query"}) {
    const Result r = run_cli(verb + " --help");
    ASSERT_EQ(r.exit_code, 0) << verb;
    const std::size_t options = r.output.find("Options:");
    ASSERT_NE(options, std::string::npos) << r.output;
    // An option's block: its line (two spaces, then '-') and the indented lines that follow.
    std::vector<std::string> blocks;
    std::istringstream lines(r.output.substr(options));
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("  -", 0) == 0)
        blocks.push_back(line);
      else if (!blocks.empty() && line.rfind("      ", 0) == 0)
        blocks.back() += " " + line;
    }
    for (const std::string& block : blocks) {
      EXPECT_EQ(block.find("->"), std::string::npos) << verb << ": " << block;
      EXPECT_EQ(block.find("{false}"), std::string::npos) << verb << ": " << block;
      const std::string head = block.substr(0, block.find("  ", 2));
      const bool takes_value =
          head.find(" TEXT") != std::string::npos || head.find(" INT") != std::string::npos ||
          head.find(" UINT") != std::string::npos || head.find(" FLOAT") != std::string::npos;
      if (!takes_value || block.find("REQUIRED") != std::string::npos ||
          block.find("--help") != std::string::npos)
        continue;
      EXPECT_NE(block.find("default"), std::string::npos) << verb << ": " << block;
    }
  }
}

TEST(Cli, RunWritesTrajectoryAndSummary) {
  const fs::path dir = scratch_dir("run");
  const Result r =
      run_cli("run " + kScenes + "free_flight.yaml -o " + dir.string() + " --steps 30");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string csv = read_file(dir / "trajectory.csv");
  std::istringstream lines(csv);
  std::string header;
  std::getline(lines, header);
  EXPECT_EQ(header, app::kTrajectoryHeader);
  int rows = 0;
  std::string line, last;
  while (std::getline(lines, line)) {
    ++rows;
    last = line;
  }
  EXPECT_EQ(rows, 31);  // the initial state and 30 steps, one body

  // Numbers round-trip exactly: the last row equals an in-process run bit for bit.
  const auto scene = std::make_shared<const Scene>(load_scene_file(kScenes + "free_flight.yaml"));
  Simulation world(scene);
  for (int k = 0; k < 30; ++k)
    world.step();
  std::istringstream fields(last);
  std::string field;
  std::vector<std::string> values;
  while (std::getline(fields, field, ','))
    values.push_back(field);
  ASSERT_EQ(values.size(), 15u);
  EXPECT_EQ(values[1], "ball");
  const BodyState& b = world.state().bodies[0];
  EXPECT_EQ(std::strtod(values[0].c_str(), nullptr), world.state().time);
  EXPECT_EQ(std::strtod(values[2].c_str(), nullptr), b.position.x());
  EXPECT_EQ(std::strtod(values[4].c_str(), nullptr), b.position.z());
  EXPECT_EQ(std::strtod(values[11].c_str(), nullptr), b.velocity.z());
  // The discrete parabola the scene's comment states, over its substeps.
  const Real n = 30, dt = scene->world.dt, substeps = scene->world.substeps;
  const BodyDesc& ball = scene->bodies[0];
  const Vec3 expected = ball.position + n * dt * ball.velocity +
                        dt * dt * scene->world.gravity * n * (n + 1 / substeps) / 2;
  EXPECT_LT((b.position - expected).norm(), 1e-12) << b.position.transpose();
  EXPECT_GT((b.position - (ball.position + n * dt * ball.velocity +
                           dt * dt * scene->world.gravity * n * (n + 1) / 2))
                .norm(),
            1e-6);  // the formula without substeps, which the comment used to give, is off

  const auto summary = nlohmann::json::parse(read_file(dir / "summary.json"));
  EXPECT_EQ(summary["settings"]["steps"], 30);
  EXPECT_EQ(summary["bodies"], 1);
  EXPECT_EQ(summary["stages"]["continuous"]["ran"], false);
  EXPECT_EQ(summary["stages"]["solve"]["ran"], true);
  char expected_hash[32];
  std::snprintf(expected_hash, sizeof expected_hash, "%016llx",
                static_cast<unsigned long long>(state_hash(world.state())));
  EXPECT_EQ(summary["final_state_hash"], expected_hash);
  EXPECT_NE(r.output.find(expected_hash), std::string::npos);
}

TEST(Cli, SameSceneTwiceGivesIdenticalBytes) {
  const fs::path a = scratch_dir("same_a");
  const fs::path b = scratch_dir("same_b");
  ASSERT_EQ(run_cli("run " + kScenes + "demo.yaml -q --steps 400 -o " + a.string()).exit_code, 0);
  ASSERT_EQ(run_cli("run " + kScenes + "demo.yaml -q --steps 400 -o " + b.string()).exit_code, 0);
  const std::string first = read_file(a / "trajectory.csv");
  EXPECT_GT(first.size(), 10000u);
  EXPECT_EQ(first, read_file(b / "trajectory.csv"));
  const auto sa = nlohmann::json::parse(read_file(a / "summary.json"));
  const auto sb = nlohmann::json::parse(read_file(b / "summary.json"));
  EXPECT_EQ(sa["final_state_hash"], sb["final_state_hash"]);
}

// The thread count changes how fast a run goes, never what it writes
// (dynamics/parallel_runner.hpp).
TEST(Cli, ThreadCountChangesNoByteOfTheTrajectory) {
  const fs::path one = scratch_dir("threads_1");
  const fs::path two = scratch_dir("threads_2");
  const std::string scene = kScenes + "demo.yaml -q --steps 200 ";
  ASSERT_EQ(run_cli("run " + scene + "--threads 1 -o " + one.string()).exit_code, 0);
  ASSERT_EQ(run_cli("run " + scene + "--threads 2 -o " + two.string()).exit_code, 0);
  EXPECT_EQ(read_file(one / "trajectory.csv"), read_file(two / "trajectory.csv"));
  const auto s1 = nlohmann::json::parse(read_file(one / "summary.json"));
  const auto s2 = nlohmann::json::parse(read_file(two / "summary.json"));
  EXPECT_EQ(s1["settings"]["threads"], 1);
  EXPECT_EQ(s2["settings"]["threads"], 2);
  EXPECT_EQ(s1["final_state_hash"], s2["final_state_hash"]);
}

TEST(Cli, DurationAndDtOverrides) {
  const fs::path dir = scratch_dir("overrides");
  ASSERT_EQ(
      run_cli("run " + kScenes + "free_flight.yaml -q --duration 0.5 --dt 0.01 -o " + dir.string())
          .exit_code,
      0);
  const auto summary = nlohmann::json::parse(read_file(dir / "summary.json"));
  EXPECT_EQ(summary["settings"]["steps"], 50);
  EXPECT_EQ(summary["settings"]["dt"], 0.01);
}

TEST(Cli, BadCommandLinesAreUserErrors) {
  const std::string scene = kScenes + "free_flight.yaml";
  for (const std::string& args : std::vector<std::string>{
           "run " + scene + " --dt -1", "run " + scene + " --dt nan", "run " + scene + " --dt inf",
           "run " + scene + " --steps 0", "run " + scene + " --steps 10 --duration 1",
           "run " + scene + " --steps abc", "run", "frobnicate", "run " + scene + " --bogus",
           "run " + scene + " --threads 0", "run " + scene + " --threads two",
           "bench " + scene + " --threads 1,0"}) {
    const Result r = run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
    EXPECT_FALSE(r.output.empty()) << args;
  }
}

TEST(Cli, VersionAndUnknownCommandsSaySo) {
  const Result version = run_cli("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.output.find("tumble 0.1.0"), std::string::npos) << version.output;
  const Result typo = run_cli("rnu scene.yaml");
  EXPECT_EQ(typo.exit_code, 1);
  EXPECT_NE(typo.output.find("unknown command 'rnu'"), std::string::npos) << typo.output;
  EXPECT_NE(typo.output.find("run, validate"), std::string::npos) << typo.output;
  // Below one frame a second ffmpeg writes no video: refused before anything runs.
  for (const char* fps : {"1e-9", "0.5", "nan", "2000"}) {
    const Result r = run_cli("render " + kScenes + "bounce.yaml --fps " + fps + " -o /tmp/x.mp4");
    EXPECT_EQ(r.exit_code, 1) << fps;
    EXPECT_NE(r.output.find("--fps"), std::string::npos) << fps << "\n" << r.output;
  }
}

// Overrides pass the scene's own checks: a time step below 1e-9 s, a duration beyond 1e9 s, and a
// step count duration / dt beyond 1e9 are refused by name before anything runs.
TEST(Cli, OverridesGetTheScenesChecks) {
  const std::string scene = kScenes + "free_flight.yaml";
  const std::vector<std::pair<std::string, std::string>> cases{
      {" --dt 1e-12", "--dt"},
      {" --dt 1e-300", "--dt"},
      {" --duration 1e300", "--duration"},
      {" --duration 1e8 --dt 0.01", "--duration"}};
  for (const auto& [args, named] : cases) {
    const Result r = run_cli("run " + scene + args + " -q -o /tmp/tumble_cli_overrides");
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("field '" + named + "'"), std::string::npos) << args << "\n"
                                                                         << r.output;
  }
}

// A trajectory past the output limit (100,000,000 rows: records times bodies) is refused before
// the run, with a --record-every that fits; that setting then runs.
TEST(Cli, ATrajectoryPastTheOutputLimitIsRefusedBeforeTheRun) {
  const fs::path dir = scratch_dir("output_limit");
  const std::string scene = kScenes + "free_flight.yaml";
  const Result refused = run_cli("run " + scene + " --steps 200000000 -q -o " + dir.string());
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("more rows than the limit of 100,000,000"), std::string::npos)
      << refused.output;
  EXPECT_NE(refused.output.find("--record-every 3 or more"), std::string::npos) << refused.output;
  EXPECT_FALSE(fs::exists(dir / "trajectory.csv"));
}

// summary.json counts the field contacts' surface walks and the capped ones (docs/sdf.md).
TEST(Cli, TheSummaryCountsTheFieldContactsWalks) {
  const fs::path dir = scratch_dir("sdf_walks");
  const Result r =
      run_cli("run " + kScenes + "sdf/torus_on_plane.yaml -q --steps 30 -o " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto counts = nlohmann::json::parse(read_file(dir / "summary.json"))["counts"];
  EXPECT_GT(counts["sdf_refinements"].get<std::int64_t>(), 0);
  EXPECT_LE(counts["sdf_refinements_capped"].get<std::int64_t>(),
            counts["sdf_refinements"].get<std::int64_t>());
  const Result boxes = run_cli("run " + kScenes + "stack10.yaml -q --steps 5 -o " + dir.string());
  ASSERT_EQ(boxes.exit_code, 0) << boxes.output;
  EXPECT_EQ(nlohmann::json::parse(read_file(dir / "summary.json"))["counts"]["sdf_refinements"], 0);
}

TEST(Cli, MissingSceneIsAUserError) {
  for (const std::string verb : {"run", "validate"}) {
    const Result r = run_cli(verb + " /nonexistent/dir/scene.yaml");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("/nonexistent/dir/scene.yaml"), std::string::npos) << r.output;
  }
}

// A fast body is swept (the summary counts it); `fast: true` under `ccd: off` runs unswept and
// says so.
TEST(Cli, FastBodiesAreSweptAndAConflictIsReported) {
  const fs::path dir = scratch_dir("ccd");
  const fs::path scene = dir / "fast.yaml";
  std::ofstream(scene) << "bodies:\n  - {name: bullet, shape: {type: sphere, radius: 0.01}, "
                          "velocity: [100, 0, 0], fast: true}\n";
  const Result r = run_cli("run " + scene.string() + " --steps 2 -o " + dir.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  const auto summary = nlohmann::json::parse(read_file(dir / "summary.json"));
  EXPECT_EQ(summary["counts"]["ccd_swept_bodies"], 2) << summary.dump();
  const fs::path off = dir / "fast_off.yaml";
  std::ofstream(off) << "world: {ccd: off}\nbodies:\n  - {name: bullet, shape: {type: sphere, "
                        "radius: 0.01}, velocity: [100, 0, 0], fast: true}\n";
  const Result warned = run_cli("run " + off.string() + " --steps 2 -o " + dir.string());
  EXPECT_EQ(warned.exit_code, 0) << warned.output;
  EXPECT_NE(warned.output.find("fast: true but sets ccd: off"), std::string::npos) << warned.output;
  const Result quiet = run_cli("run " + kScenes + "free_flight.yaml --steps 2 -o " + dir.string());
  EXPECT_EQ(quiet.output.find("warning"), std::string::npos) << quiet.output;
}

// `tumble ccd` scores a query file of the CCD benchmark, and refuses a malformed one naming the
// file and line.
TEST(Cli, CcdScoresASampleFileAndRejectsBadRows) {
  const std::string file =
      std::string(TUMBLE_SOURCE_DIR) +
      "/tests/data/external/ccd-sample-queries/unit-tests/vertex-face/data_0_0.csv";
  for (const std::string extra : {"", " --reverse-faces"}) {
    const Result r = run_cli("ccd " + file + " --kind vf" + extra);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto out = nlohmann::json::parse(r.output);
    EXPECT_EQ(out["queries"], 125);
    EXPECT_EQ(out["false_negatives"], 0);
    EXPECT_EQ(out["true_positives"], 35);  // the README's positives for this file
    EXPECT_EQ(out["true_positives"].get<int>() + out["false_positives"].get<int>() +
                  out["true_negatives"].get<int>() + out["false_negatives"].get<int>(),
              125);
    // The work per query: the largest is named (1-based) and bounds the median.
    EXPECT_GE(out["most_boxes_query"].get<int>(), 1);
    EXPECT_LE(out["most_boxes_query"].get<int>(), 125);
    EXPECT_GE(out["boxes_max"].get<int>(), out["boxes_median"].get<int>());
  }
  const fs::path dir = scratch_dir("ccd_bad");
  const fs::path bad = dir / "bad.csv";
  std::ofstream(bad) << "1,1,0,1,0,1,0\n1,1,x,1,0,1,0\n";
  const Result r = run_cli("ccd " + bad.string() + " --kind ee");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("bad.csv:2"), std::string::npos) << r.output;
  EXPECT_EQ(run_cli("ccd " + bad.string() + " --kind xx").exit_code, 1);
  // An empty file or a directory has nothing to score: an error, not a score of nothing.
  const fs::path empty = dir / "empty.csv";
  std::ofstream(empty).flush();
  const Result none = run_cli("ccd " + empty.string() + " --kind vf");
  EXPECT_EQ(none.exit_code, 1) << none.output;
  EXPECT_NE(none.output.find("no queries"), std::string::npos) << none.output;
  EXPECT_EQ(run_cli("ccd " + dir.string() + " --kind vf").exit_code, 1);
}

TEST(Cli, ValidateAcceptsEveryShippedScene) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(kScenes)) {
    if (entry.path().extension() != ".yaml")
      continue;
    const Result r = run_cli("validate " + entry.path().string());
    EXPECT_EQ(r.exit_code, 0) << entry.path() << "\n" << r.output;
    ++count;
  }
  EXPECT_GE(count, 6);
}

// Every malformed fixture is rejected with exit code 1 and a message that starts with the file
// and a line number (the loader's own tests check each message in detail).
TEST(Cli, ValidateRejectsEveryMalformedScene) {
  const fs::path dir = fs::path(TUMBLE_SOURCE_DIR) / "tests/data/malformed";
  int count = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml")
      continue;
    for (const std::string verb : {"validate ", "run -q -o /tmp/tumble_never_written "}) {
      const Result r = run_cli(verb + entry.path().string());
      EXPECT_EQ(r.exit_code, 1) << entry.path() << "\n" << r.output;
      EXPECT_EQ(r.output.rfind(entry.path().string() + ":", 0), 0u) << r.output;
    }
    ++count;
  }
  EXPECT_GE(count, 20);
}

// An interrupted run leaves the previous output untouched and no file half-written.
TEST(Cli, ASceneFileNameThatIsNotUtf8IsWrittenAsTheReplacementCharacter) {
  const fs::path dir = scratch_dir("not_utf8");
  const fs::path scene = dir / "scene\xff\xfe.yaml";  // bytes no UTF-8 text holds
  fs::copy_file(kScenes + "free_flight.yaml", scene);
  const Result r =
      run_cli("run '" + scene.string() + "' -q --steps 3 -o " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const std::string summary = read_file(dir / "out" / "summary.json");
  EXPECT_NE(summary.find("scene\xef\xbf\xbd\xef\xbf\xbd.yaml"), std::string::npos) << summary;
  EXPECT_TRUE(fs::exists(dir / "out" / "trajectory.csv"));
}

TEST(Cli, FilesOutsideTheScenesFolderNeedTheFlag) {
  const fs::path dir = scratch_dir("outside_files");
  std::ofstream(dir / "outside.obj")
      << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  fs::create_directories(dir / "scene");
  const fs::path scene = dir / "scene" / "scene.yaml";
  std::ofstream(scene)
      << "world: {dt: 0.01, duration: 0.02}\nbodies:\n"
         "  - {name: m, static: true, shape: {type: hull, file: ../outside.obj}}\n";
  const std::string out = (dir / "out").string();
  const Result refused = run_cli("run " + scene.string() + " -q -o " + out);
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("scene.yaml:3:"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("lies outside the scene's folder"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "out" / "trajectory.csv"));
  // The flag goes before or after the command.
  EXPECT_EQ(run_cli("--allow-outside-files run " + scene.string() + " -q -o " + out).exit_code, 0);
  EXPECT_EQ(run_cli("run " + scene.string() + " -q -o " + out + " --allow-outside-files").exit_code,
            0);
  EXPECT_EQ(run_cli("validate " + scene.string()).exit_code, 1);
  EXPECT_EQ(run_cli("validate " + scene.string() + " --allow-outside-files").exit_code, 0);
}

// Starts `tumble run` of a long scene into `out` and returns its pid once it is writing its
// temporary trajectory file.
pid_t start_long_run(const fs::path& out) {
  const std::string cli = TUMBLE_CLI;
  const std::string scene = kScenes + "stack10.yaml";
  const std::string dir = out.string();
  // A run of hours, writing every 1000th step (all of them would pass the output limit).
  std::vector<std::string> args = {
      cli, "run", scene, "-q", "--steps", "100000000", "--record-every", "1000", "-o", dir};
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (::posix_spawn(&pid, cli.c_str(), nullptr, nullptr, argv.data(), environ) != 0)
    return 0;
  for (int i = 0; i < 200; ++i) {
    bool temporary_seen = false;
    for (const auto& e : fs::directory_iterator(out)) {
      temporary_seen =
          temporary_seen || e.path().filename().string().find(".tmp.") != std::string::npos;
    }
    if (temporary_seen)
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  return pid;
}

int temporary_files_in(const fs::path& dir) {
  int count = 0;
  for (const auto& e : fs::directory_iterator(dir))
    count += e.path().filename().string().find(".tmp.") != std::string::npos ? 1 : 0;
  return count;
}

TEST(Cli, AnInterruptedRunLeavesNoPartialFile) {
  const fs::path dir = scratch_dir("interrupt");
  ASSERT_EQ(
      run_cli("run " + kScenes + "free_flight.yaml -q --steps 5 -o " + dir.string()).exit_code, 0);
  const std::string before = read_file(dir / "trajectory.csv");
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    const pid_t pid = start_long_run(dir);
    ASSERT_GT(pid, 0);
    ASSERT_EQ(::kill(pid, signal), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)) << "signal " << signal;
    EXPECT_EQ(WEXITSTATUS(status), 130) << "signal " << signal;
    EXPECT_EQ(read_file(dir / "trajectory.csv"), before) << "signal " << signal;
    EXPECT_EQ(temporary_files_in(dir), 0) << "signal " << signal;
  }
}

TEST(Cli, AKilledRunsTemporaryFileGoesWithTheNextRunIntoItsFolder) {
  const fs::path dir = scratch_dir("killed");
  ASSERT_EQ(
      run_cli("run " + kScenes + "free_flight.yaml -q --steps 5 -o " + dir.string()).exit_code, 0);
  const std::string before = read_file(dir / "trajectory.csv");
  const pid_t pid = start_long_run(dir);
  ASSERT_GT(pid, 0);
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  // SIGKILL cannot be caught: its temporary file stays, the complete file keeps its name.
  EXPECT_EQ(temporary_files_in(dir), 1);
  EXPECT_EQ(read_file(dir / "trajectory.csv"), before);
  // A temporary file of a process still running (this test's) is not another run's to remove.
  const fs::path live = dir / ("trajectory.csv.tmp." + std::to_string(::getpid()));
  std::ofstream(live) << "in progress";
  ASSERT_EQ(
      run_cli("run " + kScenes + "free_flight.yaml -q --steps 5 -o " + dir.string()).exit_code, 0);
  EXPECT_EQ(temporary_files_in(dir), 1);
  EXPECT_TRUE(fs::exists(live));
  EXPECT_EQ(read_file(dir / "trajectory.csv"), before);
}

// A run whose write failed with `error` (an errno) named the file and the reason, kept the
// previous run's trajectory and summary under their names and bytes, and left no temporary file.
void expect_previous_outputs_kept(const Result& r, int error, const fs::path& dir,
                                  const std::string& trajectory, const std::string& summary) {
  EXPECT_NE(r.output.find("trajectory.csv"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(std::strerror(error)), std::string::npos) << r.output;
  EXPECT_EQ(read_file(dir / "trajectory.csv"), trajectory);
  EXPECT_EQ(read_file(dir / "summary.json"), summary);
  EXPECT_EQ(temporary_files_in(dir), 0);
}

// A disk that fills while a run writes: the process's file size limit (RLIMIT_FSIZE, with
// SIGXFSZ ignored) makes a write fail part way with EFBIG, as a full disk fails it with ENOSPC,
// without the privileges a small tmpfs needs. The run must say so and fail, keep the files of the
// run before under their names, and leave no temporary file and no new summary.
TEST(Cli, AWriteThatFailsPartWayLeavesThePreviousOutputs) {
  const fs::path dir = scratch_dir("full_disk");
  ASSERT_EQ(
      run_cli("run " + kScenes + "free_flight.yaml -q --steps 5 -o " + dir.string()).exit_code, 0);
  const std::string trajectory = read_file(dir / "trajectory.csv");
  const std::string summary = read_file(dir / "summary.json");
  ASSERT_LT(trajectory.size(), 8192u);
  // 16 blocks of 512 bytes: the 2,000-step trajectory (about 300 KB) cannot fit.
  // Built with append: GCC 12 warns falsely (-Warray-bounds) about "..." + std::string inlined.
  std::string command("trap '' XFSZ; ulimit -f 16; ");
  command.append(TUMBLE_CLI).append(" run ").append(kScenes);
  command.append("free_flight.yaml -q --steps 2000 -o ").append(dir.string()).append(" 2>&1");
  const Result r = run_shell(command);
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_LT(r.exit_code, 128) << r.output;  // an error exit, not a signal
  expect_previous_outputs_kept(r, EFBIG, dir, trajectory, summary);
}

// The same on a full disk: a 64 KiB tmpfs, where the write fails with ENOSPC. Mounting needs
// privileges (root, or CAP_SYS_ADMIN); without them the test says so and skips.
TEST(Cli, AFullDiskLeavesThePreviousOutputs) {
  const fs::path dir = scratch_dir("tmpfs");
  if (::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=64k") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
  struct Unmount {
    fs::path dir;
    ~Unmount() { ::umount(dir.c_str()); }
  } unmount{dir};
  ASSERT_EQ(
      run_cli("run " + kScenes + "free_flight.yaml -q --steps 5 -o " + dir.string()).exit_code, 0);
  const std::string trajectory = read_file(dir / "trajectory.csv");
  const std::string summary = read_file(dir / "summary.json");
  ASSERT_FALSE(trajectory.empty());
  // About 300 KB of trajectory for 64 KiB of disk.
  const Result r =
      run_cli("run " + kScenes + "free_flight.yaml -q --steps 2000 -o " + dir.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_previous_outputs_kept(r, ENOSPC, dir, trajectory, summary);
}

// Memory the scene needs past what the process may have: `tumble: out of memory` and exit code 4,
// not a scene error or an internal one. The same scene with coarser cells runs under the same
// limit, so the limit is what fails, not the file. AddressSanitizer reserves terabytes of
// address space for its shadow, so an address-space limit cannot be set under it.
// GCC says AddressSanitizer by a macro, clang by __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define TUMBLE_TEST_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TUMBLE_TEST_UNDER_ASAN 1
#endif
#endif
TEST(Cli, RunningOutOfMemoryIsReportedAsSuch) {
#if defined(TUMBLE_TEST_UNDER_ASAN)
  GTEST_SKIP() << "an address-space limit does not work under AddressSanitizer";
#else
  const fs::path dir = scratch_dir("memory");
  fs::copy_file(kScenes + "sdf/meshes/bowl_closed.obj", dir / "bowl.obj");
  const auto scene = [&](const std::string& cell) {
    const fs::path path = dir / ("bowl_" + cell + ".yaml");
    std::ofstream(path) << "world: {dt: 0.01, duration: 0.02}\n"
                           "bodies:\n"
                           "  - name: bowl\n"
                           "    static: true\n"
                           "    shape: {type: sdf, sdf: {grid: {file: bowl.obj, cell: "
                        << cell << "}}}\n";
    return path.string();
  };
  // 300 MB of address space: the coarse grid's run fits in 80 MB, the fine grid's needs over
  // 430 MB (measured in the optimised build, which maps no OSMesa or OpenVDB until asked).
  const auto run_limited = [&](const std::string& path) {
    std::string command("ulimit -v 300000 && ");
    command.append(TUMBLE_CLI).append(" run -q ").append(path).append(" -o ");
    command.append((dir / "out").string()).append(" 2>&1");
    return run_shell(command);
  };
  const Result coarse = run_limited(scene("0.02"));
  ASSERT_EQ(coarse.exit_code, 0) << coarse.output;
  // 3 mm cells: tens of millions of nodes, within the grid's node limit.
  const Result fine = run_limited(scene("0.003"));
  EXPECT_EQ(fine.exit_code, 4) << fine.output;
  EXPECT_NE(fine.output.find("tumble: out of memory"), std::string::npos) << fine.output;
  EXPECT_EQ(fine.output.find("internal error"), std::string::npos) << fine.output;
  EXPECT_EQ(fine.output.find("bad_alloc"), std::string::npos) << fine.output;
#endif
}

}  // namespace
}  // namespace tumble::test
