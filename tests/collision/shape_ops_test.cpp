// The shape table (collision/shapes/shape_ops.hpp): a row per type in ShapeType order, and the
// hull row's exact point distance against two independent answers: the oracle's triangle fans
// and GJK between the hull and the point.
#include <gtest/gtest.h>

#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/shapes/shape.hpp"
#include "collision/shapes/shape_ops.hpp"
#include "tests/collision/oracle.hpp"

namespace tumble {
namespace {

TEST(ShapeOps, OneRowPerTypeInTypeOrder) {
  const char* names[] = {"sphere", "box",  "capsule",  "plane", "cylinder",
                         "hull",   "mesh", "compound", "sdf"};
  for (int t = 0; t < kShapeTypeCount; ++t) {
    const ShapeOps& row = shape_ops(static_cast<ShapeType>(t));
    EXPECT_EQ(row.name, names[t]);
    EXPECT_EQ(shape_type_name(static_cast<ShapeType>(t)), names[t]);
    EXPECT_TRUE(row.support && row.world_aabb && row.volume && row.unit_inertia &&
                row.bounding_radius && row.ray && row.signed_distance && row.inner_radius &&
                row.surface_mesh)
        << names[t];
  }
  EXPECT_EQ(shape_type_name(static_cast<ShapeType>(kShapeTypeCount)), "unknown");
}

TEST(ShapeOps, HullDistanceAgreesWithTriangleFansAndGjk) {
  testing::Rng rng(21);
  int outside = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Shape hull = testing::random_shape(rng, ShapeType::hull);
    for (int k = 0; k < 5; ++k) {
      const Vec3 p = testing::random_vector_in_box(rng, 2.0);
      const Real d = shape_ops(ShapeType::hull).signed_distance(hull, p);
      ASSERT_NEAR(d, testing::local_signed_distance(hull, p), 1e-12) << trial;
      if (d > 1e-9) {
        ++outside;
        const GjkResult g =
            gjk(ConvexSupport::of(hull, Transform{}), ConvexSupport::of_points(&p, 1, Transform{}));
        ASSERT_NEAR(d, g.distance, 1e-9) << trial;
      }
    }
  }
  EXPECT_GT(outside, 5000);
}

TEST(ShapeOps, InnerRadiusIsTheCentresDepthForConvexShapes) {
  // For a convex solid the largest ball about the centre of mass reaches the nearest face: its
  // radius is minus the signed distance there (the oracle's own distance, independent of the
  // rows). A compound's is its thinnest part's.
  testing::Rng rng(22);
  for (ShapeType type : {ShapeType::sphere, ShapeType::box, ShapeType::capsule, ShapeType::cylinder,
                         ShapeType::hull})
    for (int trial = 0; trial < 500; ++trial) {
      const Shape s = testing::random_shape(rng, type);
      ASSERT_NEAR(inner_radius(s), -testing::local_signed_distance(s, Vec3::Zero()), 1e-12)
          << shape_type_name(type) << " " << trial;
    }
  const Shape thin = Shape::box(Vec3(1, 1, 0.05));
  const Shape compound = compound_from_parts(
      {{Shape::sphere(0.5), Transform{}}, {thin, Transform{Vec3(0, 0, 1), Quat::Identity()}}});
  EXPECT_DOUBLE_EQ(inner_radius(compound), 0.05);
}

}  // namespace
}  // namespace tumble
