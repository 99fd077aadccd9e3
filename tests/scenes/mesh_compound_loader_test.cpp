// Scene loader: mesh (inline and OBJ) and compound shapes arrive as written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/triangle_mesh.hpp"
#include "scenes/query_file.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble {
namespace {

TEST(SceneLoaderMesh, InlineMeshIsStaticWithItsTriangles) {
  const Scene s = load_scene_string(R"(
bodies:
  - name: ground
    static: true
    shape:
      type: mesh
      vertices: [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
      triangles: [[0, 1, 2], [0, 2, 3]]
  - {name: ball, shape: {type: sphere, radius: 0.1}, position: [0.5, 0.5, 0.1]}
)",
                                    "inline.yaml");
  const Shape& m = s.bodies[0].shape;
  ASSERT_EQ(m.type, ShapeType::mesh);
  EXPECT_EQ(m.mesh->triangle_count(), 2);
  EXPECT_FALSE(m.mesh->is_closed());
  EXPECT_TRUE(s.bodies[0].is_static);
}

TEST(SceneLoaderMesh, ObjFileIsReadRelativeToTheScene) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("tumble_mesh_loader_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "meshes");
  {
    // A 2 m cube written with quads: tinyobjloader splits each into two triangles.
    std::ofstream obj(dir / "meshes" / "cube.obj");
    obj << "# cube\n";
    for (int v = 0; v < 8; ++v)
      obj << "v " << ((v & 1) ? 1 : -1) << ' ' << ((v & 2) ? 1 : -1) << ' ' << ((v & 4) ? 1 : -1)
          << "\n";
    obj << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    std::ofstream scene(dir / "scene.yaml");
    scene << "bodies:\n  - name: block\n    static: true\n"
             "    shape: {type: mesh, file: meshes/cube.obj}\n";
  }
  const Scene s = load_scene_file(dir / "scene.yaml");
  const TriangleMesh& m = *s.bodies[0].shape.mesh;
  EXPECT_EQ(m.triangle_count(), 12);
  ASSERT_TRUE(m.is_closed());
  EXPECT_NEAR(m.volume(), 8, 1e-12);
  std::filesystem::remove_all(dir);
}

TEST(SceneLoaderCompound, MassFromDensityAndPartsStayWhereWritten) {
  const Scene s = load_scene_string(R"(
bodies:
  - name: dumbbell
    position: [10, 0, 0]
    orientation: [0.7071067811865476, 0, 0, 0.7071067811865476]
    density: 1000
    shape:
      type: compound
      parts:
        - {shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [0, 0, 0]}
        - {shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [2, 0, 0]}
)",
                                    "compound.yaml");
  const BodyDesc& b = s.bodies[0];
  EXPECT_NEAR(b.mass, 1000 * 2.0, 1e-9);
  // Centre of mass halfway between the parts: (1, 0, 0) in the body frame, which the
  // orientation (90 degrees about z) turns into (0, 1, 0).
  EXPECT_LT((b.position - Vec3(10, 1, 0)).norm(), 1e-12);
  const auto& parts = b.shape.compound->parts();
  EXPECT_LT((parts[0].pose.translation - Vec3(-1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((parts[1].pose.translation - Vec3(1, 0, 0)).norm(), 1e-15);
  // Two unit cubes 2 m apart: I_xx = m/6, I_yy = I_zz = m/6 + m * 1^2.
  EXPECT_NEAR(b.inertia(0, 0), 2000.0 / 6, 1e-9);
  EXPECT_NEAR(b.inertia(1, 1), 2000.0 / 6 + 2000.0, 1e-9);
}

TEST(QueryFile, ReadsQueriesAndNamesBadFields) {
  const auto q = load_query_string(R"(
queries:
  - name: first
    margin: 2
    a: {shape: {type: sphere, radius: 0.5}, position: [0, 0, 1]}
    b: {shape: {type: plane}}
  - a: {shape: {type: box, half_extents: [1, 1, 1]}}
    b: {shape: {type: capsule, radius: 0.1, half_length: 0.3}, position: [0, 0, 3]}
)",
                                   "q.yaml");
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0].name, "first");
  EXPECT_EQ(q[0].margin, 2);
  EXPECT_EQ(q[1].name, "query1");
  EXPECT_EQ(q[1].b.type, ShapeType::capsule);
  try {
    load_query_string(
        "queries:\n  - name: x\n    a: {shape: {type: sphere, radius: -1}}\n"
        "    b: {shape: {type: plane}}\n",
        "bad.yaml");
    ADD_FAILURE() << "expected an error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.line, 3);
    EXPECT_EQ(e.field, "queries[0].a.shape.radius");
  }
}

TEST(QueryFile, EmptyAndBrokenFilesAreNamedAsQueryFiles) {
  try {
    load_query_string("", "empty.yaml");
    ADD_FAILURE() << "an empty query file was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field, "queries");  // not 'bodies': it is a query file
  }
  try {
    load_query_string("queries: [\n", "broken.yaml");
    ADD_FAILURE() << "a broken query file was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file, "broken.yaml");
    EXPECT_EQ(e.line, 2);
    EXPECT_NE(std::string(e.what()).find("broken.yaml:2:"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tumble
