// `tumble query` run as a user runs it: one JSON line per query, distances and normals against
// closed forms, the swap of a and b, and a bad file named by file, line and field.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace tumble::test {
namespace {

namespace fs = std::filesystem;

struct Output {
  int exit_code = -1;
  std::string text;
};

Output run_query(const fs::path& file) {
  const std::string command = std::string(TUMBLE_CLI) + " query " + file.string() + " 2>&1";
  Output r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr)
    return r;
  std::array<char, 4096> buffer;
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    r.text.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

fs::path write_query_file(const std::string& name, const std::string& text) {
  const fs::path dir =
      fs::temp_directory_path() / ("tumble_query_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

std::vector<nlohmann::json> lines_of(const std::string& text) {
  std::vector<nlohmann::json> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    out.push_back(nlohmann::json::parse(line));
  return out;
}

TEST(QueryCommand, AnswersEachQueryOnOneJsonLine) {
  const fs::path file = write_query_file("good.yaml", R"(
queries:
  - name: spheres_apart
    a: {shape: {type: sphere, radius: 0.5}, position: [3, 0, 0]}
    b: {shape: {type: sphere, radius: 1.0}, position: [0, 0, 0]}
  - name: spheres_apart_swapped
    a: {shape: {type: sphere, radius: 1.0}, position: [0, 0, 0]}
    b: {shape: {type: sphere, radius: 0.5}, position: [3, 0, 0]}
  - name: ball_in_mesh
    a: {shape: {type: sphere, radius: 0.5}, position: [0.2, 0.2, 0.4]}
    b:
      shape: {type: mesh, vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles: [[0, 1, 2]]}
  - name: dumbbell_on_floor
    a:
      shape:
        type: compound
        parts:
          - {shape: {type: sphere, radius: 0.5}, position: [-1, 0, 0]}
          - {shape: {type: sphere, radius: 0.5}, position: [1, 0, 0]}
      position: [0, 0, 0.45]
    b: {shape: {type: plane}}
  - name: far_apart
    margin: 1
    a: {shape: {type: sphere, radius: 0.5}, position: [0, 0, 100]}
    b: {shape: {type: plane}}
  - name: two_meshes
    a: {shape: {type: mesh, vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles: [[0, 1, 2]]}}
    b: {shape: {type: plane}}
)");
  const Output r = run_query(file);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const auto q = lines_of(r.text);
  ASSERT_EQ(q.size(), 6u);
  EXPECT_EQ(q[0]["name"], "spheres_apart");
  EXPECT_EQ(q[0]["status"], "separated");
  EXPECT_NEAR(q[0]["distance"].get<double>(), 1.5, 1e-12);
  EXPECT_NEAR(q[0]["normal"][0].get<double>(), 1, 1e-12);  // from b to a
  EXPECT_NEAR(q[0]["point_a"][0].get<double>(), 2.5, 1e-12);
  EXPECT_NEAR(q[0]["point_b"][0].get<double>(), 1.0, 1e-12);
  // Swapped: the normal flips, the witnesses swap, the distance stays.
  EXPECT_EQ(q[1]["distance"], q[0]["distance"]);
  EXPECT_NEAR(q[1]["normal"][0].get<double>(), -1, 1e-12);
  EXPECT_EQ(q[1]["point_a"], q[0]["point_b"]);
  EXPECT_EQ(q[1]["point_b"], q[0]["point_a"]);
  EXPECT_EQ(q[2]["status"], "penetrating");
  EXPECT_NEAR(q[2]["distance"].get<double>(), -0.1, 1e-12);
  EXPECT_EQ(q[3]["status"], "penetrating");
  EXPECT_EQ(q[3]["contacts"].size(), 2u);
  EXPECT_NEAR(q[3]["distance"].get<double>(), -0.05, 1e-12);
  EXPECT_EQ(q[4]["status"], "beyond_margin");
  EXPECT_TRUE(q[4]["distance"].is_null());
  EXPECT_EQ(q[5]["status"], "unsupported");
}

TEST(QueryCommand, BadFileNamesFileLineAndField) {
  const fs::path file = write_query_file("bad.yaml", R"(queries:
  - name: broken
    a: {shape: {type: box, half_extents: [1, 1]}}
    b: {shape: {type: plane}}
)");
  const Output r = run_query(file);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.text.find("bad.yaml:3:"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("field 'queries[0].a.shape.half_extents'"), std::string::npos) << r.text;
  const fs::path kind = write_query_file("kind.yaml", R"(queries:
  - {kind: sweep, a: {shape: {type: plane}}, b: {shape: {type: plane}}}
)");
  const Output k = run_query(kind);
  EXPECT_EQ(k.exit_code, 1);
  EXPECT_NE(k.text.find("field 'queries[0].kind': expected one of: contact"), std::string::npos)
      << k.text;
}

}  // namespace
}  // namespace tumble::test
