// CompoundShape: mass properties against a single box and against the divergence-theorem
// integral of the same solid written as a mesh (an independent route), and contacts against
// the parts' own contacts.
#include <gtest/gtest.h>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/shapes/compound_shape.hpp"
#include "tests/collision/mesh_fixtures.hpp"
#include "tests/collision/oracle.hpp"

namespace tumble::testing {
namespace {

TEST(CompoundShape, TwoHalvesOfABoxAreTheBox) {
  const Vec3 h(0.8, 0.3, 0.5);
  // Halves along x, given off-centre: the compound re-centres and reports the shift.
  const Vec3 offset(1, 2, 3);
  Vec3 com;
  const CompoundShape c = CompoundShape::build(
      {{Shape::box({h.x() / 2, h.y(), h.z()}), {offset + Vec3(-h.x() / 2, 0, 0), Quat::Identity()}},
       {Shape::box({h.x() / 2, h.y(), h.z()}), {offset + Vec3(h.x() / 2, 0, 0), Quat::Identity()}}},
      &com);
  EXPECT_LT((com - offset).norm(), 1e-15);
  EXPECT_NEAR(c.volume(), 8 * h.prod(), 1e-14);
  EXPECT_LT((c.unit_inertia() - unit_inertia(Shape::box(h))).norm(), 1e-14);
  const Shape s = Shape::compound_of(std::make_shared<const CompoundShape>(c));
  EXPECT_NEAR(volume(s), 8 * h.prod(), 1e-14);
  EXPECT_NEAR(bounding_radius(s), h.norm(), 1e-12 + 0.6);  // a bound, not the tightest
  EXPECT_GE(bounding_radius(s), h.norm() - 1e-12);
}

TEST(CompoundShape, MassPropertiesMatchTheMeshOfTheSameSolid) {
  Rng rng(501);
  for (int c = 0; c < 200; ++c) {
    // Two boxes side by side (disjoint), rotated and placed at random.
    const Vec3 h1(uniform(rng, 0.1, 1), uniform(rng, 0.1, 1), uniform(rng, 0.1, 1));
    const Vec3 h2(uniform(rng, 0.1, 1), uniform(rng, 0.1, 1), uniform(rng, 0.1, 1));
    const Transform p1{random_vector_in_box(rng, 1), random_rotation(rng)};
    const Transform p2{p1.translation + random_unit_vector(rng) * (h1.norm() + h2.norm() + 0.01),
                       random_rotation(rng)};
    Vec3 com;
    const CompoundShape compound =
        CompoundShape::build({{Shape::box(h1), p1}, {Shape::box(h2), p2}}, &com);
    const TriangleMesh a = box_mesh(h1, p1);
    const TriangleMesh b = box_mesh(h2, p2);
    std::vector<Vec3> v = a.vertices();
    std::vector<TriangleMesh::Triangle> t = a.triangles();
    for (const Vec3& x : b.vertices())
      v.push_back(x);
    for (auto tri : b.triangles()) {
      for (auto& i : tri)
        i += 8;
      t.push_back(tri);
    }
    const TriangleMesh both = TriangleMesh::build(v, t);
    ASSERT_TRUE(both.is_closed());
    EXPECT_NEAR(compound.volume(), both.volume(), 1e-12 * both.volume());
    EXPECT_LT((com - both.centroid()).norm(), 1e-12 * 4);
    EXPECT_LT((compound.unit_inertia() - both.unit_inertia()).norm(),
              1e-10 * both.unit_inertia().norm());
  }
}

TEST(CompoundShape, RejectsBadParts) {
  EXPECT_THROW(CompoundShape::build({}), CompoundError);
  EXPECT_THROW(CompoundShape::build({{Shape::plane(), {}}}), CompoundError);
  Transform nan_pose;
  nan_pose.translation.x() = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_THROW(CompoundShape::build({{Shape::sphere(1), nan_pose}}), CompoundError);
}

TEST(CompoundShape, DumbbellOnAPlaneTouchesWithBothSpheres) {
  const Shape dumbbell =
      Shape::compound_of(std::make_shared<const CompoundShape>(CompoundShape::build(
          {{Shape::sphere(0.5), {Vec3(-1, 0, 0), Quat::Identity()}},
           {Shape::sphere(0.5), {Vec3(1, 0, 0), Quat::Identity()}},
           {Shape::capsule(0.1, 0.8),
            {Vec3::Zero(), Quat(Eigen::AngleAxis<Real>(M_PI / 2, Vec3::UnitY()))}}})));
  Manifold m;
  ASSERT_EQ(collide(dumbbell, {Vec3(0, 0, 0.49), Quat::Identity()}, Shape::plane(), {}, 0.01, m),
            2);
  EXPECT_EQ(m.normal, Vec3::UnitZ());
  for (int i = 0; i < 2; ++i)
    EXPECT_NEAR(m.points[i].depth, 0.01, 1e-15);
  // The part index is in the compound's half of the feature id: part 0 and part 1.
  EXPECT_NE(m.points[0].feature, m.points[1].feature);
  EXPECT_EQ(m.points[0].feature.a >> 8, 0);
  EXPECT_EQ(m.points[1].feature.a >> 8, 1);
}

TEST(CompoundShape, OnePartCompoundCollidesAsThePart) {
  Rng rng(502);
  const std::vector<Shape> shapes = {Shape::sphere(0.4), Shape::box({0.3, 0.5, 0.2}),
                                     Shape::capsule(0.2, 0.4)};
  int touching = 0;
  for (int c = 0; c < scaled(2000); ++c) {
    const Shape& part = shapes[c % 3];
    const Shape& other = shapes[(c / 3) % 3];
    const Shape one = Shape::compound_of(
        std::make_shared<const CompoundShape>(CompoundShape::build({{part, {}}})));
    const Transform pa{random_vector_in_box(rng, 0.5), random_rotation(rng)};
    const Transform pb{random_vector_in_box(rng, 0.5), random_rotation(rng)};
    Manifold direct;
    Manifold through;
    const int n = collide(part, pa, other, pb, 0.05, direct);
    ASSERT_EQ(collide(one, pa, other, pb, 0.05, through), n);
    touching += n > 0;
    if (n == 0)
      continue;
    EXPECT_LT((direct.normal - through.normal).norm(), 1e-12);
    EXPECT_NEAR(direct.points[deepest_point(direct)].depth,
                through.points[deepest_point(through)].depth, 1e-12);
  }
  EXPECT_GT(touching, scaled(2000) / 4);
}

}  // namespace
}  // namespace tumble::testing
