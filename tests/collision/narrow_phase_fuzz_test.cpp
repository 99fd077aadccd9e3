// Degenerate fuzz of GJK, EPA and the narrow phase: nearly flat and needle hulls,
// duplicated points, shapes of 1e-6 m and 1e4 m, bodies 1e6 m from the origin, exactly touching
// and exactly coincident poses. Every query must end (the iteration caps bound it), return a
// status from the enum, and give finite numbers with a unit normal. Counts by status are printed.
// Exactly flat, collinear or coincident point sets must be refused by ConvexHull with a
// DegenerateHullError, never crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "collision/narrow_phase/gjk_epa/epa.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "tests/collision/oracle.hpp"
#include "tests/property_scale.hpp"

namespace tumble::testing {
namespace {

// Points for a degenerate-ish hull of size `size`: kind 0 nearly flat, 1 needle, 2 many duplicates,
// 3 a tiny cluster plus one far point, 4 exactly flat (refused), 5 exactly collinear (refused),
// 6 all coincident (refused).
std::vector<Vec3> degenerate_points(Rng& rng, int kind, Real size) {
  std::vector<Vec3> points;
  const int n = 4 + int(uniform(rng, 0, 30));
  const Real thin = std::pow(Real(10), uniform(rng, -8, -2));
  for (int i = 0; i < n; ++i) {
    Vec3 p = random_vector_in_box(rng, 1);
    switch (kind) {
      case 0:
        p.z() *= thin;
        break;
      case 1:
        p.x() *= thin;
        p.y() *= thin;
        break;
      case 2:
        p = Vec3(i % 4 == 0 ? 1 : 0, i % 4 == 1 ? 1 : 0, i % 4 == 2 ? 1 : 0);  // 4 points, repeated
        break;
      case 3:
        p = i == 0 ? Vec3(1, 1, 1) : Vec3(p * thin);
        break;
      case 4:
        p.z() = 0;
        break;
      case 5:
        p = Vec3(p.x(), 2 * p.x(), -p.x());
        break;
      default:
        p = Vec3(0.5, 0.25, 0.125);
        break;
    }
    points.push_back(p * size);
  }
  return points;
}

bool finite_unit(const Vec3& n) {
  return n.allFinite() && std::abs(n.norm() - 1) < 1e-9;
}

TEST(NarrowPhaseFuzz, DegenerateInputsGiveAStatusAndNoNaN) {
  Rng rng(4101);
  // A pool of shapes: degenerate hulls (the ones Qhull accepts) at three sizes, plus the
  // primitives at extreme sizes.
  std::vector<Shape> pool;
  int refused = 0;
  int accepted = 0;
  const std::array<Real, 3> sizes = {1e-6, 1, 1e4};
  for (int i = 0; i < 1200; ++i) {
    const int kind = i % 7;
    const Real size = sizes[std::size_t(i / 7 % 3)];
    const std::vector<Vec3> points = degenerate_points(rng, kind, size);
    try {
      pool.push_back(
          Shape::convex_hull(std::make_shared<const ConvexHull>(ConvexHull::from_points(points))));
      ++accepted;
      const ConvexHull& hull = *pool.back().hull;
      EXPECT_TRUE(std::isfinite(hull.volume()) && hull.volume() > 0);
      EXPECT_TRUE(hull.unit_inertia().allFinite());
      EXPECT_LE(kind, 3) << "an exactly flat, collinear or coincident set was accepted";
    } catch (const DegenerateHullError& e) {
      ++refused;
      EXPECT_GT(std::string(e.what()).size(), 10u);
    }
  }
  for (const Real size : sizes) {
    pool.push_back(Shape::sphere(size));
    pool.push_back(Shape::box(Vec3(size, size * 1e-3, size)));
    pool.push_back(Shape::box(Vec3::Constant(size)));
    pool.push_back(Shape::capsule(size, size));
    pool.push_back(Shape::capsule(size, 0));
    pool.push_back(Shape::cylinder(size, size * 1e-3));
    pool.push_back(Shape::cylinder(size * 1e-3, size));
  }
  EXPECT_GT(accepted, 300);
  EXPECT_GT(refused, 300);

  std::map<std::string, int> gjk_counts;
  std::map<std::string, int> epa_counts;
  int contacts = 0;
  const int queries = std::max(1000, int(100000 * property_scale()));
  for (int q = 0; q < queries; ++q) {
    const Shape& a = pool[std::size_t(uniform(rng, 0, Real(pool.size()) - 1e-9))];
    const Shape& b = pool[std::size_t(uniform(rng, 0, Real(pool.size()) - 1e-9))];
    const Real reach = bounding_radius(a) + bounding_radius(b);
    const Vec3 far = uniform(rng, 0, 1) < 0.3 ? Vec3(1e6, -1e6, 1e6) : Vec3::Zero();
    Transform pose_a{far + random_vector_in_box(rng, reach), random_rotation(rng)};
    Transform pose_b{pose_a.translation + random_unit_vector(rng) * uniform(rng, 0, 1.2) * reach,
                     random_rotation(rng)};
    const int special = q % 10;
    if (special == 0) {
      pose_b = pose_a;  // coincident
    } else if (special == 1) {
      pose_b.rotation = pose_a.rotation;  // aligned: exact face-face and touching cases
      pose_b.translation = pose_a.translation + pose_a.rotate(Vec3::UnitZ()) * reach * 0.5;
    } else if (special == 2) {
      // Exactly touching along A's support: B placed so its support meets A's.
      const Vec3 d = random_unit_vector(rng);
      const Vec3 on_a = pose_a.apply(support(a, pose_a.rotate_inverse(d)));
      const Vec3 on_b_local = support(b, pose_b.rotate_inverse(-d));
      pose_b.translation = on_a - pose_b.rotate(on_b_local);
    }
    const ConvexSupport sa = ConvexSupport::of(a, pose_a);
    const ConvexSupport sb = ConvexSupport::of(b, pose_b);
    const GjkResult g = gjk(sa, sb);
    gjk_counts[gjk_status_name(g.status)]++;
    ASSERT_TRUE(std::isfinite(g.distance)) << "query " << q;
    ASSERT_TRUE(finite_unit(g.normal)) << "query " << q;
    ASSERT_TRUE(g.point_a.allFinite() && g.point_b.allFinite()) << "query " << q;
    ASSERT_LE(g.iterations, GjkSettings{}.max_iterations);
    if (g.status == GjkStatus::intersecting) {
      const EpaResult e = epa(sa, sb, g);
      epa_counts[epa_status_name(e.status)]++;
      ASSERT_TRUE(std::isfinite(e.depth) && e.depth >= 0) << "query " << q;
      ASSERT_TRUE(finite_unit(e.normal)) << "query " << q;
      ASSERT_TRUE(e.point_a.allFinite() && e.point_b.allFinite()) << "query " << q;
    }
    Manifold m;
    const int count = collide(a, pose_a, b, pose_b, Real(0.01) * reach, m);
    ASSERT_GE(count, 0);
    ASSERT_LE(count, kMaxManifoldPoints);
    if (count > 0) {
      ++contacts;
      ASSERT_TRUE(finite_unit(m.normal)) << "query " << q;
      for (int i = 0; i < count; ++i) {
        ASSERT_TRUE(m.points[std::size_t(i)].position.allFinite()) << "query " << q;
        ASSERT_TRUE(std::isfinite(m.points[std::size_t(i)].depth)) << "query " << q;
      }
    }
  }
  std::printf(
      "[ stats    ] fuzz: %zu shapes (%d degenerate hulls accepted, %d refused), %d "
      "queries, %d with contact\n",
      pool.size(), accepted, refused, queries, contacts);
  for (const auto& [status, count] : gjk_counts)
    std::printf("[ stats    ]   gjk %-15s %d\n", status.c_str(), count);
  for (const auto& [status, count] : epa_counts)
    std::printf("[ stats    ]   epa %-15s %d\n", status.c_str(), count);
}

}  // namespace
}  // namespace tumble::testing
