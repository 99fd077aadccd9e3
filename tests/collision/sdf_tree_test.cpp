// SdfTree against independent truth: the convex shapes' own signed distances (collision/ccd's
// signed_distance and the oracle's), a brute-force torus, the Eikonal property, closest-point
// projection, central finite differences of every gradient, bounds that hold every inside
// point, and the smooth union's documented gap.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include "collision/ccd/ray_cast.hpp"
#include "collision/sdf/sdf_grid.hpp"
#include "collision/sdf/sdf_tree.hpp"
#include "tests/collision/oracle.hpp"
#include "tests/collision/sampled_grid.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

using testing::random_rotation;
using testing::random_vector_in_box;
using testing::Rng;
using testing::uniform;

Transform random_pose(Rng& rng, Real spread) {
  return {random_vector_in_box(rng, spread), random_rotation(rng)};
}

SdfNode random_primitive(Rng& rng) {
  switch (rng() % 5) {
    case 0:
      return SdfNode::sphere(uniform(rng, 0.1, 1.0));
    case 1:
      return SdfNode::box(Vec3(uniform(rng, 0.1, 1), uniform(rng, 0.1, 1), uniform(rng, 0.1, 1)));
    case 2:
      return SdfNode::capsule(uniform(rng, 0.1, 0.6), uniform(rng, 0.1, 1.0));
    case 3:
      return SdfNode::cylinder(uniform(rng, 0.1, 0.8), uniform(rng, 0.1, 1.0));
    default: {
      const Real major = uniform(rng, 0.4, 1.2);
      return SdfNode::torus(major, uniform(rng, 0.05, 0.9) * major);
    }
  }
}

// A random CSG tree of up to `depth` levels, every node placed at random.
SdfNode random_tree(Rng& rng, int depth) {
  if (depth == 0 || rng() % 3 == 0)
    return random_primitive(rng).placed(random_pose(rng, 0.6));
  const SdfKind ops[] = {SdfKind::union_of, SdfKind::intersection_of, SdfKind::difference_of,
                         SdfKind::smooth_union_of};
  const SdfKind op = ops[rng() % 4];
  std::vector<SdfNode> operands;
  const int count = 2 + int(rng() % 3);
  for (int i = 0; i < count; ++i)
    operands.push_back(random_tree(rng, depth - 1));
  return SdfNode::combine(op, std::move(operands), uniform(rng, 2, 30))
      .placed(random_pose(rng, 0.3));
}

TEST(SdfTree, PrimitivesAgreeWithTheConvexShapesSignedDistance) {
  Rng rng(11);
  for (int trial = 0; trial < 4000; ++trial) {
    const Transform pose = random_pose(rng, 2);
    Shape shape;
    SdfNode node;
    switch (trial % 5) {
      case 0:
        shape = Shape::sphere(uniform(rng, 0.1, 1));
        node = SdfNode::sphere(shape.radius);
        break;
      case 1:
        shape = Shape::box(Vec3(uniform(rng, 0.1, 1), uniform(rng, 0.1, 1), uniform(rng, 0.1, 1)));
        node = SdfNode::box(shape.half_extents);
        break;
      case 2:
        shape = Shape::capsule(uniform(rng, 0.1, 1), uniform(rng, 0.1, 1));
        node = SdfNode::capsule(shape.radius, shape.half_length);
        break;
      case 3:
        shape = Shape::cylinder(uniform(rng, 0.1, 1), uniform(rng, 0.1, 1));
        node = SdfNode::cylinder(shape.radius, shape.half_length);
        break;
      default:
        shape = Shape::plane();
        node = SdfNode::plane();
        break;
    }
    const SdfTree tree(node.placed(pose));
    EXPECT_TRUE(tree.is_exact());
    for (int k = 0; k < 5; ++k) {
      const Vec3 p = pose.translation + random_vector_in_box(rng, 2.5);
      const Real expected = signed_distance(shape, pose, p);
      ASSERT_NEAR(tree.distance(p), expected, 1e-12) << trial;
      ASSERT_NEAR(tree.distance(p), testing::signed_distance_to_shape(shape, pose, p), 1e-12);
    }
  }
}

TEST(SdfTree, TorusAgreesWithABruteForceDistanceToItsCoreCircle) {
  Rng rng(12);
  for (int trial = 0; trial < 300; ++trial) {
    const Real major = uniform(rng, 0.3, 2), minor = uniform(rng, 0.05, 0.95) * major;
    const SdfTree tree(SdfNode::torus(major, minor));
    const Vec3 p = random_vector_in_box(rng, 3);
    // The nearest point of the circle is in the direction of p's xy part; search the whole
    // circle anyway, finely, then refine around the best sample.
    Real best = std::numeric_limits<Real>::infinity();
    Real best_angle = 0;
    for (int i = 0; i < 4096; ++i) {
      const Real a = 2 * M_PI * i / 4096;
      const Real d = (p - major * Vec3(std::cos(a), std::sin(a), 0)).norm();
      if (d < best) {
        best = d;
        best_angle = a;
      }
    }
    for (Real step = 2 * M_PI / 4096; step > 1e-12; step *= 0.5) {
      for (const Real a : {best_angle - step, best_angle + step}) {
        const Real d = (p - major * Vec3(std::cos(a), std::sin(a), 0)).norm();
        if (d < best) {
          best = d;
          best_angle = a;
        }
      }
    }
    EXPECT_NEAR(tree.distance(p), best - minor, 1e-9) << trial;
  }
}

TEST(SdfTree, ExactDistancesHaveUnitGradientsAndProjectOntoTheSurface) {
  Rng rng(13);
  int checked = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const SdfTree tree(random_primitive(rng).placed(random_pose(rng, 1)));
    for (int k = 0; k < 10; ++k) {
      const Vec3 p = random_vector_in_box(rng, 2.5);
      const sdf::Sample s = tree.sample(p);
      ASSERT_NEAR(s.gradient.norm(), 1.0, 1e-12);
      // The closest point: x - phi grad phi is on the surface.
      ASSERT_NEAR(tree.distance(p - s.distance * s.gradient), 0.0, 1e-9) << trial;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 20000);
}

// Central differences with step h agree with the analytic gradient, except within h of where
// phi is not differentiable (a kink: the gradient jumps there). Every disagreement must be such
// a point, found by the analytic gradients on either side differing; they are counted.
struct GradientCheck {
  int points = 0;
  int kinks = 0;
  int unexplained = 0;
};

GradientCheck check_gradients(const SdfTree& tree, Rng& rng, int points, Real spread) {
  GradientCheck c;
  const Real h = 1e-6;
  for (int i = 0; i < points; ++i) {
    const Vec3 p = random_vector_in_box(rng, spread);
    const sdf::Sample s = tree.sample(p);
    Vec3 fd;
    bool jump = false;
    for (int k = 0; k < 3; ++k) {
      Vec3 e = Vec3::Zero();
      e[k] = h;
      fd[k] = (tree.distance(p + e) - tree.distance(p - e)) / (2 * h);
      jump = jump || (tree.sample(p + e).gradient - tree.sample(p - e).gradient).norm() > 1e-4;
    }
    ++c.points;
    if ((fd - s.gradient).norm() > 1e-5) {
      if (jump)
        ++c.kinks;
      else
        ++c.unexplained;
    }
  }
  return c;
}

TEST(SdfTree, GradientsMatchCentralDifferencesOnRandomTrees) {
  Rng rng(14);
  GradientCheck total;
  for (int trial = 0; trial < 400; ++trial) {
    const SdfTree tree(random_tree(rng, 3));
    const GradientCheck c = check_gradients(tree, rng, 50, 2.0);
    total.points += c.points;
    total.kinks += c.kinks;
    total.unexplained += c.unexplained;
  }
  EXPECT_EQ(total.points, 20000);
  EXPECT_EQ(total.unexplained, 0);
  // Kinks are where two operands meet or a box's medial planes: a thin set, met rarely.
  EXPECT_LT(total.kinks, total.points / 200) << total.kinks;
  std::printf("gradient check: %d points, %d within 1e-6 of a kink\n", total.points, total.kinks);
}

// distance() evaluates the tree without gradients (cheaper, for culling); it must give the
// sample's distance to the bit, on random trees (and morphs of them) at points inside, on and
// far outside, the tree's origin and z axis among them.
TEST(SdfTree, TheDistanceAloneIsTheSamplesDistanceToTheBit) {
  Rng rng(1203);
  int points = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const SdfNode root = random_tree(rng, 3);
    const bool morph = trial % 4 == 3;
    const SdfTree tree(morph ? SdfNode::morph(root, random_tree(rng, 2), 0.5, 1.5) : root);
    for (int i = 0; i < 40; ++i, ++points) {
      const Vec3 p = i == 0   ? Vec3::Zero()
                     : i == 1 ? Vec3(0, 0, uniform(rng, -1, 1))
                              : random_vector_in_box(rng, i % 2 == 0 ? 1.5 : 40.0);
      const Real t = uniform(rng, 0, 2);
      const Real alone = tree.distance(p, t);
      const Real sampled = tree.sample(p, t).distance;
      ASSERT_TRUE(alone == sampled && std::signbit(alone) == std::signbit(sampled))
          << "trial " << trial << " point " << i << ": " << alone << " against " << sampled;
    }
  }
  EXPECT_EQ(points, 40000);
}

TEST(SdfTree, CsgGradientsAreUnitExceptTheSmoothUnionsBlend) {
  Rng rng(15);
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<SdfNode> operands{random_primitive(rng).placed(random_pose(rng, 0.5)),
                                  random_primitive(rng).placed(random_pose(rng, 0.5))};
    for (const SdfKind op : {SdfKind::union_of, SdfKind::intersection_of, SdfKind::difference_of}) {
      const SdfTree tree(SdfNode::combine(op, operands));
      EXPECT_FALSE(tree.is_exact());
      for (int k = 0; k < 5; ++k)
        ASSERT_NEAR(tree.sample(random_vector_in_box(rng, 2)).gradient.norm(), 1.0, 1e-12);
    }
    const Real kk = uniform(rng, 1, 50);
    const SdfTree smooth(SdfNode::combine(SdfKind::smooth_union_of, operands, kk));
    const SdfTree sharp(SdfNode::combine(SdfKind::union_of, operands));
    for (int k = 0; k < 10; ++k) {
      const Vec3 p = random_vector_in_box(rng, 2);
      const Real a = smooth.distance(p), b = sharp.distance(p);
      // Below the union by at most log(2) / k, and never steeper than 1.
      EXPECT_LE(a, b + 1e-12);
      EXPECT_GE(a, b - std::log(2.0) / kk - 1e-12);
      EXPECT_LE(smooth.sample(p).gradient.norm(), 1.0 + 1e-12);
    }
  }
}

TEST(SdfTree, EveryInsidePointIsInTheBounds) {
  Rng rng(16);
  int inside = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const SdfTree tree(random_tree(rng, 3));
    // Points around the bounds (a box twice their size), so that many fall inside.
    const Aabb around =
        tree.is_bounded() ? tree.bounds() : Aabb{Vec3::Constant(-3), Vec3::Constant(3)};
    const Vec3 centre = (around.min + around.max) / 2, half = around.max - around.min;
    for (int k = 0; k < 200; ++k) {
      const Vec3 p = centre + half.cwiseProduct(random_vector_in_box(rng, 1));
      if (tree.distance(p) <= 0) {
        ++inside;
        ASSERT_TRUE(tree.bounds().contains(p)) << trial;
      }
    }
  }
  EXPECT_GT(inside, 3000);
}

TEST(SdfTree, ADifferenceCarvesAndAHalfSpaceCuts) {
  // A bowl: a box minus a sphere sunk into its top face.
  const SdfTree bowl(SdfNode::combine(
      SdfKind::difference_of, {SdfNode::box(Vec3(1, 1, 0.5)),
                               SdfNode::sphere(0.9).placed({Vec3(0, 0, 0.6), Quat::Identity()})}));
  EXPECT_GT(bowl.distance(Vec3(0, 0, 0.3)), 0);            // in the hollow
  EXPECT_LT(bowl.distance(Vec3(0, 0, -0.4)), 0);           // in the bottom under it
  EXPECT_NEAR(bowl.distance(Vec3(0, 0, -0.3)), 0, 1e-12);  // the hollow's floor: 0.6 - 0.9
  EXPECT_NEAR(bowl.sample(Vec3(0, 0, -0.2)).gradient.z(), 1, 1e-12);  // out of the floor, up
  // A half-space cuts a sphere to a dome; the bounds stay finite.
  const SdfTree dome(
      SdfNode::combine(SdfKind::intersection_of, {SdfNode::sphere(1), SdfNode::plane()}));
  EXPECT_TRUE(dome.is_bounded());
  EXPECT_NEAR(dome.bounds().max.z(), 0, 1e-12);
  EXPECT_FALSE(SdfTree(SdfNode::plane()).is_bounded());
}

TEST(SdfTree, BadDescriptionsNameTheNode) {
  const auto message = [](const SdfNode& n) {
    try {
      SdfTree tree(n);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(SdfNode::sphere(-1)).find("root: radius"), std::string::npos);
  EXPECT_NE(message(SdfNode::sphere(std::nan(""))).find("radius"), std::string::npos);
  EXPECT_NE(message(SdfNode::torus(0.5, 0.6)).find("less than major_radius"), std::string::npos);
  const std::string deep = message(SdfNode::combine(
      SdfKind::union_of, {SdfNode::sphere(1),
                          SdfNode::combine(SdfKind::smooth_union_of,
                                           {SdfNode::sphere(1), SdfNode::box(Vec3(1, 0, 1))}, 5)}));
  EXPECT_NE(deep.find("root.children[1].children[1]: every half extent"), std::string::npos)
      << deep;
  EXPECT_NE(message(SdfNode::combine(SdfKind::union_of, {SdfNode::sphere(1)})).find("two operands"),
            std::string::npos);
  EXPECT_NE(message(SdfNode::combine(SdfKind::smooth_union_of,
                                     {SdfNode::sphere(1), SdfNode::sphere(2)}, 0))
                .find("k must be positive"),
            std::string::npos);
  SdfNode chain = SdfNode::sphere(1);
  for (int i = 0; i < 70; ++i)
    chain = SdfNode::combine(SdfKind::union_of, {chain, SdfNode::sphere(1)});
  EXPECT_NE(message(chain).find("deeper than 64"), std::string::npos);
  Transform nan_pose;
  nan_pose.translation.x() = std::nan("");
  EXPECT_NE(message(SdfNode::sphere(1).placed(nan_pose)).find("position"), std::string::npos);
  EXPECT_NE(message(SdfNode::morph(SdfNode::sphere(1), SdfNode::sphere(2), 0, 0)).find("duration"),
            std::string::npos);
  SdfNode lone = SdfNode::morph(SdfNode::sphere(1), SdfNode::sphere(2), 0, 1);
  lone.children.pop_back();
  EXPECT_NE(message(lone).find("two fields"), std::string::npos);
}

TEST(SdfTree, AMorphIsTheTimeBlendOfItsTwoFields) {
  // A sphere of 0.5 m at the origin becoming a box 0.3 m up between t = 1 and t = 3 s.
  const SdfNode from = SdfNode::sphere(0.5);
  const SdfNode to = SdfNode::box(Vec3(0.4, 0.3, 0.2)).placed({Vec3(0, 0, 0.3), Quat::Identity()});
  const SdfTree morph(SdfNode::morph(from, to, 1, 2));
  const SdfTree a(from), b(to);
  EXPECT_TRUE(morph.changes_with_time());
  EXPECT_FALSE(a.changes_with_time());
  EXPECT_EQ(morph.changes_from(), 1);
  EXPECT_EQ(morph.changes_until(), 3);
  // Within the union of the two solids' boxes.
  EXPECT_LE(morph.bounds().min.z(), -0.5);
  EXPECT_GE(morph.bounds().max.z(), 0.5);
  std::mt19937_64 rng(71);
  std::uniform_real_distribution<Real> u(-1, 1), when(-1, 5);
  for (int i = 0; i < 5000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const Real t = when(rng);
    const Real w = std::clamp((t - 1) / 2, Real(0), Real(1));
    const sdf::Sample s = morph.sample(p, t), sa = a.sample(p), sb = b.sample(p);
    ASSERT_NEAR(s.distance, (1 - w) * sa.distance + w * sb.distance, 1e-15) << t;
    ASSERT_LT((s.gradient - ((1 - w) * sa.gradient + w * sb.gradient)).norm(), 1e-15) << t;
    if (t <= 1) {
      ASSERT_EQ(s.distance, sa.distance);  // before the start, the first field alone
    }
    if (t >= 3) {
      ASSERT_EQ(s.distance, sb.distance);  // after the end, the second alone
    }
  }
}

TEST(SdfTree, AMorphBetweenTwoGridsIsTheirTimeBlend) {
  // Two grids of 5 cm cells: a sphere of 0.4 m and a box of half extents (0.5, 0.3, 0.2), both
  // sampled from their exact fields, morphed over t in [0, 1].
  const auto grid_of = [](auto&& exact) {
    const Real cell = 0.05;
    const int n = 33;
    const Vec3 origin = Vec3::Constant(-cell * (n - 1) / 2);
    return SdfNode::from_grid(
        std::make_shared<const SdfGrid>(test::sampled_grid(origin, cell, {n, n, n}, exact)));
  };
  const SdfNode sphere = grid_of([](const Vec3& p) { return p.norm() - 0.4; });
  const SdfNode box =
      grid_of([](const Vec3& p) { return sdf::box(p, Vec3(0.5, 0.3, 0.2)).distance; });
  const SdfTree morph(SdfNode::morph(sphere, box, 0, 1));
  const SdfTree a(sphere), b(box);
  std::mt19937_64 rng(72);
  std::uniform_real_distribution<Real> u(-0.7, 0.7), when(0, 1);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const Real t = when(rng);
    ASSERT_NEAR(morph.distance(p, t), (1 - t) * a.distance(p) + t * b.distance(p), 1e-15);
  }
  // Half-way, the surface crosses +x between the sphere's 0.4 m and the box's 0.5 m.
  EXPECT_LT(morph.distance(Vec3(0.4, 0, 0), 0.5), 0);
  EXPECT_GT(morph.distance(Vec3(0.5, 0, 0), 0.5), 0);
}

}  // namespace
}  // namespace tumble
