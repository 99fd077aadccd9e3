// The distance of a convex shape to a triangle mesh (shape_distance_bound, which conservative
// advancement calls at every advance) against brute force: GJK, or EPA where they overlap, run on
// every triangle of the mesh (no tree, no pruning), the nearest kept. The function skips triangles
// whose plane is too far to beat the nearest found; it must give the same distance and normal, to
// the bit, for thousands of random shapes (every convex type, fixed seed) above and into a wavy
// terrain.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "collision/ccd/shape_distance.hpp"
#include "collision/narrow_phase/gjk_epa/epa.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/triangle_mesh.hpp"
#include "tests/ccd/ccd_test_support.hpp"

namespace tumble::testing {
namespace {

Shape wavy_terrain(int cells, Real cell) {
  std::vector<Vec3> vertices;
  std::vector<TriangleMesh::Triangle> triangles;
  for (int i = 0; i <= cells; ++i)
    for (int j = 0; j <= cells; ++j)
      vertices.emplace_back((i - 0.5 * cells) * cell, (j - 0.5 * cells) * cell,
                            0.8 * std::sin(0.9 * i) * std::cos(0.7 * j));
  const auto vertex = [&](int i, int j) { return std::int32_t(i * (cells + 1) + j); };
  for (int i = 0; i < cells; ++i) {
    for (int j = 0; j < cells; ++j) {
      triangles.push_back({vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)});
      triangles.push_back({vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
    }
  }
  return Shape::triangle_mesh(std::make_shared<const TriangleMesh>(
      TriangleMesh::build(std::move(vertices), std::move(triangles))));
}

// The nearest triangle within max_distance, the function's own arithmetic on every triangle.
DistanceBound brute_force(const Shape& convex, const Transform& pose_c, const Shape& mesh_shape,
                          const Transform& pose_m, Real max_distance) {
  const TriangleMesh& mesh = *mesh_shape.mesh;
  const ConvexSupport shape_support = ConvexSupport::of(convex, {Vec3::Zero(), pose_c.rotation});
  DistanceBound out;
  out.distance = max_distance;
  out.separating_normal = false;
  bool found = false;
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    std::array<Vec3, 3> corners;
    for (int k = 0; k < 3; ++k)
      corners[std::size_t(k)] = pose_m.apply(mesh.corner(t, k)) - pose_c.translation;
    const ConvexSupport triangle = ConvexSupport::of_points(corners.data(), 3, {});
    const GjkResult g = gjk(shape_support, triangle);
    Real distance = g.distance;
    Vec3 normal = g.normal;
    if (g.status == GjkStatus::intersecting) {
      const EpaResult e = epa(shape_support, triangle, g);
      distance = -e.depth;
      normal = e.normal;
    }
    if (!(distance <= max_distance) || (found && distance >= out.distance))
      continue;
    out.distance = distance;
    out.normal = normal;
    found = true;
  }
  return out;
}

Shape random_convex(std::mt19937_64& rng, int kind) {
  std::uniform_real_distribution<Real> u(0.2, 0.8);
  switch (kind) {
    case 0:
      return Shape::sphere(u(rng));
    case 1:
      return Shape::box(Vec3(u(rng), u(rng), u(rng)));
    case 2:
      return Shape::capsule(u(rng), u(rng));
    case 3:
      return Shape::cylinder(u(rng), u(rng));
    default: {
      std::vector<Vec3> points;
      for (int k = 0; k < 12; ++k)
        points.push_back(random_vector(rng, -0.7, 0.7));
      return Shape::convex_hull(
          std::make_shared<const ConvexHull>(ConvexHull::from_points(std::span(points))));
    }
  }
}

TEST(ConvexMeshDistance, SkippingFarTrianglesChangesNoBit) {
  std::mt19937_64 rng(20261126);
  const Shape terrain = wavy_terrain(16, 0.9);
  const Transform pose_m{Vec3(3, -2, 1), Quat(Eigen::AngleAxis<Real>(0.3, Vec3::UnitZ()))};
  const int cases = scaled(3000);
  int overlapping = 0, apart = 0;
  for (int c = 0; c < cases; ++c) {
    const Shape convex = random_convex(rng, c % 5);
    std::uniform_real_distribution<Real> xy(-6, 6), z(-0.8, 2);
    const Transform pose_c{pose_m.apply(Vec3(xy(rng), xy(rng), z(rng))), random_rotation(rng)};
    const Real max_distance = std::uniform_real_distribution<Real>(0.05, 1.5)(rng);
    const DistanceBound fast = shape_distance_bound(convex, pose_c, terrain, pose_m, max_distance);
    const DistanceBound truth = brute_force(convex, pose_c, terrain, pose_m, max_distance);
    ASSERT_EQ(fast.distance, truth.distance) << "case " << c;
    ASSERT_EQ(fast.normal, truth.normal) << "case " << c;
    overlapping += truth.distance < 0 ? 1 : 0;
    apart += truth.distance > 0 && truth.distance < max_distance ? 1 : 0;
  }
  // Both kinds of answer occur often.
  EXPECT_GT(overlapping, cases / 20);
  EXPECT_GT(apart, cases / 20);
}

}  // namespace
}  // namespace tumble::testing
