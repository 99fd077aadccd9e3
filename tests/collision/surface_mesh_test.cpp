// Shape meshes against the shapes they draw: enclosed volume against the analytic volume,
// outward winding, vertices on the surface. The generic support-map path is checked on every
// shape that has a dedicated mesh, so it is known to work before a new shape relies on it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <random>
#include <stdexcept>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/shape.hpp"
#include "collision/shapes/surface_mesh.hpp"
#include "collision/shapes/triangle_mesh.hpp"
#include "tests/property_scale.hpp"

namespace tumble {
namespace {

// Every triangle faces away from the centre of mass (true for convex shapes centred at the
// origin) and every normal is unit and on the same side as its triangle's face.
void expect_outward(const SurfaceMesh& mesh, const char* what) {
  ASSERT_EQ(mesh.positions.size(), mesh.normals.size()) << what;
  ASSERT_EQ(mesh.indices.size() % 3, 0u) << what;
  ASSERT_GT(mesh.triangle_count(), 0) << what;
  for (const Vec3& n : mesh.normals)
    ASSERT_NEAR(n.norm(), 1.0, 1e-9) << what;
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    const Vec3& a = mesh.positions[mesh.indices[i]];
    const Vec3& b = mesh.positions[mesh.indices[i + 1]];
    const Vec3& c = mesh.positions[mesh.indices[i + 2]];
    const Vec3 face = (b - a).cross(c - a);
    if (face.norm() < 1e-12)
      continue;  // pole triangles of a revolved mesh
    ASSERT_GE(face.dot(a + b + c), -1e-12) << what << ": triangle " << i / 3 << " faces inwards";
    for (int k = 0; k < 3; ++k)
      ASSERT_GT(mesh.normals[mesh.indices[i + k]].dot(face), 0) << what << ": triangle " << i / 3;
  }
}

// An inscribed polyhedron holds a little less than the shape; 3% is far more than 32 segments
// or 3 icosphere subdivisions lose, far less than a missing or inverted patch.
void expect_volume(const SurfaceMesh& mesh, const Shape& shape, const char* what) {
  const Real v = enclosed_volume(mesh);
  EXPECT_LE(v, volume(shape) * (1 + 1e-9)) << what;
  EXPECT_GE(v, volume(shape) * 0.97) << what;
}

TEST(SurfaceMesh, SphereIsClosedOutwardAndOnTheSurface) {
  const Shape s = Shape::sphere(0.7);
  const SurfaceMesh m = tessellate(s, {});
  expect_outward(m, "sphere");
  expect_volume(m, s, "sphere");
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_NEAR(m.positions[i].norm(), 0.7, 1e-12);
    EXPECT_NEAR((m.positions[i] - 0.7 * m.normals[i]).norm(), 0, 1e-12);
  }
}

TEST(SurfaceMesh, BoxIsExact) {
  const Shape s = Shape::box(Vec3(0.5, 0.2, 1.5));
  const SurfaceMesh m = tessellate(s, {});
  expect_outward(m, "box");
  EXPECT_EQ(m.triangle_count(), 12);
  EXPECT_NEAR(enclosed_volume(m), volume(s), 1e-12);
  for (const Vec3& p : m.positions)
    EXPECT_TRUE(((p.cwiseAbs() - s.half_extents).cwiseAbs().array() < 1e-15).all()) << p;
}

TEST(SurfaceMesh, CapsuleCoreRunsAlongZ) {
  const Shape s = Shape::capsule(0.3, 0.8);
  const SurfaceMesh m = tessellate(s, {});
  expect_outward(m, "capsule");
  expect_volume(m, s, "capsule");
  Real top = -1;
  for (const Vec3& p : m.positions) {
    // Distance to the core segment is the radius.
    const Vec3 core(0, 0, std::clamp(p.z(), Real(-0.8), Real(0.8)));
    EXPECT_NEAR((p - core).norm(), 0.3, 1e-12);
    top = std::max(top, p.z());
  }
  EXPECT_NEAR(top, 1.1, 1e-12);
}

TEST(SurfaceMesh, PlaneHasNoMesh) {
  EXPECT_THROW(tessellate(Shape::plane(), {}), std::invalid_argument);
  EXPECT_THROW(tessellate_convex_support(Shape::plane(), {}), std::invalid_argument);
}

TEST(SurfaceMesh, IcosphereIsAClosedUnitSphere) {
  std::vector<Vec3> d;
  std::vector<std::uint32_t> t;
  icosphere(2, d, t);
  EXPECT_EQ(d.size(), 162u);  // 10 * 4^n + 2
  EXPECT_EQ(t.size(), 3u * 320);
  SurfaceMesh m;
  m.positions = d;
  m.normals = d;
  m.indices = t;
  expect_outward(m, "icosphere");
}

// The generic path on random spheres, boxes and capsules: every vertex is a support point (on
// the surface), the mesh winds outwards and holds the shape's volume. A box's support points
// are its corners, so its generic mesh must be exact.
TEST(SurfaceMesh, GenericSupportMeshMatchesEveryShapeItCanCompareWith) {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<Real> size(0.02, 3.0);
  const int cases = std::max(20, static_cast<int>(300 * property_scale()));
  TessellationDetail detail;
  for (int i = 0; i < cases; ++i) {
    Shape s;
    switch (i % 3) {
      case 0:
        s = Shape::sphere(size(rng));
        break;
      case 1:
        s = Shape::box(Vec3(size(rng), size(rng), size(rng)));
        break;
      default:
        s = Shape::capsule(size(rng), size(rng));
        break;
    }
    const SurfaceMesh m = tessellate_convex_support(s, detail);
    const std::string what =
        "case " + std::to_string(i) + " " + std::string(shape_type_name(s.type));
    expect_outward(m, what.c_str());
    if (s.type == ShapeType::box) {
      EXPECT_NEAR(enclosed_volume(m), volume(s), 1e-9 * volume(s)) << what;
    } else {
      expect_volume(m, s, what.c_str());
    }
    for (std::size_t k = 0; k < m.positions.size(); ++k) {
      // A vertex normal is either the direction it is the support point of, or the normal of
      // a flat facet of the shape: either way no point of the shape lies beyond the vertex.
      const Vec3& n = m.normals[k];
      EXPECT_NEAR(support(s, n).dot(n), m.positions[k].dot(n), 1e-9 * (1 + size.max())) << what;
    }
  }
}

}  // namespace
}  // namespace tumble

namespace tumble {
namespace {

// A dumbbell (two boxes apart on x): its mesh holds both boxes, so it encloses their volume,
// not the volume of their convex hull (the generic support-map path would give the hull).
TEST(SurfaceMesh, CompoundIsItsPartsNotTheirHull) {
  std::vector<CompoundPart> parts(2);
  parts[0].shape = Shape::box(Vec3(0.1, 0.1, 0.1));
  parts[0].pose.translation = Vec3(-1, 0, 0);
  parts[1].shape = Shape::box(Vec3(0.1, 0.1, 0.1));
  parts[1].pose.translation = Vec3(1, 0, 0);
  const Shape s = Shape::compound_of(
      std::make_shared<const CompoundShape>(CompoundShape::build(std::move(parts))));
  const SurfaceMesh m = tessellate(s, {});
  EXPECT_EQ(m.triangle_count(), 24);
  EXPECT_NEAR(enclosed_volume(m), 2 * 0.008, 1e-12);
  Real x_min = 0, x_max = 0;
  for (const Vec3& p : m.positions) {
    x_min = std::min(x_min, p.x());
    x_max = std::max(x_max, p.x());
  }
  EXPECT_NEAR(x_min, -1.1, 1e-12);
  EXPECT_NEAR(x_max, 1.1, 1e-12);
}

// A triangle mesh is drawn with its own triangles, each with its face normal.
TEST(SurfaceMesh, TriangleMeshKeepsItsTriangles) {
  // A non-convex "V" of two triangles: its convex hull would be a tetrahedron-like solid.
  std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 1}, {1, 1, 1}, {-1, 0, 1}, {-1, 1, 1}, {0, 1, 0}};
  std::vector<TriangleMesh::Triangle> t = {{0, 1, 2}, {0, 2, 5}, {0, 3, 4}, {0, 4, 5}};
  const TriangleMesh source = TriangleMesh::build(v, t);
  const Shape s = Shape::triangle_mesh(std::make_shared<const TriangleMesh>(source));
  const SurfaceMesh m = tessellate(s, {});
  ASSERT_EQ(m.triangle_count(), source.triangle_count());
  for (int tri = 0; tri < m.triangle_count(); ++tri) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = m.indices[std::size_t(3 * tri + k)];
      EXPECT_EQ(m.positions[i], source.corner(tri, k));
      EXPECT_NEAR((m.normals[i] - source.normal(tri)).norm(), 0, 1e-15);
    }
  }
}

}  // namespace
}  // namespace tumble
