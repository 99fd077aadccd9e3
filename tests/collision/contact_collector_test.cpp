// The contact collector (collision/narrow_phase/pairs/contact_collector.hpp) merges points closer
// than its merge distance, keeping the deepest: a box corner on a mesh vertex where several
// triangles meet gives one contact per triangle a hair apart, and the solver must see one row
// there, not four copies of it. Checked on the corner case and on thousands of random candidate
// sets (fixed seed) against brute force: no two kept points closer than the distance, the deepest
// candidate always kept.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "collision/narrow_phase/pairs/contact_collector.hpp"

namespace tumble::test {
namespace {

using detail::ContactCollector;

TEST(ContactCollector, ACornerOnAMeshVertexIsOnePoint) {
  const Vec3 up = Vec3::UnitZ();
  ContactCollector collector;
  // Four triangles around a vertex at the origin each report the corner, a hair apart.
  const Real depths[4] = {0.010, 0.012, 0.011, 0.0105};
  for (int k = 0; k < 4; ++k)
    collector.add(up, Vec3(1e-5 * k, -1e-5 * k, 0), depths[k], {std::uint16_t(k), 0});
  // Three more corners of the box, far away.
  collector.add(up, Vec3(1, 0, 0), 0.009, {10, 0});
  collector.add(up, Vec3(1, 1, 0), 0.008, {11, 0});
  collector.add(up, Vec3(0, 1, 0), 0.007, {12, 0});
  Manifold merged;
  ASSERT_EQ(collector.finish(0.005, 1e-3, merged), 4);
  int near_origin = 0;
  for (int i = 0; i < merged.count; ++i) {
    if (merged.points[i].position.head<2>().norm() < 1e-3) {
      ++near_origin;
      EXPECT_DOUBLE_EQ(merged.points[i].depth, 0.012);  // the deepest of the four
    }
  }
  EXPECT_EQ(near_origin, 1);
}

TEST(ContactCollector, RandomSetsKeepTheDeepestAndNoTwoPointsClose) {
  std::mt19937_64 rng(20261125);
  std::uniform_real_distribution<Real> unit(0, 1);
  const Vec3 up = Vec3::UnitZ();
  for (int trial = 0; trial < 4000; ++trial) {
    ContactCollector collector;
    const int n = 1 + int(unit(rng) * 20);
    // Clusters: each candidate lands near one of a few centres, some within the merge distance.
    const Real merge = 0.01;
    std::vector<Vec3> centres;
    for (int c = 0; c < 1 + int(unit(rng) * 5); ++c)
      centres.emplace_back(unit(rng), unit(rng), 0);
    Real deepest = -1;
    for (int k = 0; k < n; ++k) {
      const Vec3 centre = centres[std::size_t(unit(rng) * Real(centres.size()))];
      const Vec3 p = centre + Vec3(unit(rng) - 0.5, unit(rng) - 0.5, 0) * (3 * merge * unit(rng));
      const Real depth = 0.02 * unit(rng) - 0.004;
      collector.add(up, p, depth, {std::uint16_t(k), 0});
      deepest = std::max(deepest, depth);
    }
    Manifold out;
    const int count = collector.finish(0.005, merge, out);
    ASSERT_GE(count, 1) << "trial " << trial;
    ASSERT_LE(count, 4);
    Real kept_deepest = -1;
    for (int i = 0; i < count; ++i) {
      kept_deepest = std::max(kept_deepest, out.points[i].depth);
      for (int j = 0; j < i; ++j) {
        ASSERT_GE((out.points[i].position - out.points[j].position).norm(), merge)
            << "trial " << trial;
      }
    }
    EXPECT_DOUBLE_EQ(kept_deepest, deepest) << "trial " << trial;
  }
}

}  // namespace
}  // namespace tumble::test
