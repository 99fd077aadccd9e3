// `tumble query` run as a user runs it: one JSON line per query, distances and normals against
// closed forms, the swap of a and b, and a bad file named by file, line and field.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "collision/math.hpp"

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

// A pair with a field reports its surface walks: how many, how many stopped at the step cap,
// and whether the deepest one converged; other pairs do not have the fields.
TEST(QueryCommand, AFieldPairReportsItsSurfaceWalks) {
  const fs::path file = write_query_file("fields.yaml", R"(
queries:
  - name: two_field_balls
    a: {shape: {type: sdf, sdf: {sphere: {radius: 0.3}}}, position: [0.1, 0, 0.79]}
    b: {shape: {type: sdf, sdf: {sphere: {radius: 0.5}}}}
  - name: ball_on_mesh
    a: {shape: {type: sphere, radius: 0.5}, position: [0.2, 0.2, 0.4]}
    b:
      shape: {type: mesh, vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles: [[0, 1, 2]]}
)");
  const Output r = run_query(file);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const std::vector<nlohmann::json> answers = lines_of(r.text);
  ASSERT_EQ(answers.size(), 2u);
  EXPECT_GT(answers[0]["refinements"].get<int>(), 0);
  EXPECT_LE(answers[0]["refinements_capped"].get<int>(), answers[0]["refinements"].get<int>());
  EXPECT_EQ(answers[0]["deepest_walk"], "converged");
  EXPECT_FALSE(answers[1].contains("refinements"));
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

std::string yaml_vector(const Vec3& v) {
  std::ostringstream out;
  out.precision(17);
  out << '[' << v.x() << ", " << v.y() << ", " << v.z() << ']';
  return out.str();
}

std::string yaml_quaternion(const Quat& q) {
  std::ostringstream out;
  out.precision(17);
  out << '[' << q.w() << ", " << q.x() << ", " << q.y() << ", " << q.z() << ']';
  return out.str();
}

Vec3 vec_of(const nlohmann::json& j) {
  return Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
}

TEST(QueryCommand, SphereDistanceByGjkEqualsClosedForm) {
  const Vec3 ca(0.3, -1.2, 2.5), cb(-1.1, 0.4, 0.9);
  const Real ra = 0.7, rb = 0.45;
  const fs::path file = write_query_file(
      "spheres.yaml",
      "queries:\n  - a: {shape: {type: sphere, radius: 0.7}, position: " + yaml_vector(ca) +
          "}\n    b: {shape: {type: sphere, radius: 0.45}, position: " + yaml_vector(cb) + "}\n");
  const Output r = run_query(file);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const auto q = lines_of(r.text);
  ASSERT_EQ(q.size(), 1u);
  EXPECT_EQ(q[0]["status_source"], "gjk");
  EXPECT_EQ(q[0]["status"], "separated");
  EXPECT_EQ(q[0]["state"], "separated");
  const Real expected = (ca - cb).norm() - ra - rb;
  EXPECT_NEAR(q[0]["distance"].get<double>(), expected, 1e-12);
  const Vec3 n = (ca - cb).normalized();
  EXPECT_NEAR((vec_of(q[0]["normal"]) - n).norm(), 0, 1e-12);
  EXPECT_NEAR((vec_of(q[0]["point_a"]) - (ca - ra * n)).norm(), 0, 1e-12);
  EXPECT_NEAR((vec_of(q[0]["point_b"]) - (cb + rb * n)).norm(), 0, 1e-12);
  EXPECT_FALSE(q[0]["contacts"].empty());  // the manifold is listed within the margin
}

// Penetration depth of two boxes: the minimum overlap over the 15 separating-axis candidates
// (3 face normals of each box, 9 edge-edge cross products), computed here independently.
Real box_box_sat_depth(const Vec3& ha, const Transform& pa, const Vec3& hb, const Transform& pb) {
  const Mat3 ra = pa.rotation.toRotationMatrix();
  const Mat3 rb = pb.rotation.toRotationMatrix();
  std::vector<Vec3> axes;
  for (int i = 0; i < 3; ++i) {
    axes.push_back(ra.col(i));
    axes.push_back(rb.col(i));
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Vec3 c = ra.col(i).cross(rb.col(j));
      if (c.norm() > 1e-9)
        axes.push_back(c.normalized());
    }
  const Vec3 d = pb.translation - pa.translation;
  Real depth = std::numeric_limits<Real>::infinity();
  for (const Vec3& l : axes) {
    Real reach = 0;
    for (int i = 0; i < 3; ++i)
      reach += ha[i] * std::abs(ra.col(i).dot(l)) + hb[i] * std::abs(rb.col(i).dot(l));
    depth = std::min(depth, reach - std::abs(d.dot(l)));
  }
  return depth;
}

TEST(QueryCommand, BoxBoxDepthByEpaEqualsSatMinimum) {
  const Vec3 ha(0.6, 0.4, 0.3), hb(0.5, 0.35, 0.25);
  Transform pa, pb;
  pa.translation = Vec3(0.1, -0.2, 0.3);
  pa.rotation = Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  pb.translation = Vec3(0.75, 0.15, 0.55);
  pb.rotation = Quat(Eigen::AngleAxisd(1.1, Vec3(-2, 1, 0.5).normalized()));
  const Real expected = box_box_sat_depth(ha, pa, hb, pb);
  ASSERT_GT(expected, 0.01);  // the poses overlap by a clear margin
  const fs::path file = write_query_file(
      "boxes.yaml", "queries:\n  - a: {shape: {type: box, half_extents: " + yaml_vector(ha) +
                        "}, position: " + yaml_vector(pa.translation) +
                        ", orientation: " + yaml_quaternion(pa.rotation) +
                        "}\n    b: {shape: {type: box, half_extents: " + yaml_vector(hb) +
                        "}, position: " + yaml_vector(pb.translation) +
                        ", orientation: " + yaml_quaternion(pb.rotation) + "}\n");
  const Output r = run_query(file);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const auto q = lines_of(r.text);
  ASSERT_EQ(q.size(), 1u);
  EXPECT_EQ(q[0]["status_source"], "epa");
  EXPECT_EQ(q[0]["status"], "converged");
  EXPECT_EQ(q[0]["state"], "penetrating");
  EXPECT_NEAR(-q[0]["distance"].get<double>(), expected, 1e-9);
  // Witnesses: point_a - point_b = distance * normal (translating a by depth along the normal
  // separates the boxes).
  const Vec3 n = vec_of(q[0]["normal"]);
  EXPECT_NEAR(n.norm(), 1, 1e-12);
  EXPECT_NEAR(
      (vec_of(q[0]["point_a"]) - vec_of(q[0]["point_b"]) - q[0]["distance"].get<double>() * n)
          .norm(),
      0, 1e-9);
  EXPECT_FALSE(q[0]["contacts"].empty());
}

TEST(QueryCommand, TimeOfImpactOfTwoSpheresMatchesClosedForm) {
  // a (radius 0.5) moves at 2 m/s along x past b (radius 0.25) offset by 0.2 in y: contact when
  // |d + v t| = 0.75 with d = a - b = (-3, -0.2, 0), v = (2, 0, 0).
  const fs::path file = write_query_file("toi.yaml", R"(queries:
  - name: glancing
    kind: toi
    duration: 2
    a: {shape: {type: sphere, radius: 0.5}, position: [10, 5, 1], velocity: [2, 0, 0]}
    b: {shape: {type: sphere, radius: 0.25}, position: [13, 5.2, 1]}
  - name: miss
    kind: toi
    a: {shape: {type: sphere, radius: 0.5}, position: [0, 0, 0], velocity: [2, 0, 0]}
    b: {shape: {type: sphere, radius: 0.25}, position: [3, 1, 0], angular_velocity: [0, 0, 3]}
)");
  const Output r = run_query(file);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const auto q = lines_of(r.text);
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0]["kind"], "toi");
  EXPECT_EQ(q[0]["status"], "hit");
  const Real expected = (3 - std::sqrt(0.75 * 0.75 - 0.2 * 0.2)) / 2;
  EXPECT_NEAR(q[0]["toi"].get<double>(), expected, 1e-9);
  const Vec3 a_at(10 + 2 * expected, 5, 1), b_at(13, 5.2, 1);
  EXPECT_NEAR((vec_of(q[0]["normal"]) - (a_at - b_at).normalized()).norm(), 0, 1e-6);
  EXPECT_NEAR((vec_of(q[0]["pose_a"]["position"]) - a_at).norm(), 0, 1e-8);
  EXPECT_NEAR((vec_of(q[0]["pose_b"]["position"]) - b_at).norm(), 0, 1e-12);
  // Closest approach in the second query is 1 m > 0.75 m: no impact within the default 1 s.
  EXPECT_EQ(q[1]["status"], "separated");
  EXPECT_TRUE(q[1]["toi"].is_null());
}

TEST(QueryCommand, TimeExtendedSatMethodMatchesTheClosedFormAndAdvancement) {
  // A cube (half size 0.5) falls at 4 m/s onto a cube (half size 0.25) turned about z: the gap
  // of 1.25 m closes at t = 0.3125 s. The hull version spins about the vertical, which moves
  // no point along it: the same time.
  const fs::path file = write_query_file("sat.yaml", R"(queries:
  - name: boxes
    kind: toi
    method: sat
    a: {shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [3, 1, 2.5],
        velocity: [0, 0, -4]}
    b: {shape: {type: box, half_extents: [0.25, 0.25, 0.25]}, position: [3.1, 1, 0.5],
        orientation: [0.9238795325112867, 0, 0, 0.3826834323650898]}
  - name: spinning_hull
    kind: toi
    method: sat
    a: {shape: {type: hull, points: [[-0.5, -0.5, -0.5], [0.5, -0.5, -0.5], [-0.5, 0.5, -0.5],
        [0.5, 0.5, -0.5], [-0.5, -0.5, 0.5], [0.5, -0.5, 0.5], [-0.5, 0.5, 0.5], [0.5, 0.5, 0.5]]},
        position: [3, 1, 2.5], velocity: [0, 0, -4], angular_velocity: [0, 0, 3]}
    b: {shape: {type: box, half_extents: [0.25, 0.25, 0.25]}, position: [3.1, 1, 0.5]}
  - name: boxes_by_advancement
    kind: toi
    a: {shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [3, 1, 2.5],
        velocity: [0, 0, -4]}
    b: {shape: {type: box, half_extents: [0.25, 0.25, 0.25]}, position: [3.1, 1, 0.5],
        orientation: [0.9238795325112867, 0, 0, 0.3826834323650898]}
)");
  const Output r = run_query(file);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const auto q = lines_of(r.text);
  ASSERT_EQ(q.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(q[i]["status"], "hit") << i;
    EXPECT_NEAR(q[i]["toi"].get<double>(), 0.3125, i == 0 ? 1e-12 : 1e-9) << i;
    EXPECT_NEAR((vec_of(q[i]["normal"]) - Vec3::UnitZ()).norm(), 0, 1e-6) << i;
  }
  EXPECT_EQ(q[0]["method"], "sat");
  EXPECT_EQ(q[2]["method"], "advancement");
  // A sphere has no faces or edges for the SAT: the field is named.
  const fs::path sphere = write_query_file("satsphere.yaml", R"(queries:
  - kind: toi
    method: sat
    a: {shape: {type: sphere, radius: 1}, velocity: [1, 0, 0]}
    b: {shape: {type: box, half_extents: [1, 1, 1]}, position: [5, 0, 0]}
)");
  const Output s = run_query(sphere);
  EXPECT_EQ(s.exit_code, 1);
  EXPECT_NE(s.text.find("satsphere.yaml:3:"), std::string::npos) << s.text;
  EXPECT_NE(s.text.find("field 'queries[0].method': method sat needs a box or hull on both "
                        "sides, got sphere and box"),
            std::string::npos)
      << s.text;
}

TEST(QueryCommand, UnknownKindAndMisplacedMotionAreNamed) {
  const fs::path kind = write_query_file("badkind.yaml", R"(queries:
  - a: {shape: {type: sphere, radius: 1}}
    b: {shape: {type: sphere, radius: 1}}
  - kind: impact
    a: {shape: {type: sphere, radius: 1}}
    b: {shape: {type: sphere, radius: 1}}
)");
  const Output k = run_query(kind);
  EXPECT_EQ(k.exit_code, 1);
  EXPECT_NE(k.text.find("badkind.yaml:4:"), std::string::npos) << k.text;
  EXPECT_NE(k.text.find("field 'queries[1].kind': expected one of: contact, toi, got 'impact'"),
            std::string::npos)
      << k.text;
  // A velocity only means something for kind toi.
  const fs::path still = write_query_file("still.yaml", R"(queries:
  - a: {shape: {type: sphere, radius: 1}, velocity: [1, 0, 0]}
    b: {shape: {type: sphere, radius: 1}}
)");
  const Output s = run_query(still);
  EXPECT_EQ(s.exit_code, 1);
  EXPECT_NE(s.text.find("still.yaml:2:"), std::string::npos) << s.text;
  EXPECT_NE(s.text.find("velocity"), std::string::npos) << s.text;
}

}  // namespace
}  // namespace tumble::test
