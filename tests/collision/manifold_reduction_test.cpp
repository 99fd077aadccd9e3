// manifold_reduction against its definition (deepest point, the point farthest from it, then
// the largest area) and against the best possible choice found by trying every subset.
#include "collision/narrow_phase/pairs/manifold_reduction.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <vector>

#include "tests/collision/oracle.hpp"

namespace tumble::testing {
namespace {

// Area of the convex hull of points in the plane z = const (gift wrapping, at most 4 here).
Real hull_area_xy(std::vector<Vec3> points) {
  const Vec3 centre =
      std::accumulate(points.begin(), points.end(), Vec3(Vec3::Zero())) / Real(points.size());
  std::sort(points.begin(), points.end(), [&](const Vec3& a, const Vec3& b) {
    return std::atan2(a.y() - centre.y(), a.x() - centre.x()) <
           std::atan2(b.y() - centre.y(), b.x() - centre.x());
  });
  // For four points, the hull is either the quadrilateral in angular order (convex) or a
  // triangle; the larger of the shoelace area and every triangle's area is the hull's.
  Real best = 0;
  const int n = int(points.size());
  Real shoelace = 0;
  for (int i = 0; i < n; ++i) {
    shoelace += points[i].x() * points[(i + 1) % n].y() - points[(i + 1) % n].x() * points[i].y();
  }
  best = std::abs(shoelace) / 2;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      for (int k = j + 1; k < n; ++k) {
        best =
            std::max(best, std::abs((points[j] - points[i]).cross(points[k] - points[i]).z()) / 2);
      }
    }
  }
  return best;
}

TEST(ManifoldReduction, FourOrFewerAreKeptAsTheyAre) {
  std::vector<ContactPoint> points(3);
  std::array<int, kMaxManifoldPoints> kept{};
  EXPECT_EQ(reduce_manifold(Vec3::UnitZ(), points, kept), 3);
  EXPECT_EQ(kept[0], 0);
  EXPECT_EQ(kept[2], 2);
}

TEST(ManifoldReduction, RegularOctagonGivesTheDeepestAndTheInscribedSquare) {
  std::vector<ContactPoint> points;
  for (int i = 0; i < 8; ++i) {
    const Real angle = 2 * std::numbers::pi * i / 8 + 0.1;
    points.push_back({Vec3(std::cos(angle), std::sin(angle), 0), i == 3 ? 0.02 : 0.01, {}});
  }
  std::array<int, kMaxManifoldPoints> kept{};
  ASSERT_EQ(reduce_manifold(Vec3::UnitZ(), points, kept), 4);
  EXPECT_EQ(kept[0], 3);  // the deepest
  EXPECT_EQ(kept[1], 7);  // opposite it
  std::vector<int> sorted(kept.begin(), kept.end());
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, (std::vector<int>{1, 3, 5, 7}));
}

TEST(ManifoldReduction, RandomCloudsKeepTheDeepestAndNearlyTheLargestArea) {
  Rng rng(301);
  Real worst_ratio = 1;
  for (int trial = 0; trial < 400; ++trial) {
    const int count = 5 + trial % 12;
    // Points in a tilted plane, with depths that vary a little.
    const Quat tilt = random_rotation(rng);
    const Vec3 normal = tilt * Vec3::UnitZ();
    std::vector<ContactPoint> points;
    std::vector<Vec3> flat;
    for (int i = 0; i < count; ++i) {
      const Vec3 p(uniform(rng, -1, 1), uniform(rng, -0.6, 0.6), 0);
      flat.push_back(p);
      points.push_back({tilt * p + normal * uniform(rng, -1e-3, 1e-3), uniform(rng, 0, 0.01), {}});
    }
    std::array<int, kMaxManifoldPoints> kept{};
    ASSERT_EQ(reduce_manifold(normal, points, kept), 4);
    // Distinct.
    std::vector<int> sorted(kept.begin(), kept.end());
    std::sort(sorted.begin(), sorted.end());
    ASSERT_TRUE(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
    // 1: the deepest.
    const int deepest = int(std::max_element(points.begin(), points.end(),
                                             [](const ContactPoint& a, const ContactPoint& b) {
                                               return a.depth < b.depth;
                                             }) -
                            points.begin());
    EXPECT_EQ(kept[0], deepest);
    // 2: the farthest from it in the contact plane.
    Real farthest = 0;
    for (int i = 0; i < count; ++i)
      farthest = std::max(farthest, (flat[i] - flat[deepest]).norm());
    EXPECT_NEAR((flat[kept[1]] - flat[deepest]).norm(), farthest, 1e-12);
    // The area compared with the best four that include the deepest, found by trying all.
    Real best = 0;
    for (int i = 0; i < count; ++i) {
      for (int j = i + 1; j < count; ++j) {
        for (int k = j + 1; k < count; ++k) {
          if (deepest == i || deepest == j || deepest == k)
            continue;
          best = std::max(best, hull_area_xy({flat[deepest], flat[i], flat[j], flat[k]}));
        }
      }
    }
    const Real area = hull_area_xy({flat[kept[0]], flat[kept[1]], flat[kept[2]], flat[kept[3]]});
    ASSERT_GT(best, 0);
    worst_ratio = std::min(worst_ratio, area / best);
  }
  std::printf("[ stats    ] reduction: worst kept area / best area with the deepest = %.3f\n",
              worst_ratio);
  // The greedy choice (deepest, farthest, largest triangle, largest addition) is not optimal,
  // but never far from it on these clouds.
  EXPECT_GT(worst_ratio, 0.7);
}

}  // namespace
}  // namespace tumble::testing
