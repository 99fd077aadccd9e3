// ConvexHull: topology and exact mass properties against closed forms (box, octahedron, a
// rotated and shifted box), support maps against brute force, and clear errors for point sets
// without volume.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/shape.hpp"
#include "tests/collision/oracle.hpp"

namespace tumble::testing {
namespace {

std::vector<Vec3> box_corners(const Vec3& h) {
  std::vector<Vec3> points;
  for (int v = 0; v < 8; ++v)
    points.emplace_back(v & 1 ? h.x() : -h.x(), v & 2 ? h.y() : -h.y(), v & 4 ? h.z() : -h.z());
  return points;
}

TEST(ConvexHull, BoxCornersGiveSixSquareFacesAndTheBoxMassProperties) {
  const Vec3 h(0.5, 1.0, 1.5);
  Rng rng(501);
  std::vector<Vec3> points = box_corners(h);
  for (int i = 0; i < 50; ++i)
    points.push_back(random_vector_in_box(rng, 1).cwiseProduct(h));  // interior points
  points.push_back(points[3]);                                       // a duplicate
  const ConvexHull hull = ConvexHull::from_points(points);
  EXPECT_EQ(hull.vertices().size(), 8u);
  EXPECT_EQ(hull.faces().size(), 6u);
  EXPECT_EQ(hull.edges().size(), 12u);
  for (const HullFace& f : hull.faces())
    EXPECT_EQ(f.count, 4);
  EXPECT_NEAR(hull.volume(), 8 * h.prod(), 1e-12);
  EXPECT_LT((hull.unit_inertia() - unit_inertia(Shape::box(h))).norm(), 1e-12);
  EXPECT_LT(hull.centre_of_mass_offset().norm(), 1e-12);
  // Every edge's two faces hold both of its vertices; each vertex has three neighbours.
  for (const HullEdge& e : hull.edges()) {
    EXPECT_NE(e.face[0], e.face[1]);
    for (int side = 0; side < 2; ++side) {
      const HullFace& f = hull.faces()[std::size_t(e.face[side])];
      int found = 0;
      for (int k = 0; k < f.count; ++k) {
        const int v = hull.face_vertices()[std::size_t(f.first_index + k)];
        found += (v == e.vertex[0] || v == e.vertex[1]) ? 1 : 0;
      }
      EXPECT_EQ(found, 2);
    }
  }
  for (int v = 0; v < 8; ++v)
    EXPECT_EQ(hull.neighbour_start(v + 1) - hull.neighbour_start(v), 3);
}

TEST(ConvexHull, ShiftedRotatedBoxIsRecentredWithRotatedInertia) {
  const Vec3 h(0.3, 0.7, 0.2);
  const Quat q(Eigen::AngleAxis<Real>(0.7, Vec3(1, 2, 3).normalized()));
  const Vec3 shift(10, -4, 2.5);
  std::vector<Vec3> points;
  for (const Vec3& p : box_corners(h))
    points.push_back(q * p + shift);
  const ConvexHull hull = ConvexHull::from_points(points);
  EXPECT_LT((hull.centre_of_mass_offset() - shift).norm(), 1e-12);
  const Mat3 r = q.toRotationMatrix();
  const Mat3 expected = r * unit_inertia(Shape::box(h)) * r.transpose();
  EXPECT_LT((hull.unit_inertia() - expected).norm(), 1e-12);
  EXPECT_NEAR(hull.volume(), 8 * h.prod(), 1e-12);
}

TEST(ConvexHull, OctahedronMatchesItsClosedForm) {
  // |x| + |y| + |z| <= a: volume 4a^3/3, E[x^2] = a^2/10, so I/m = a^2/5 on the diagonal.
  const Real a = 0.8;
  const std::vector<Vec3> points = {{a, 0, 0},  {-a, 0, 0}, {0, a, 0},
                                    {0, -a, 0}, {0, 0, a},  {0, 0, -a}};
  const ConvexHull hull = ConvexHull::from_points(points);
  EXPECT_EQ(hull.faces().size(), 8u);
  EXPECT_NEAR(hull.volume(), 4 * a * a * a / 3, 1e-12);
  EXPECT_LT((hull.unit_inertia() - Mat3::Identity() * (a * a / 5)).norm(), 1e-12);
}

TEST(ConvexHull, ManyPointsOnASphereApproachTheSphere) {
  Rng rng(502);
  std::vector<Vec3> points;
  for (int i = 0; i < 4000; ++i)
    points.push_back(random_unit_vector(rng));
  const ConvexHull hull = ConvexHull::from_points(points);
  const Real sphere = 4 * std::numbers::pi / 3;
  // An inscribed polytope: below the sphere, within a percent with 4000 points.
  EXPECT_LT(hull.volume(), sphere);
  EXPECT_GT(hull.volume(), 0.99 * sphere);
  EXPECT_NEAR(hull.unit_inertia()(0, 0), 0.4, 0.01);
  EXPECT_NEAR(hull.unit_inertia()(0, 1), 0, 0.01);
}

TEST(ConvexHull, HillClimbingSupportEqualsTheBruteForceMaximum) {
  Rng rng(503);
  std::vector<Vec3> points;
  for (int i = 0; i < 500; ++i)
    points.push_back(random_unit_vector(rng).cwiseProduct(Vec3(1, 0.5, 2)));
  const ConvexHull hull = ConvexHull::from_points(points);
  ASSERT_GT(int(hull.vertices().size()), kHullScanLimit);
  int start = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 d = random_unit_vector(rng);
    Real best = -1e300;
    for (const Vec3& v : hull.vertices())
      best = std::max(best, v.dot(d));
    start = hull.support_index(d, start);
    EXPECT_NEAR(hull.vertex(start).dot(d), best, 1e-15);
  }
}

TEST(ConvexHull, PointSetsWithoutVolumeAreRefusedWithAClearMessage) {
  const auto message = [](const std::vector<Vec3>& points) -> std::string {
    try {
      (void)ConvexHull::from_points(points);
    } catch (const DegenerateHullError& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_NE(message({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).find("at least 4"), std::string::npos);
  EXPECT_NE(message({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.2, 0}}).find("coplanar"),
            std::string::npos);
  EXPECT_NE(message({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}).find("collinear"),
            std::string::npos);
  EXPECT_NE(message({{1, 2, 3}, {1, 2, 3}, {1, 2, 3}, {1, 2, 3}}).find("coincident"),
            std::string::npos);
  EXPECT_NE(message({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, std::nan("")}}).find("not finite"),
            std::string::npos);
}

TEST(CylinderShape, MassPropertiesMatchClosedFormsAndTheAabbIsExact) {
  const Shape c = Shape::cylinder(0.4, 0.9);
  EXPECT_NEAR(volume(c), std::numbers::pi * 0.16 * 1.8, 1e-12);
  const Mat3 i = unit_inertia(c);
  EXPECT_NEAR(i(2, 2), 0.16 / 2, 1e-12);
  EXPECT_NEAR(i(0, 0), (3 * 0.16 + 1.8 * 1.8) / 12, 1e-12);
  EXPECT_NEAR(bounding_radius(c), std::hypot(0.4, 0.9), 1e-12);
  // The box from support points along the world axes equals the closed form.
  Rng rng(504);
  for (int n = 0; n < 200; ++n) {
    const Transform pose{random_vector_in_box(rng, 3), random_rotation(rng)};
    const Aabb box = world_aabb(c, pose);
    for (int k = 0; k < 3; ++k) {
      const Vec3 axis = Vec3::Unit(k);
      EXPECT_NEAR(box.max[k], support_value(c, pose, axis), 1e-12);
      EXPECT_NEAR(box.min[k], -support_value(c, pose, -axis), 1e-12);
    }
  }
}

}  // namespace
}  // namespace tumble::testing
