// scenes/mesh_slide.yaml: a box sliding over an 800-triangle mesh floor moves as it does on a
// plane floor (same scene with the floor swapped for a plane): no vertical velocity bumps at
// the triangle edges, the same stopping point.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "collision/shapes/triangle_mesh.hpp"
#include "tests/physics/scene_fixture.hpp"

namespace tumble::test {
namespace {

struct Track {
  Real max_vertical_speed = 0;
  Real max_height_change = 0;
  std::vector<Vec3> positions;
};

Track slide(std::shared_ptr<const Scene> scene) {
  Simulation world(scene);
  const int box = body_index(*scene, "box");
  const Real start_height = world.state().bodies[box].position.z();
  Track t;
  const int steps = int(std::ceil(scene->world.duration / scene->world.dt));
  for (int i = 0; i < steps; ++i) {
    world.step();
    const BodyState& b = world.state().bodies[box];
    t.max_vertical_speed = std::max(t.max_vertical_speed, std::abs(b.velocity.z()));
    t.max_height_change = std::max(t.max_height_change, std::abs(b.position.z() - start_height));
    t.positions.push_back(b.position);
  }
  return t;
}

TEST(MeshSlide, BoxSlidesOverMeshFloorAsOverAPlane) {
  const auto on_mesh = shipped_scene("mesh_slide.yaml");
  ASSERT_EQ(on_mesh->bodies[body_index(*on_mesh, "floor")].shape.mesh->triangle_count(), 800);
  auto plane_scene = std::make_shared<Scene>(*on_mesh);
  plane_scene->bodies[body_index(*plane_scene, "floor")].shape = Shape::plane();
  const Track mesh = slide(on_mesh);
  const Track plane = slide(plane_scene);
  Real max_gap = 0;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    max_gap = std::max(max_gap, (mesh.positions[i] - plane.positions[i]).norm());
  std::printf(
      "[ stats    ] mesh floor: max |vz| %.3g m/s, max height change %.3g m; plane floor: "
      "max |vz| %.3g m/s, %.3g m; largest position gap mesh vs plane %.3g m\n",
      mesh.max_vertical_speed, mesh.max_height_change, plane.max_vertical_speed,
      plane.max_height_change, max_gap);
  // Control: the same triangles without shared vertices (every edge a boundary, so no
  // internal-edge rules). Printed, not asserted: it measures what the rules are worth.
  {
    const TriangleMesh& grid = *on_mesh->bodies[body_index(*on_mesh, "floor")].shape.mesh;
    std::vector<Vec3> v;
    std::vector<TriangleMesh::Triangle> t;
    for (int i = 0; i < grid.triangle_count(); ++i) {
      const std::int32_t base = std::int32_t(v.size());
      for (int k = 0; k < 3; ++k)
        v.push_back(grid.corner(i, k));
      t.push_back({base, base + 1, base + 2});
    }
    auto loose_scene = std::make_shared<Scene>(*on_mesh);
    loose_scene->bodies[body_index(*loose_scene, "floor")].shape =
        Shape::triangle_mesh(std::make_shared<const TriangleMesh>(TriangleMesh::build(v, t)));
    const Track loose = slide(loose_scene);
    Real loose_gap = 0;
    for (std::size_t i = 0; i < loose.positions.size(); ++i)
      loose_gap = std::max(loose_gap, (loose.positions[i] - plane.positions[i]).norm());
    std::printf(
        "[ stats    ] without internal-edge rules: max |vz| %.3g m/s, max height change "
        "%.3g m, largest position gap vs plane %.3g m\n",
        loose.max_vertical_speed, loose.max_height_change, loose_gap);
  }
  // The box crosses dozens of triangle edges; none may kick it up more than the plane does.
  EXPECT_LE(mesh.max_vertical_speed, plane.max_vertical_speed + 1e-6);
  EXPECT_LE(mesh.max_height_change, plane.max_height_change + 1e-6);
  EXPECT_LT(max_gap, 1e-3);
  // It really slid across many cells: more than a metre.
  EXPECT_GT((mesh.positions.back() - on_mesh->bodies[body_index(*on_mesh, "box")].position).norm(),
            1.0);
}

}  // namespace
}  // namespace tumble::test
