// Signed distance fields in YAML (scenes/sdf_section.hpp): the documented forms read to the
// trees they describe (compared by value with trees built in code), and every mistake named by
// line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include <unistd.h>

#include "collision/sdf/sdf_tree.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "scenes/scene_loader.hpp"
#include "scenes/sdf_section.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

void expect_same_field(const SdfTree& a, const SdfTree& b) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<Real> u(-2, 2);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const sdf::Sample x = a.sample(p), y = b.sample(p);
    ASSERT_EQ(x.distance, y.distance);
    ASSERT_EQ(x.gradient, y.gradient);
  }
}

TEST(SdfYaml, TheDocumentedFormsReadToTheirTrees) {
  expect_same_field(
      SdfTree(load_sdf_string("{torus: {major_radius: 1.0, minor_radius: 0.25}}", "t")),
      SdfTree(SdfNode::torus(1.0, 0.25)));
  expect_same_field(
      SdfTree(load_sdf_string("{difference: [{box: {half_extents: [1, 1, 0.5]}},\n"
                              "              {sphere: {radius: 0.9}, position: [0, 0, 0.6]}]}",
                              "bowl")),
      SdfTree(
          SdfNode::combine(SdfKind::difference_of,
                           {SdfNode::box(Vec3(1, 1, 0.5)),
                            SdfNode::sphere(0.9).placed({Vec3(0, 0, 0.6), Quat::Identity()})})));
  expect_same_field(
      SdfTree(load_sdf_string("{smooth_union: {k: 8, of: [{sphere: {radius: 0.5}},\n"
                              "  {capsule: {radius: 0.2, half_length: 0.6}}]}}",
                              "blob")),
      SdfTree(SdfNode::combine(SdfKind::smooth_union_of,
                               {SdfNode::sphere(0.5), SdfNode::capsule(0.2, 0.6)}, 8)));
  const Quat turn(std::sqrt(0.5), std::sqrt(0.5), 0, 0);
  expect_same_field(
      SdfTree(load_sdf_string(
          "intersection:\n  - {cylinder: {radius: 1, half_length: 2}, orientation: "
          "[0.7071067811865476, "
          "0.7071067811865476, 0, 0]}\n  - {plane: {}, position: [0, 0, 0.5]}\n"
          "  - union: [{sphere: {radius: 1.5}}, {box: {half_extents: [2, 0.1, 0.1]}}]\n",
          "cut")),
      SdfTree(SdfNode::combine(
          SdfKind::intersection_of,
          {SdfNode::cylinder(1, 2).placed({Vec3::Zero(), turn.normalized()}),
           SdfNode::plane().placed({Vec3(0, 0, 0.5), Quat::Identity()}),
           SdfNode::combine(SdfKind::union_of,
                            {SdfNode::sphere(1.5), SdfNode::box(Vec3(2, 0.1, 0.1))})})));
}

// `yaml`, read as the file `source`, is refused with a message holding `where` and `what`.
void expect_refused(const std::string& yaml, const std::string& source, const std::string& where,
                    const std::string& what) {
  try {
    load_sdf_string(yaml, source);
    ADD_FAILURE() << "accepted: " << yaml;
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(SdfYaml, MistakesNameTheLineAndField) {
  const auto expect = [](const std::string& yaml, const std::string& where,
                         const std::string& what) { expect_refused(yaml, "s.yaml", where, what); };
  expect("{sphere: {radius: -1}}", "field 'sdf.sphere.radius'", "got -1");
  expect("union:\n  - {sphere: {radius: 2e6}}\n  - {plane: {}}\n",
         "s.yaml:2:", "sdf.union[0].sphere.radius");
  expect("{torus: {major_radius: 1, minor_radius: 1}}", "sdf.torus.minor_radius", "ring torus");
  expect("{spher: {radius: 1}}", "field 'sdf.spher'", "did you mean 'sphere'");
  expect("{sphere: {radius: 1}, box: {half_extents: [1, 1, 1]}}", "sdf.box", "one kind");
  expect("{position: [0, 0, 1]}", "field 'sdf'", "needs a kind");
  expect("union:\n  - {sphere: {radius: 1}}\n", "s.yaml:2:3: field 'sdf.union'", "at least two");
  expect("difference:\n  - {sphere: {radius: 1}}\n  - {box: {half_extents: [1, 0, 1]}}\n",
         "s.yaml:3:", "sdf.difference[1].box.half_extents[1]");
  expect("{smooth_union: {k: 0, of: [{sphere: {radius: 1}}, {sphere: {radius: 2}}]}}",
         "sdf.smooth_union.k", "greater than 0");
  expect("{sphere: {radius: 1}, orientation: [1, 1, 0, 0]}", "sdf.orientation", "unit quaternion");
  std::string deep = "{sphere: {radius: 1}}";
  for (int i = 0; i < 70; ++i)
    deep = "{union: [" + deep + ", {sphere: {radius: 1}}]}";
  expect(deep, "s.yaml", "deeper than 64");
}

// Grid and network nodes read their files relative to the source's folder; the test names the
// sources as files in the repository so that relative paths resolve there.
TEST(SdfYaml, GridAndNeuralNodesReadTheirFiles) {
  const std::string source = std::string(TUMBLE_SOURCE_DIR) + "/scenes/sdf/here.yaml";
  const std::string data = std::string(TUMBLE_SOURCE_DIR) + "/tests/data/here.yaml";
  const SdfTree grid(
      load_sdf_string("{grid: {file: sdf/cube.obj, cell: 0.05, interpolation: trilinear}}", data));
  // The unit cube: at grid nodes within the exact band (three cells of a face), 0.1 m in and out.
  EXPECT_NEAR(grid.distance(Vec3(0.4, 0, 0)), -0.1, 1e-9);
  EXPECT_NEAR(grid.distance(Vec3(0, 0.6, 0)), 0.1, 1e-9);
  EXPECT_LT(grid.distance(Vec3(0, 0, 0)), -0.4);  // the centre, swept from the band
  // Refined 5 times near the surface: exact at the fine nodes within its band (1 cm cells, 3 a
  // side). Beside an edge the distance is round, which the 5 cm cells alone interpolate 5 mm off
  // at (0.51, 0.52, 0).
  const SdfNode refined_node = load_sdf_string(
      "{grid: {file: sdf/cube.obj, cell: 0.05, interpolation: trilinear, refine: 5}}", data);
  ASSERT_NE(refined_node.grid, nullptr);
  ASSERT_NE(refined_node.grid->refinement(), nullptr);
  EXPECT_EQ(refined_node.grid->refinement()->refine(), 5);
  const SdfTree refined(refined_node);
  EXPECT_NEAR(refined.distance(Vec3(0.51, 0.52, 0)), std::hypot(0.01, 0.02), 1e-9);
  EXPECT_GT(std::abs(grid.distance(Vec3(0.51, 0.52, 0)) - std::hypot(0.01, 0.02)), 1e-3);
  EXPECT_NEAR(refined.distance(Vec3(0.48, 0.13, -0.21)), -0.02, 1e-9);
  const SdfTree net(load_sdf_string("{neural: {file: neural/torus_sdf.json}}", data));
  // The committed fit: a torus of ring 0.6 m and tube 0.2 m, trained near its surface
  // (tests/data/neural/README.md: 5.7 mm at worst there); deep inside and far out, only signs.
  EXPECT_NEAR(net.distance(Vec3(0.8, 0, 0)), 0, 6e-3);
  EXPECT_NEAR(net.distance(Vec3(0, 0.4, 0)), 0, 6e-3);
  EXPECT_LT(net.distance(Vec3(0.6, 0, 0)), -0.15);
  EXPECT_GT(net.distance(Vec3(0, 0, 0)), 0.3);
  const auto expect = [&](const std::string& yaml, const std::string& where,
                          const std::string& what) { expect_refused(yaml, source, where, what); };
  expect("{grid: {file: meshes/bowl_closed.obj}}", "sdf.grid.cell", "needs 'cell'");
  expect("{grid: {file: meshes/bowl_closed.obj, cell: 0}}", "sdf.grid.cell", "got 0");
  expect("{grid: {file: meshes/bowl_closed.obj, cell: 0.1, interpolation: cubic}}",
         "sdf.grid.interpolation", "tricubic or trilinear");
  expect("{grid: {file: meshes/bowl_inner.obj, cell: 0.1}}", "sdf.grid.file", "not closed");
  expect("{grid: {file: meshes/missing.obj, cell: 0.1}}", "sdf.grid.file", "missing.obj");
  expect("{grid: {file: part.vdb, cell: 0.1}}", "sdf.grid.cell", "own voxel size");
  expect("{grid: {file: meshes/bowl_closed.obj, cell: 0.1, builder: vdb}}", "sdf.grid.builder",
         "tumble or openvdb");
  expect("{grid: {file: meshes/bowl_closed.obj, cell: 0.1, band: 3}}", "sdf.grid.band",
         "builder: openvdb");
  expect("{grid: {file: meshes/bowl_closed.obj, cell: 0.1, builder: openvdb, band: 100}}",
         "sdf.grid.band", "1 to 64");
  expect("{grid: {file: meshes/bowl_closed.obj, cell: 0.1, refine: 17}}", "sdf.grid.refine",
         "1 to 16");
  expect("{grid: {file: meshes/bowl_closed.obj, cell: 0.1, refine: 2.5}}", "sdf.grid.refine",
         "whole");
  expect("{grid: {file: meshes/bowl_closed.obj, cell: 0.1, builder: openvdb, refine: 2}}",
         "sdf.grid.refine", "builder: tumble");
  expect("{neural: {file: nothing.json}}", "sdf.neural.file", "nothing.json");
}

TEST(SdfYaml, AMorphReadsBothFieldsAndItsTimes) {
  const SdfNode n = load_sdf_string(
      "{morph: {from: {sphere: {radius: 0.5}}, to: {box: {half_extents: [0.4, 0.3, 0.2]}, "
      "position: [0, 0, 0.3]}, start: 1, duration: 2}}",
      "s.yaml");
  ASSERT_EQ(n.kind, SdfKind::morph);
  ASSERT_EQ(n.children.size(), 2u);
  EXPECT_EQ(n.children[1].pose.translation, Vec3(0, 0, 0.3));
  const SdfTree tree(n);
  EXPECT_EQ(tree.changes_from(), 1);
  EXPECT_EQ(tree.changes_until(), 3);
  EXPECT_EQ(load_sdf_string("{morph: {from: {sphere: {radius: 1}}, to: {sphere: {radius: 2}}, "
                            "duration: 1}}",
                            "s.yaml")
                .start,
            0);
  expect_refused("{morph: {from: {sphere: {radius: 1}}, duration: 1}}", "s.yaml", "sdf.morph.to",
                 "missing");
  expect_refused("{morph: {from: {sphere: {radius: 1}}, to: {sphere: {radius: 2}}}}", "s.yaml",
                 "sdf.morph.duration", "missing");
  expect_refused("{morph: {from: {sphere: {radius: 1}}, to: {sphere: {radius: 2}}, duration: 0}}",
                 "s.yaml", "sdf.morph.duration", "greater than 0");
  expect_refused("{morph: {from: {sphere: {radius: 1}}, to: {sphere: {radius: -2}}, duration: 1}}",
                 "s.yaml", "sdf.morph.to.sphere.radius", "");
  // A morph is an obstacle: a dynamic body of one is refused, naming the body's shape.
  const std::string body =
      "world: {dt: 0.01}\nbodies:\n  - name: lump\n    shape: {type: sdf, sdf: {morph: {from: "
      "{sphere: {radius: 1}}, to: {sphere: {radius: 2}}, duration: 1}}}\n    mass: 1\n";
  try {
    (void)load_scene_string(body, "morph.yaml");
    ADD_FAILURE() << "a dynamic morph was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[0].shape"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("static or kinematic"), std::string::npos) << e.what();
  }
  std::string kinematic = body;
  kinematic.replace(kinematic.find("    mass: 1\n"), 12, "    kinematic: true\n");
  EXPECT_TRUE(load_scene_string(kinematic, "morph.yaml").bodies[0].kinematic);
}

// A shape's resolution: the cells of its mass grid along the longest side (48 unless given),
// which set the spacing of its surface points; outside 8 to 96 it is refused by line and field.
TEST(SdfYaml, AShapesResolutionSetsItsGrid) {
  const auto scene = [](const std::string& resolution) {
    return "world: {dt: 0.01}\nbodies:\n  - name: ring\n    shape: {type: sdf, sdf: {torus: "
           "{major_radius: 0.4, minor_radius: 0.1}}" +
           resolution + "}\n    density: 500\n";
  };
  const Scene given = load_scene_string(scene(", resolution: 24"), "ring.yaml");
  const Scene plain = load_scene_string(scene(""), "ring.yaml");
  const SdfShape& coarse = *given.bodies[0].shape.sdf;
  const SdfShape& fine = *plain.bodies[0].shape.sdf;
  // The torus's bounds are 1.0 m along x and y.
  EXPECT_NEAR(coarse.cell_size(), 1.0 / 24, 1e-12);
  EXPECT_NEAR(fine.cell_size(), 1.0 / SdfShape::kMassCells, 1e-12);
  // Points about one a cell of surface: a quarter as many at half the resolution.
  const Real ratio = Real(fine.surface_point_count()) / Real(coarse.surface_point_count());
  EXPECT_GT(ratio, 3.5);
  EXPECT_LT(ratio, 4.5);
  for (const char* bad : {", resolution: 7", ", resolution: 97", ", resolution: 24.5"}) {
    try {
      (void)load_scene_string(scene(bad), "ring.yaml");
      ADD_FAILURE() << bad << " was accepted";
    } catch (const SceneError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("ring.yaml:4:"), std::string::npos) << m;
      EXPECT_NE(m.find("bodies[0].shape.resolution"), std::string::npos) << m;
      EXPECT_NE(m.find("8 to 96"), std::string::npos) << m;
    }
  }
}

// OpenVDB: a level set built from the same cube as the grid above, written to a .vdb file and
// read back by a scene; without OpenVDB both are refused with the reason.
TEST(SdfYaml, OpenVdbLevelSetsFromMeshesAndFiles) {
  const std::string source = std::string(TUMBLE_SOURCE_DIR) + "/tests/data/here.yaml";
  const std::string built =
      "{grid: {file: sdf/cube.obj, cell: 0.05, builder: openvdb, band: 4, "
      "interpolation: trilinear}}";
  if (!VdbLevelSet::available()) {
    expect_refused(built, source, "sdf.grid.file", "needs a build with OpenVDB");
    expect_refused("{grid: {file: part.vdb}}", source, "sdf.grid.file",
                   "needs a build with OpenVDB");
    GTEST_SKIP() << "this build has no OpenVDB";
  }
  const SdfNode node = load_sdf_string(built, source);
  ASSERT_EQ(node.kind, SdfKind::level_set);
  const SdfTree tree(node);
  // The unit cube at voxel centres 0.1 m in and out of a face: its exact distance.
  EXPECT_NEAR(tree.distance(Vec3(0.4, 0, 0)), -0.1, 1e-6);
  EXPECT_NEAR(tree.distance(Vec3(0, 0.6, 0)), 0.1, 1e-6);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("tumble_sdf_yaml_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  node.level_set->save(dir / "cube.vdb", true);
  const std::string in_dir = (dir / "scene.yaml").string();
  const SdfTree read(load_sdf_string("{grid: {file: cube.vdb, interpolation: trilinear}}", in_dir));
  for (const Vec3& p : {Vec3(0.4, 0, 0), Vec3(0, 0.6, 0), Vec3(0.31, -0.27, 0.45)})
    EXPECT_NEAR(read.distance(p), tree.distance(p), 1e-6) << p.transpose();
  expect_refused("{grid: {file: missing.vdb}}", in_dir, "sdf.grid.file", "missing.vdb");
  expect_refused("{grid: {file: cube.vdb, builder: openvdb}}", in_dir, "sdf.grid.builder",
                 "read as it is");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tumble
