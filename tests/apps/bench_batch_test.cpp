// The batch benchmark's peers are sane before their times are compared: the MJCF of a scene holds
// its bodies, MuJoCo rests its boxes on the plane at their half heights (a fact of the scene, not
// of tumble), and `tumble bench-batch` runs all three engines and writes its CSV.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "apps/bullet_bridge.hpp"
#include "apps/mujoco_bridge.hpp"
#include "tests/apps/command_runner.hpp"
#include "tumble/load_scene.hpp"

namespace tumble::test {
namespace {

const std::filesystem::path kBoxes =
    std::filesystem::path(TUMBLE_SOURCE_DIR) / "scenes/rl/boxes20.yaml";

int count_of(const std::string& text, const std::string& word) {
  int n = 0;
  for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1))
    ++n;
  return n;
}

TEST(MujocoPeer, MjcfHoldsEveryBodyAndRefusesWhatItCannotExpress) {
  const auto scene = load_scene(kBoxes);
  const std::string xml = app::mjcf_of(*scene);
  EXPECT_EQ(count_of(xml, "<freejoint/>"), 20);
  EXPECT_EQ(count_of(xml, "type=\"box\""), 20);
  EXPECT_EQ(count_of(xml, "type=\"plane\""), 1);
  Scene with_hull = *scene;
  with_hull.bodies[3].shape =
      hull_from_points(std::vector<Vec3>{{0, 0, 0}, {0.2, 0, 0}, {0, 0.2, 0}, {0, 0, 0.2}});
  try {
    app::mjcf_of(with_hull);
    FAIL() << "a hull was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[3] 'box2'"), std::string::npos) << e.what();
  }
}

TEST(MujocoPeer, BoxesComeToRestOnThePlaneAtTheirHalfHeights) {
  if (!app::mujoco_available())
    GTEST_SKIP() << "built without MuJoCo";
  const auto scene = load_scene(kBoxes);
  app::MujocoBatch batch(*scene, 2);
  for (int s = 0; s < 90; ++s)
    for (int w = 0; w < 2; ++w)
      batch.step(w);
  for (int b = 0; b < 20; ++b) {
    const Real half_height = scene->bodies[std::size_t(b + 1)].shape.half_extents.z();
    EXPECT_NEAR(batch.height(0, b), half_height, 5e-3) << "box " << b;
    EXPECT_EQ(batch.height(0, b), batch.height(1, b));
  }
  EXPECT_GE(batch.contacts(0), 20 * 3);  // each box stands on at least three points
  EXPECT_GT(batch.bytes_per_world(), 0u);
}

TEST(BenchBatch, RunsEveryEngineAndWritesItsCsv) {
  const std::filesystem::path csv = std::filesystem::temp_directory_path() /
                                    ("tumble_bench_batch_" + std::to_string(::getpid()) + ".csv");
  const CommandOutput run = run_tumble_command(
      "bench-batch " + kBoxes.string() +
      " --worlds 1,3 --threads 1,2 --steps 4 --repetitions 2 -o " + csv.string());
  const std::string& output = run.text;
  ASSERT_EQ(run.exit_code, 0) << output;
  EXPECT_NE(output.find("Where a batch step goes: 3 worlds"), std::string::npos) << output;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("worlds,threads,engine,rate_median", 0), 0u) << line;
  int tumble_rows = 0, mujoco_rows = 0, bullet_rows = 0;
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::string worlds, threads, engine, rate;
    std::getline(fields, worlds, ',');
    std::getline(fields, threads, ',');
    std::getline(fields, engine, ',');
    std::getline(fields, rate, ',');
    EXPECT_GT(std::stod(rate), 0) << line;
    tumble_rows += engine == "tumble";
    mujoco_rows += engine == "MuJoCo";
    bullet_rows += engine == "Bullet";
  }
  EXPECT_EQ(tumble_rows, 4);  // 2 world counts x 2 thread counts
  EXPECT_EQ(mujoco_rows, app::mujoco_available() ? 4 : 0);
  EXPECT_EQ(bullet_rows, app::bullet_available() ? 4 : 0);
  std::filesystem::remove(csv);
}

// The figures of a large batch depend on whether malloc backs the heap with huge pages (a glibc
// tunable read at the start of the process): the output says which.
TEST(BenchBatch, SaysWhetherMallocUsesHugePages) {
  const char* before = std::getenv("GLIBC_TUNABLES");
  const std::string kept = before == nullptr ? "" : before;
  const auto huge_pages_line = [] {
    const CommandOutput run =
        run_tumble_command("bench-batch " + kBoxes.string() +
                           " --worlds 1 --threads 1 --steps 1 --repetitions 1 --peers none");
    EXPECT_EQ(run.exit_code, 0) << run.text;
    const std::size_t at = run.text.find("malloc huge pages: ");
    return at == std::string::npos ? std::string()
                                   : run.text.substr(at, run.text.find('\n', at) - at);
  };
  ::setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1", 1);
  EXPECT_EQ(huge_pages_line().rfind("malloc huge pages: on", 0), 0u);
  ::setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=0", 1);
  EXPECT_EQ(huge_pages_line().rfind("malloc huge pages: off", 0), 0u);
  ::unsetenv("GLIBC_TUNABLES");
  EXPECT_EQ(huge_pages_line().rfind("malloc huge pages: off", 0), 0u);
  if (before != nullptr)
    ::setenv("GLIBC_TUNABLES", kept.c_str(), 1);
}

}  // namespace
}  // namespace tumble::test
