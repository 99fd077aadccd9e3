// `tumble run --format npy|both --contacts`: the .npy file holds what the CSV holds, under a
// header numpy reads (checked here against the format's definition), and contacts.csv holds what
// the World's contact reports hold, step by step.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "apps/npy_trajectory_writer.hpp"
#include "tumble/tumble.hpp"

namespace tumble::test {
namespace {

namespace fs = std::filesystem;

int run_tumble(const std::string& arguments) {
  // Built by appending: GCC 12 warns (falsely) on a chain of + starting from a literal here.
  std::string command = TUMBLE_CLI;
  command += ' ';
  command += arguments;
  command += " > /dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::vector<std::string>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> row;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ','))
      row.push_back(field);
    rows.push_back(row);
  }
  return rows;
}

TEST(RunOutputs, NpyHoldsTheCsvsNumbersUnderAValidHeader) {
  const fs::path dir = fs::temp_directory_path() / "tumble_run_outputs_npy";
  fs::remove_all(dir);
  const std::string scene = std::string(TUMBLE_SOURCE_DIR) + "/scenes/stack10.yaml";
  ASSERT_EQ(run_tumble("run " + scene + " --steps 20 --format both -q -o " + dir.string()), 0);
  std::ifstream in(dir / "trajectory.npy", std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
  ASSERT_GT(bytes.size(), 10u);
  // Magic, version 1.0, a little-endian header length; the data starts on a 64-byte boundary.
  EXPECT_EQ(std::memcmp(bytes.data(), "\x93NUMPY\x01\x00", 8), 0);
  const std::size_t header_length =
      std::size_t(std::uint8_t(bytes[8])) | std::size_t(std::uint8_t(bytes[9])) << 8;
  const std::size_t data_start = 10 + header_length;
  EXPECT_EQ(data_start % 64, 0u);
  const std::string header(bytes.data() + 10, header_length);
  EXPECT_NE(header.find("'descr': '<f8'"), std::string::npos) << header;
  EXPECT_NE(header.find("'fortran_order': False"), std::string::npos);
  // The ten boxes: the static ground is left out (it never moves).
  EXPECT_NE(header.find("'shape': (21, 10, 13)"), std::string::npos) << header;
  EXPECT_EQ(header.back(), '\n');
  ASSERT_EQ(bytes.size(), data_start + 21 * 10 * 13 * sizeof(double));
  std::vector<double> data(21 * 10 * 13);
  std::memcpy(data.data(), bytes.data() + data_start, data.size() * sizeof(double));
  const auto rows = read_csv(dir / "trajectory.csv");
  ASSERT_EQ(rows.size(), 1u + 21 * 10);
  for (std::size_t r = 1; r < rows.size(); ++r) {
    for (std::size_t c = 0; c < 13; ++c)
      ASSERT_EQ(std::stod(rows[r][c + 2]), data[(r - 1) * 13 + c]) << "row " << r << " col " << c;
  }
  fs::remove_all(dir);
}

TEST(RunOutputs, StaticBodiesOnlyWhenAskedAndNamedInTheSummary) {
  const fs::path dir = fs::temp_directory_path() / "tumble_run_outputs_static";
  fs::remove_all(dir);
  const std::string scene = std::string(TUMBLE_SOURCE_DIR) + "/scenes/stack10.yaml";
  ASSERT_EQ(run_tumble("run " + scene + " --steps 3 -q -o " + dir.string()), 0);
  const auto without = read_csv(dir / "trajectory.csv");
  ASSERT_EQ(without.size(), 1u + 4 * 10);
  for (std::size_t r = 1; r < without.size(); ++r)
    EXPECT_NE(without[r][1], "floor") << "row " << r;
  std::ifstream summary(dir / "summary.json");
  const std::string text((std::istreambuf_iterator<char>(summary)), {});
  EXPECT_NE(text.find("\"trajectory_bodies\""), std::string::npos);
  EXPECT_EQ(text.find("\"floor\""), std::string::npos) << text;
  ASSERT_EQ(run_tumble("run " + scene + " --steps 3 -q --static-bodies -o " + dir.string()), 0);
  const auto with = read_csv(dir / "trajectory.csv");
  ASSERT_EQ(with.size(), 1u + 4 * 11);
  EXPECT_EQ(with[1][1], "floor");
  fs::remove_all(dir);
}

// An inertia no mass within the shape can have (above m R^2) once ran into NaN; now the run
// refuses it before writing anything, naming the line and the field.
TEST(RunOutputs, AnImpossibleInertiaIsRefusedBeforeAnyOutput) {
  const fs::path dir = fs::temp_directory_path() / "tumble_run_outputs_non_finite";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = dir / "needle.yaml";
  std::ofstream(scene) << "bodies:\n"
                          "  - {name: floor, static: true, shape: {type: plane}}\n"
                          "  - {name: needle, shape: {type: box, half_extents: [0.5, 0.5, 0.5]},"
                          " mass: 1, inertia: [1e-20, 1e20, 1e20], position: [0, 0, 0.6],"
                          " angular_velocity: [1, 2, 3]}\n";
  const fs::path out = dir / "out";
  EXPECT_EQ(run_tumble("run " + scene.string() + " --steps 50 -q -o " + out.string()), 1);
  EXPECT_FALSE(fs::exists(out / "trajectory.csv"));
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  fs::remove_all(dir);
}

TEST(RunOutputs, ContactsCsvHoldsTheWorldsReports) {
  const fs::path dir = fs::temp_directory_path() / "tumble_run_outputs_contacts";
  fs::remove_all(dir);
  const std::string scene = std::string(TUMBLE_SOURCE_DIR) + "/scenes/stack10.yaml";
  ASSERT_EQ(run_tumble("run " + scene + " --steps 30 --contacts -q -o " + dir.string()), 0);
  const auto rows = read_csv(dir / "contacts.csv");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0].size(), 14u);
  World world(load_scene(scene));
  std::size_t row = 1;
  for (int step = 1; step <= 30; ++step) {
    world.step();
    for (const ContactReport& r : world.contact_reports()) {
      for (int k = 0; k < r.point_count; ++k, ++row) {
        ASSERT_LT(row, rows.size());
        EXPECT_EQ(rows[row][1], world.name(r.body_a));
        EXPECT_EQ(rows[row][2], world.name(r.body_b));
        EXPECT_EQ(std::stod(rows[row][10]), r.points[std::size_t(k)].normal_impulse);
      }
    }
  }
  EXPECT_EQ(row, rows.size());
  fs::remove_all(dir);
}

TEST(RunOutputs, NpyHeaderIsPaddedToItsSize) {
  const std::string h = app::NpyTrajectoryWriter::header(123456789, 3000, 128);
  EXPECT_EQ(h.size(), 128u);
  EXPECT_EQ(h.back(), '\n');
}

}  // namespace
}  // namespace tumble::test
