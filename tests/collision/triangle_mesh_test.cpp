// TriangleMesh: validation errors, the BVH against a brute-force scan of every triangle, edge
// classification, and mass properties of closed meshes against analytic values and sampling.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "collision/shapes/triangle_mesh.hpp"
#include "tests/collision/mesh_fixtures.hpp"
#include "tests/collision/oracle.hpp"

namespace tumble::testing {
namespace {

void expect_mesh_error(std::vector<Vec3> v, std::vector<TriangleMesh::Triangle> t,
                       const std::string& fragment) {
  try {
    TriangleMesh::build(std::move(v), std::move(t));
    ADD_FAILURE() << "expected an error mentioning '" << fragment << "'";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(TriangleMesh, RejectsBadInputWithClearMessages) {
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
  expect_mesh_error(v, {}, "at least one triangle");
  expect_mesh_error(v, {{0, 1, 7}}, "triangle 0 has vertex index 7 out of range");
  expect_mesh_error(v, {{0, 1, 2}, {0, -1, 2}}, "triangle 1 has vertex index -1");
  expect_mesh_error(v, {{0, 1, 1}}, "triangle 0 repeats a vertex");
  expect_mesh_error(v, {{0, 1, 2}, {0, 1, 3}}, "triangle 1 has zero area");
  std::vector<Vec3> nan = v;
  nan[2].y() = std::numeric_limits<Real>::quiet_NaN();
  expect_mesh_error(nan, {{0, 1, 2}}, "vertex 2 is not finite");
  const std::vector<Vec3> fan = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  expect_mesh_error(fan, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}, "shared by 3 triangles");
}

TEST(TriangleMesh, BvhQueryMatchesBruteForce) {
  Rng rng(301);
  // A bumpy 30 x 30 grid plus random triangles scattered above it.
  TriangleMesh grid = grid_mesh(30, 0.2);
  std::vector<Vec3> vertices = grid.vertices();
  std::vector<TriangleMesh::Triangle> triangles = grid.triangles();
  for (Vec3& v : vertices)
    v.z() = 0.1 * std::sin(3 * v.x()) * std::cos(2 * v.y());
  for (int i = 0; i < 400; ++i) {
    const Vec3 c = random_vector_in_box(rng, 3);
    const std::int32_t base = std::int32_t(vertices.size());
    for (int k = 0; k < 3; ++k)
      vertices.push_back(c + random_vector_in_box(rng, 0.3));
    triangles.push_back({base, base + 1, base + 2});
  }
  const TriangleMesh mesh = TriangleMesh::build(vertices, triangles);
  // Every triangle is in exactly one leaf.
  std::vector<int> seen(mesh.triangle_count(), 0);
  Aabb everything;
  everything.grow(Vec3::Constant(-100));
  everything.grow(Vec3::Constant(100));
  mesh.for_each_overlapping(everything, [&](int t) { ++seen[t]; });
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; }));

  const int cases = scaled(5000);
  long long visited = 0;
  long long matched = 0;
  for (int c = 0; c < cases; ++c) {
    const Vec3 centre = random_vector_in_box(rng, 3.5);
    const Vec3 half = Vec3(uniform(rng, 0, 0.6), uniform(rng, 0, 0.6), uniform(rng, 0, 0.6));
    const Aabb box{centre - half, centre + half};
    std::vector<int> from_bvh;
    mesh.for_each_overlapping(box, [&](int t) { from_bvh.push_back(t); });
    std::vector<int> brute;
    for (int t = 0; t < mesh.triangle_count(); ++t) {
      Aabb tb;
      for (int k = 0; k < 3; ++k)
        tb.grow(mesh.corner(t, k));
      if (tb.overlaps(box))
        brute.push_back(t);
    }
    std::sort(from_bvh.begin(), from_bvh.end());
    ASSERT_EQ(from_bvh, brute) << "case " << c;
    visited += long(from_bvh.size());
    matched += long(brute.size());
  }
  EXPECT_GT(matched, 0);
  EXPECT_EQ(visited, matched);
}

TEST(TriangleMesh, GridEdgesAreFlatOrBoundary) {
  const TriangleMesh grid = grid_mesh(20, 0.5);
  ASSERT_EQ(grid.triangle_count(), 800);
  EXPECT_FALSE(grid.is_closed());
  EXPECT_EQ(grid.volume(), 0);
  int boundary = 0;
  for (int t = 0; t < grid.triangle_count(); ++t) {
    EXPECT_NEAR(grid.normal(t).z(), 1, 1e-15);
    for (int e = 0; e < 3; ++e) {
      const EdgeKind k = grid.edge_kind(t, e);
      EXPECT_TRUE(k == EdgeKind::flat || k == EdgeKind::boundary);
      boundary += k == EdgeKind::boundary;
    }
  }
  EXPECT_EQ(boundary, 4 * 20);
}

TEST(TriangleMesh, BoxEdgesAreConvexAndTentEdgesConcave) {
  const TriangleMesh box = box_mesh({1, 2, 3});
  int convex = 0;
  int flat = 0;
  for (int t = 0; t < box.triangle_count(); ++t)
    for (int e = 0; e < 3; ++e) {
      convex += box.edge_kind(t, e) == EdgeKind::convex;
      flat += box.edge_kind(t, e) == EdgeKind::flat;
    }
  EXPECT_EQ(convex, 24);  // 12 cube edges, seen from both sides
  EXPECT_EQ(flat, 12);    // the 6 face diagonals
  // A valley: two triangles meeting at the x axis and rising to either side.
  const TriangleMesh valley =
      TriangleMesh::build({{-1, 0, 0}, {1, 0, 0}, {0, -1, 1}, {0, 1, 1}}, {{0, 1, 3}, {1, 0, 2}});
  EXPECT_EQ(valley.edge_kind(0, 0), EdgeKind::concave);
  EXPECT_EQ(valley.edge_kind(1, 0), EdgeKind::concave);
  const TriangleMesh ridge =
      TriangleMesh::build({{-1, 0, 0}, {1, 0, 0}, {0, -1, -1}, {0, 1, -1}}, {{0, 1, 3}, {1, 0, 2}});
  EXPECT_EQ(ridge.edge_kind(0, 0), EdgeKind::convex);
}

TEST(TriangleMesh, ClosedBoxMassPropertiesMatchAnalytic) {
  Rng rng(302);
  for (int c = 0; c < 50; ++c) {
    const Vec3 h(uniform(rng, 0.1, 2), uniform(rng, 0.1, 2), uniform(rng, 0.1, 2));
    const Transform pose{random_vector_in_box(rng, 5), random_rotation(rng)};
    const TriangleMesh mesh = box_mesh(h, pose);
    ASSERT_TRUE(mesh.is_closed());
    EXPECT_NEAR(mesh.volume(), 8 * h.prod(), 1e-11 * (1 + 8 * h.prod()));
    EXPECT_LT((mesh.centroid() - pose.translation).norm(), 1e-11 * 10);
    const Mat3 r = pose.rotation.toRotationMatrix();
    const Mat3 expected = r * unit_inertia(Shape::box(h)) * r.transpose();
    EXPECT_LT((mesh.unit_inertia() - expected).norm(), 1e-9 * (1 + expected.norm()));
  }
}

TEST(TriangleMesh, TetrahedronMassPropertiesMatchSampling) {
  // Volume and centroid are closed forms; the inertia is checked against Monte Carlo sampling
  // of the solid (uniform barycentric coordinates), an independent route.
  Rng rng(303);
  const std::array<Vec3, 4> p = {Vec3(0.2, -0.1, 0.3), Vec3(1.5, 0.1, 0.2), Vec3(0.4, 1.3, -0.1),
                                 Vec3(0.5, 0.4, 1.2)};
  // Orientation: faces counter-clockwise seen from outside.
  const bool positive = (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) > 0;
  std::vector<TriangleMesh::Triangle> faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  if (!positive)
    for (auto& f : faces)
      std::swap(f[1], f[2]);
  const TriangleMesh mesh = TriangleMesh::build({p.begin(), p.end()}, faces);
  ASSERT_TRUE(mesh.is_closed());
  const Real volume = std::abs((p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0])) / 6;
  EXPECT_NEAR(mesh.volume(), volume, 1e-14);
  EXPECT_LT((mesh.centroid() - (p[0] + p[1] + p[2] + p[3]) / 4).norm(), 1e-14);
  const int samples = scaled(400000);
  Mat3 sampled = Mat3::Zero();
  for (int s = 0; s < samples; ++s) {
    // Sorted uniforms give a uniform point of the simplex.
    std::array<Real, 3> u = {uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1)};
    std::sort(u.begin(), u.end());
    const Vec3 x = p[0] * u[0] + p[1] * (u[1] - u[0]) + p[2] * (u[2] - u[1]) + p[3] * (1 - u[2]);
    const Vec3 d = x - mesh.centroid();
    sampled += d.squaredNorm() * Mat3::Identity() - d * d.transpose();
  }
  sampled /= samples;
  EXPECT_LT((mesh.unit_inertia() - sampled).norm(), 0.02 * sampled.norm());
  // Flipping every face gives an inside-out mesh: no volume.
  for (auto& f : faces)
    std::swap(f[1], f[2]);
  const TriangleMesh inside_out = TriangleMesh::build({p.begin(), p.end()}, faces);
  EXPECT_FALSE(inside_out.is_closed());
  EXPECT_EQ(inside_out.volume(), 0);
}

TEST(TriangleMesh, WorldAabbHoldsEveryVertex) {
  Rng rng(304);
  const TriangleMesh mesh = box_mesh({0.5, 1, 2}, {Vec3(1, 2, 3), random_rotation(rng)});
  for (int c = 0; c < 100; ++c) {
    const Transform pose{random_vector_in_box(rng, 10), random_rotation(rng)};
    const Aabb box = world_aabb(mesh_shape(mesh), pose);
    for (const Vec3& v : mesh.vertices())
      EXPECT_TRUE(box.inflated(1e-12).contains(pose.apply(v)));
  }
}

}  // namespace
}  // namespace tumble::testing
