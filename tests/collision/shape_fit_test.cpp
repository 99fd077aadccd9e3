// fit_shape: on thousands of random detailed shapes (boxes, capsules, cylinders, hulls,
// compounds of them), every point of the detailed shape's surface found by its support function
// lies inside the fitted box, sphere, capsule or hull, and the fit is tight: some surface point
// reaches its boundary.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/shape.hpp"
#include "tests/collision/oracle.hpp"
#include "tests/property_scale.hpp"
#include "tumble/error.hpp"
#include "tumble/shape.hpp"

namespace tumble {
namespace {

Shape random_part(std::mt19937_64& rng) {
  std::uniform_real_distribution<Real> size(0.05, 0.5);
  switch (std::uniform_int_distribution<int>(0, 4)(rng)) {
    case 0:
      return Shape::box(Vec3(size(rng), size(rng), size(rng)));
    case 1:
      return Shape::capsule(size(rng), size(rng));
    case 2:
      return Shape::cylinder(size(rng), size(rng));
    case 3:
      return Shape::sphere(size(rng));
    default: {
      std::vector<Vec3> points;
      for (int i = 0; i < 12; ++i)
        points.push_back(
            testing::random_unit_vector(rng).cwiseProduct(Vec3(size(rng), size(rng), size(rng))));
      return hull_from_points(points);
    }
  }
}

Shape random_detailed(std::mt19937_64& rng) {
  if (std::uniform_int_distribution<int>(0, 2)(rng) > 0)
    return random_part(rng);
  std::vector<CompoundPart> parts;
  const int n = std::uniform_int_distribution<int>(2, 4)(rng);
  std::uniform_real_distribution<Real> offset(-0.6, 0.6);
  for (int i = 0; i < n; ++i) {
    CompoundPart p{random_part(rng), Transform{}};
    p.pose.translation = Vec3(offset(rng), offset(rng), offset(rng));
    p.pose.rotation = testing::random_rotation(rng);
    parts.push_back(p);
  }
  return compound_from_parts(parts);
}

// The signed distance from p to the fitted shape (negative inside), exact for each fit.
Real distance_to(const Shape& fit, const Vec3& p) {
  switch (fit.type) {
    case ShapeType::sphere:
      return p.norm() - fit.radius;
    case ShapeType::box:
      return (p.cwiseAbs() - fit.half_extents).maxCoeff();
    case ShapeType::capsule: {
      const Real z = std::clamp(p.z(), -fit.half_length, fit.half_length);
      return (p - Vec3(0, 0, z)).norm() - fit.radius;
    }
    case ShapeType::compound: {  // a capsule turned onto another axis
      const CompoundPart& part = fit.compound->parts().front();
      return distance_to(part.shape, part.pose.rotation.conjugate() * (p - part.pose.translation));
    }
    case ShapeType::hull: {
      Real d = -std::numeric_limits<Real>::infinity();
      for (const HullFace& f : fit.hull->faces())
        d = std::max(d, f.normal.dot(p) - f.offset);
      return d;
    }
    default:
      ADD_FAILURE() << "unexpected fit type";
      return 0;
  }
}

TEST(ShapeFit, EveryFitHoldsTheDetailedShapeAndTouchesIt) {
  std::mt19937_64 rng(2024);
  const int cases = scaled(2000);
  for (int c = 0; c < cases; ++c) {
    const Shape detailed = random_detailed(rng);
    std::vector<Vec3> surface;
    for (int k = 0; k < 200; ++k)
      surface.push_back(support(detailed, testing::random_unit_vector(rng)));
    for (int k = 0; k < 3; ++k) {
      surface.push_back(support(detailed, Vec3::Unit(k)));
      surface.push_back(support(detailed, -Vec3::Unit(k)));
    }
    // The farthest point from the origin, which the sphere must reach: from the farthest sample,
    // p <- support(p / |p|) never decreases |p| (|support(u)| >= u . support(u) >= u . p) and
    // climbs to a farthest point.
    Vec3 far = *std::max_element(surface.begin(), surface.end(),
                                 [](const Vec3& a, const Vec3& b) { return a.norm() < b.norm(); });
    for (int k = 0; k < 50; ++k)
      far = support(detailed, far.normalized());
    surface.push_back(far);
    for (const ShapeFit fit : {ShapeFit::box, ShapeFit::sphere, ShapeFit::capsule}) {
      const Shape shape = fit_shape(detailed, fit);
      Real deepest_out = -std::numeric_limits<Real>::infinity();
      for (const Vec3& p : surface)
        deepest_out = std::max(deepest_out, distance_to(shape, p));
      // A cylinder counts by 32 rim points: its rim bulges past their chords by r (1 - cos 5.6
      // degrees), under 0.5% of its radius.
      const Real slack = 0.005 * bounding_radius(detailed);
      EXPECT_LE(deepest_out, slack) << "case " << c << " fit " << int(fit);
      // Tight: the box's and sphere's extents are reached by the support points exactly; the
      // capsule is the least about its axis, within the cylinder's rim points.
      if (fit != ShapeFit::capsule) {
        EXPECT_GE(deepest_out, -slack - 1e-9) << "case " << c << " fit " << int(fit);
      }
    }
    // The hull holds every vertex of a polytope exactly (round parts from inside).
    const Shape hull = fit_shape(detailed, ShapeFit::hull);
    if (detailed.type == ShapeType::box || detailed.type == ShapeType::hull) {
      for (const Vec3& p : surface) {
        EXPECT_LE(distance_to(hull, p), 1e-9) << "case " << c;
      }
      EXPECT_NEAR(volume(hull), volume(detailed), 1e-9 * volume(detailed)) << "case " << c;
    }
  }
}

TEST(ShapeFit, BuildersInFrameKeepThePointsWhereTheyAre) {
  const std::vector<Vec3> points{{1, 1, 1}, {2, 1, 1}, {1, 2, 1}, {1, 1, 2}};
  const Shape kept = hull_in_frame(points);
  EXPECT_EQ(support(kept, Vec3(1, 0, 0)), Vec3(2, 1, 1));
  const Shape centred = hull_from_points(points);
  EXPECT_NE(support(centred, Vec3(1, 0, 0)), Vec3(2, 1, 1));
  CompoundPart part{Shape::sphere(0.5), Transform{}};
  part.pose.translation = Vec3(3, 0, 0);
  const Shape compound = compound_in_frame({part});
  EXPECT_NEAR((support(compound, Vec3(1, 0, 0)) - Vec3(3.5, 0, 0)).norm(), 0, 1e-12);
  EXPECT_THROW(fit_shape(Shape::plane(), ShapeFit::box), Error);
}

}  // namespace
}  // namespace tumble
