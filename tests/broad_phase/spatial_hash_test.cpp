// Spatial hash against brute force: the shared random layouts with the automatic cell size and
// with cells much smaller and much larger than the boxes, a box spanning 1000 cells, cells that
// collide in the hash, planes, queries between two builds, and the cell-size rule.
#include "collision/broad_phase/spatial_hash_broad_phase.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "collision/broad_phase/brute_force_broad_phase.hpp"
#include "tests/broad_phase/broad_phase_property.hpp"

namespace tumble::test {
namespace {

BroadPhaseFactory hash(SpatialHashSettings settings = {}) {
  return [settings] { return std::make_unique<SpatialHashBroadPhase>(settings); };
}

// Two structures fed the same calls; compare() checks pairs, box queries and ray casts.
struct HashLockstep {
  SpatialHashBroadPhase tested;
  BruteForceBroadPhase reference;
  std::vector<ProxyPair> got, want;
  std::vector<std::int32_t> got_ids, want_ids;

  explicit HashLockstep(const SpatialHashSettings& s = {}) : tested(s) {}
  void insert(int id, const Aabb& b, bool is_static = false) {
    tested.insert(id, b, is_static);
    reference.insert(id, b, is_static);
  }
  void update(int id, const Aabb& b) {
    tested.update(id, b);
    reference.update(id, b);
  }
  void remove(int id) {
    tested.remove(id);
    reference.remove(id);
  }
  void compare_queries(const std::vector<Aabb>& probes, const std::vector<Vec3>& ray_points) {
    for (const Aabb& p : probes) {
      tested.query(p, got_ids);
      reference.query(p, want_ids);
      EXPECT_EQ(got_ids, want_ids);
    }
    for (std::size_t i = 0; i + 1 < ray_points.size(); i += 2) {
      const Vec3 d = ray_points[i + 1] - ray_points[i];
      tested.ray_cast(ray_points[i], d, 1, got_ids);
      reference.ray_cast(ray_points[i], d, 1, want_ids);
      EXPECT_EQ(got_ids, want_ids);
    }
  }
  // Returns the number of pairs, so a caller can check the case was not trivial.
  std::size_t compare(const std::vector<Aabb>& probes, const std::vector<Vec3>& ray_points) {
    tested.find_pairs(got);
    reference.find_pairs(want);
    EXPECT_EQ(got, want);
    compare_queries(probes, ray_points);
    return want.size();
  }
};

TEST(SpatialHash, AgreesWithBruteForceInEveryLayout) {
  check_every_layout(hash());
}

TEST(SpatialHash, AgreesWithBruteForceWithManyBodies) {
  check_every_layout(hash(), {.bodies = 2000, .steps = 60});
}

// Cells a tenth of the typical box (boxes span hundreds to thousands of cells, kept in the
// table), and cells 25 times the typical box (hundreds of boxes share a cell).
TEST(SpatialHash, CellsMuchSmallerThanTheBoxesAgree) {
  check_every_layout(hash({.cell_size = 0.25, .max_cells_per_box = 20000}),
                     {.bodies = 150, .steps = 40});
}

TEST(SpatialHash, CellsMuchLargerThanTheBoxesAgree) {
  check_every_layout(hash({.cell_size = 50}), {.bodies = 300, .steps = 100});
}

// One box over 10 x 10 x 10 = 1000 cells (kept in the table), a second one over 729 of the same
// cells, and small boxes inside both: every pair once, however many cells its boxes share.
TEST(SpatialHash, BoxSpanning1000CellsReportsEachPairOnce) {
  HashLockstep s({.cell_size = 1, .max_cells_per_box = 4096});
  s.insert(0, {Vec3::Constant(0.5), Vec3::Constant(9.5)});       // cells 0..9 on each axis
  s.insert(1, {Vec3::Constant(1.5), Vec3::Constant(9.25)});      // cells 1..9
  s.insert(2, {Vec3::Constant(-5), Vec3::Constant(0.5)}, true);  // touches box 0 at a corner
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<Real> u(-1, 11);
  for (int i = 3; i < 200; ++i) {
    const Vec3 c(u(rng), u(rng), u(rng));
    s.insert(i, {c - Vec3::Constant(0.3), c + Vec3::Constant(0.7)}, i % 5 == 0);
  }
  EXPECT_GT(s.compare({{Vec3::Constant(2), Vec3::Constant(3)}}, {Vec3(-1, 5, 5), Vec3(11, 5, 5)}),
            150u);
  EXPECT_EQ(s.tested.oversized_count(), 0u);
  EXPECT_GE(s.tested.entry_count(), 1000u + 729u);
  const auto& pairs = s.got;
  EXPECT_EQ(std::adjacent_find(pairs.begin(), pairs.end()), pairs.end());
  EXPECT_NE(std::find(pairs.begin(), pairs.end(), ProxyPair{0, 1}), pairs.end());
  EXPECT_NE(std::find(pairs.begin(), pairs.end(), ProxyPair{0, 2}), pairs.end());
  // With the default limit (256 cells) the same two boxes go to the oversized list instead.
  SpatialHashBroadPhase limited({.cell_size = 1});
  limited.insert(0, {Vec3::Constant(0.5), Vec3::Constant(9.5)}, false);
  limited.insert(1, {Vec3::Constant(1.5), Vec3::Constant(9.25)}, false);
  limited.insert(2, {Vec3::Constant(3), Vec3::Constant(3.5)}, false);
  std::vector<ProxyPair> out;
  limited.find_pairs(out);
  EXPECT_EQ(limited.oversized_count(), 2u);
  EXPECT_EQ(out, (std::vector<ProxyPair>{{0, 1}, {0, 2}, {1, 2}}));
}

// Cells whose x differs by 2^20 land in the same bucket for every table of up to 2^20 buckets
// (the Teschner hash is linear mod a power of two): boxes there must not pair.
TEST(SpatialHash, HashCollisionsMakeNoFalsePairs) {
  HashLockstep s({.cell_size = 1});
  const Real far = Real(1 << 20);
  for (int i = 0; i < 50; ++i) {
    const Vec3 c(0.5 + (i % 2) * far, 0.5 + i / 2 * 3, 0.5);
    s.insert(i, {c - Vec3::Constant(0.25), c + Vec3::Constant(0.25)});
  }
  // And a real pair in one of those cells, and one across a cell face.
  s.insert(50, {Vec3(0.5, 0.5, 0.5), Vec3(0.9, 0.9, 0.9)});
  s.insert(51, {Vec3(far + 0.75, 0.5, 0.5), Vec3(far + 1.5, 0.6, 0.6)});
  EXPECT_EQ(s.compare({{Vec3::Zero(), Vec3::Constant(1)}}, {Vec3(0, 0.5, 0.5), Vec3(2, 0.5, 0.5)}),
            2u);
  EXPECT_LT(s.tested.bucket_count(), std::size_t(1) << 20);
  EXPECT_GE(s.tested.bucket_count(), 2 * s.tested.occupied_cells());
  EXPECT_EQ(s.tested.occupied_cells(), 50u + 1u);  // 50 cells, and box 51's second cell
}

// A ground plane (x, y infinite, z in (-inf, 0]), an infinite wall and an everything-box among
// finite boxes that fall through the plane, rest exactly on it, and leave it.
TEST(SpatialHash, InfiniteBoxesAgree) {
  HashLockstep s;
  s.insert(1000, {Vec3(-kInf, -kInf, -kInf), Vec3(kInf, kInf, 0)}, true);
  s.insert(1001, {Vec3(5, -kInf, -kInf), Vec3(kInf, kInf, kInf)}, false);
  s.insert(1002, {Vec3(-kInf, -kInf, -kInf), Vec3(kInf, kInf, kInf)}, true);
  std::vector<Aabb> boxes;
  for (int i = 0; i < 100; ++i) {
    const Vec3 c(i % 10 - 4, i / 10 - 4, Real(i % 7) - 2);
    boxes.push_back({c - Vec3::Constant(0.5), c + Vec3::Constant(0.5)});
    s.insert(i, boxes.back());
  }
  const std::vector<Aabb> probes = {{Vec3(-1, -1, -1), Vec3(1, 1, 1)},
                                    {Vec3(-kInf, 0, 0), Vec3(kInf, 0, 0)},
                                    {Vec3(6, 0, 0.5), Vec3(7, 1, 1)}};
  const std::vector<Vec3> rays = {Vec3(0, 0, 5), Vec3(0, 0, -5), Vec3(-9, 0, 0.5),
                                  Vec3(9, 0.1, 0.5)};
  EXPECT_GT(s.compare(probes, rays), 100u);
  EXPECT_EQ(s.tested.oversized_count(), 3u);
  for (int step = 0; step < 30; ++step) {
    for (int i = 0; i < 100; ++i) {
      const Vec3 d(Real(0.25) * ((i + step) % 3 - 1), 0, -0.25);
      boxes[i] = {boxes[i].min + d, boxes[i].max + d};
      s.update(i, boxes[i]);
    }
    if (step == 10)
      s.update(1001, {Vec3(-kInf, -kInf, 2), Vec3(kInf, kInf, kInf)});
    if (step == 20)
      s.remove(1002);
    EXPECT_GT(s.compare(probes, rays), 50u) << "step " << step;
    if (::testing::Test::HasFailure())
      return;
  }
}

// Queries asked after updates, inserts and removes but before the next find_pairs (the table
// is stale): the changed boxes must be seen where they are now, removed ones not at all.
TEST(SpatialHash, QueriesBetweenBuildsSeeTheCurrentBoxes) {
  HashLockstep s;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<Real> u(-10, 10);
  std::vector<Aabb> boxes;
  for (int i = 0; i < 300; ++i) {
    const Vec3 c(u(rng), u(rng), u(rng));
    boxes.push_back({c - Vec3::Constant(1), c + Vec3::Constant(1)});
    s.insert(i, boxes.back());
  }
  std::vector<Aabb> probes;
  std::vector<Vec3> rays;
  for (int q = 0; q < 20; ++q) {
    const Vec3 c(u(rng), u(rng), u(rng));
    probes.push_back({c - Vec3::Constant(2), c + Vec3::Constant(2)});
    rays.push_back(Vec3(u(rng), u(rng), u(rng)));
  }
  s.compare_queries(probes, rays);  // before any build
  for (int step = 0; step < 10; ++step) {
    s.compare(probes, rays);
    for (int i = step; i < 300; i += 3) {
      const Vec3 c(u(rng), u(rng), u(rng));
      boxes[i] = {c - Vec3::Constant(1), c + Vec3::Constant(1)};
      s.update(i, boxes[i]);
    }
    s.remove(step * 7);
    s.insert(step * 7, boxes[step * 7], step % 2 == 0);
    s.remove(step * 7 + 1);
    s.insert(300 + step, boxes[step * 7 + 1]);  // likely reuses the slot just freed
    s.compare_queries(probes, rays);
    s.remove(300 + step);
    s.insert(step * 7 + 1, boxes[step * 7 + 1]);
  }
}

// h = 2 r, r the mean half-diagonal: set at the first find_pairs, kept while that mean stays
// within a factor 2 of the one it was derived from, derived again past that.
TEST(SpatialHash, AutomaticCellSizeFollowsTheMeanRadius) {
  SpatialHashBroadPhase h;
  std::vector<ProxyPair> out;
  for (int i = 0; i < 100; ++i)
    h.insert(i, {Vec3(i * 3, 0, 0), Vec3(i * 3 + 2, 4, 4)}, false);  // diagonal 6
  h.find_pairs(out);
  EXPECT_DOUBLE_EQ(h.cell_size(), 6);
  for (int i = 0; i < 100; ++i)
    h.update(i, {Vec3(i * 3, 0, 0), Vec3(i * 3 + 3, 6, 6)});  // diagonal 9: x1.5, kept
  h.find_pairs(out);
  EXPECT_DOUBLE_EQ(h.cell_size(), 6);
  for (int i = 0; i < 100; ++i)
    h.update(i, {Vec3(i * 3, 0, 0), Vec3(i * 3 + 5, 10, 10)});  // diagonal 15: x2.5, re-derived
  h.find_pairs(out);
  EXPECT_DOUBLE_EQ(h.cell_size(), 15);
  EXPECT_EQ(out.size(), 99u);
  SpatialHashBroadPhase fixed({.cell_size = 0.5});
  fixed.insert(0, {Vec3::Zero(), Vec3::Constant(4)}, false);
  fixed.find_pairs(out);
  EXPECT_DOUBLE_EQ(fixed.cell_size(), 0.5);
}

}  // namespace
}  // namespace tumble::test
