// The shape table (collision/shapes/shape_ops.hpp): a row per type in ShapeType order, and the
// hull row's exact point distance against two independent answers: the oracle's triangle fans
// and GJK between the hull and the point.
#include <gtest/gtest.h>

#include "collision/narrow_phase/gjk_epa/gjk.hpp"
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
                row.bounding_radius && row.ray && row.signed_distance)
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

}  // namespace
}  // namespace tumble
