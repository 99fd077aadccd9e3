// Hierarchical grid: the shared property suite, plus the level rule, the 2 x 2 x 2 bound, cell
// faces, base cells far from the box sizes, coordinates past the cell clamp, the symmetric
// (static finer than dynamic) lookups and re-deriving s_0.
#include <cmath>
#include <limits>
#include <random>

#include "collision/broad_phase/hierarchical_grid_broad_phase.hpp"
#include "tests/broad_phase/broad_phase_property.hpp"

namespace tumble::test {
namespace {

TEST(HierarchicalGrid, AgreesWithBruteForceInEveryLayout) {
  check_every_layout([] { return std::make_unique<HierarchicalGridBroadPhase>(); });
}

TEST(HierarchicalGrid, AgreesWithBruteForceWithManyBodies) {
  check_every_layout([] { return std::make_unique<HierarchicalGridBroadPhase>(); },
                     {.bodies = 2000, .steps = 60});
}

TEST(HierarchicalGrid, InfiniteBoxAmongFiniteOnes) {
  HierarchicalGridBroadPhase grid;
  BruteForceBroadPhase reference;
  const Aabb ground{Vec3(-kInf, -kInf, -kInf), Vec3(kInf, kInf, 0)};
  grid.insert(0, ground, true);
  reference.insert(0, ground, true);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<Real> u(-10, 10);
  for (int i = 1; i <= 200; ++i) {
    const Vec3 c(u(rng), u(rng), i % 3 == 0 ? Real(0.5) : u(rng));  // every third touches z = 0
    grid.insert(i, cube(c, 0.05 * (1 + i % 20)), false);
    reference.insert(i, cube(c, 0.05 * (1 + i % 20)), false);
  }
  const Aabb slab{Vec3(-kInf, 2, -kInf), Vec3(kInf, 3, kInf)};
  grid.insert(500, slab, false);
  reference.insert(500, slab, false);
  const std::size_t pairs = expect_same(grid, reference, 1, 12);
  EXPECT_GT(pairs, 60u);
  EXPECT_EQ(grid.oversized_count(), 2);
  EXPECT_EQ(grid.level_of(0), -1);
  for (int step = 0; step < 20; ++step) {
    for (int i = 1; i <= 200; i += 7) {
      const Vec3 c(Real(i % 17) - 8, Real(i % 13) - 6, Real(2) - Real(0.2) * step);
      grid.update(i, cube(c, 0.5));
      reference.update(i, cube(c, 0.5));
    }
    expect_same(grid, reference, 100 + step, 12);
  }
}

// l = ceil(log2(r / s0)), 0 for r <= s0, decided exactly at the powers of two.
TEST(HierarchicalGrid, LevelRuleOnKnownSizes) {
  using H = HierarchicalGridBroadPhase;
  EXPECT_EQ(H::level_for_size(0, 1), 0);
  EXPECT_EQ(H::level_for_size(0.5, 1), 0);
  EXPECT_EQ(H::level_for_size(1, 1), 0);
  EXPECT_EQ(H::level_for_size(std::nextafter(1.0, 2.0), 1), 1);
  EXPECT_EQ(H::level_for_size(2, 1), 1);
  EXPECT_EQ(H::level_for_size(3, 1), 2);
  EXPECT_EQ(H::level_for_size(4, 1), 2);
  EXPECT_EQ(H::level_for_size(std::nextafter(4.0, 5.0), 1), 3);
  EXPECT_EQ(H::level_for_size(1000, 1), 10);  // 512 < 1000 <= 1024
  EXPECT_EQ(H::level_for_size(1024, 1), 10);
  EXPECT_EQ(H::level_for_size(1e-3, std::ldexp(1.0, -10)), 1);  // 1e-3 / 2^-10 = 1.024
  // An s0 that is not a power of two: 0.3 * 2 = 0.6 exactly in binary.
  EXPECT_EQ(H::level_for_size(0.6, 0.3), 1);
  EXPECT_EQ(H::level_for_size(std::nextafter(0.6, 1.0), 0.3), 2);
  EXPECT_EQ(H::level_for_size(1e30, 1), 100);  // 2^99 < 1e30 <= 2^100: past the last level
  EXPECT_GE(H::level_for_size(1e300, 1e-300), H::kMaxLevels);  // r / s0 overflows to inf
  // Just above s0 * 2^k goes up a level, whatever the mantissa of s0.
  for (const Real s0 : {0.3, 0.99999999, 1.5, 1.9999999999999998, 1e-7}) {
    for (int k = 0; k < 6; ++k) {
      EXPECT_EQ(H::level_for_size(std::ldexp(s0, k), s0), k) << s0 << " " << k;
      EXPECT_EQ(H::level_for_size(std::nextafter(std::ldexp(s0, k), 1e9), s0), k + 1)
          << s0 << " " << k;
    }
  }

  // In the structure: s0 derived as the power of two at or above the smallest size (0.3 -> 0.5),
  // r the largest extent of each box.
  HierarchicalGridBroadPhase grid;
  grid.insert(0, {Vec3(0, 0, 0), Vec3(0.3, 0.1, 0.1)}, false);   // r = 0.3 -> level 0
  grid.insert(1, {Vec3(0, 0, 0), Vec3(0.1, 0.5, 0.1)}, false);   // r = 0.5 -> level 0
  grid.insert(2, {Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.75)}, false);  // r = 0.75 -> level 1
  grid.insert(3, {Vec3(5, 5, 5), Vec3(5 + 3.9, 6, 6)}, true);    // r = 3.9 -> level 3 (4)
  grid.insert(4, {Vec3(5, 5, 5), Vec3(5 + 1e14, 6, 6)}, false);  // past level 47: oversized
  grid.insert(5, {Vec3(-kInf, 0, 0), Vec3(0, 1, 1)}, true);      // infinite: oversized
  std::vector<ProxyPair> pairs;
  grid.find_pairs(pairs);
  EXPECT_EQ(grid.base_cell(), 0.5);
  EXPECT_EQ(grid.level_of(0), 0);
  EXPECT_EQ(grid.level_of(1), 0);
  EXPECT_EQ(grid.level_of(2), 1);
  EXPECT_EQ(grid.level_of(3), 3);
  EXPECT_EQ(grid.level_of(4), -1);
  EXPECT_EQ(grid.level_of(5), -1);
  EXPECT_EQ(grid.level_of(6), -1);  // unknown id
  EXPECT_EQ(pairs,
            (std::vector<ProxyPair>{{0, 1}, {0, 2}, {0, 5}, {1, 2}, {1, 5}, {2, 5}, {3, 4}}));
}

// Whatever the box, on its level it overlaps at most 2 x 2 x 2 cells.
TEST(HierarchicalGrid, EveryBoxSpansAtMostTwoCellsPerAxisOfItsLevel) {
  HierarchicalGridBroadPhase grid;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<Real> u(-50, 50);
  std::uniform_real_distribution<Real> exponent(-3, 2);
  std::vector<Aabb> boxes;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 c(u(rng), u(rng), u(rng));
    const Vec3 h(std::pow(10, exponent(rng)), std::pow(10, exponent(rng)),
                 std::pow(10, exponent(rng)));
    // Every tenth box lands exactly on powers of two: the case where s_l = r.
    boxes.push_back(i % 10 == 0 ? Aabb{Vec3::Constant(std::ldexp(1.0, i % 7)),
                                       Vec3::Constant(std::ldexp(1.0, i % 7 + 1))}
                                : Aabb{c - h, c + h});
    grid.insert(i, boxes.back(), i % 3 == 0);
  }
  std::vector<ProxyPair> pairs;
  grid.find_pairs(pairs);
  int levels_used = 0;
  std::vector<bool> used(HierarchicalGridBroadPhase::kMaxLevels, false);
  for (int i = 0; i < 2000; ++i) {
    const int l = grid.level_of(i);
    ASSERT_GE(l, 0);
    const Real s = std::ldexp(grid.base_cell(), l);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(std::floor(boxes[i].max[k] / s) - std::floor(boxes[i].min[k] / s), 1)
          << "box " << i << " axis " << k;
    }
    EXPECT_GE(s, grid_detail::largest_extent(boxes[i]));
    if (!used[l])
      ++levels_used;
    used[l] = true;
  }
  EXPECT_GE(levels_used, 12);  // sizes over 4 to 5 orders of magnitude
}

// Boxes whose faces lie on cell faces of several levels (s0 = 1: faces at integers), touching
// face to face, edge to edge and corner to corner across levels.
TEST(HierarchicalGrid, BoxesExactlyOnCellBoundaries) {
  HierarchicalGridBroadPhase grid(1.0);
  BruteForceBroadPhase reference;
  int id = 0;
  for (int x = 0; x < 8; ++x) {
    for (int y = 0; y < 8; ++y) {
      const Real size = Real(1 << ((x + 2 * y) % 3));  // 1, 2 or 4: levels 0, 1, 2 exactly
      const Aabb b{Vec3(x, y, 0), Vec3(x + size, y + size, size)};
      grid.insert(id, b, id % 5 == 0);
      reference.insert(id, b, id % 5 == 0);
      ++id;
    }
  }
  const std::size_t pairs = expect_same(grid, reference, 2, 8);
  EXPECT_GT(pairs, 300u);
  EXPECT_EQ(grid.level_of(0), 0);  // x = 0, y = 0: size 1
  EXPECT_EQ(grid.level_of(8), 1);  // x = 1, y = 0: size 2
  EXPECT_EQ(grid.level_of(1), 2);  // x = 0, y = 1: size 4
  std::vector<std::int32_t> got, want;
  const Aabb probe{Vec3(2, 2, 1), Vec3(4, 4, 1)};
  grid.query(probe, got);
  reference.query(probe, want);
  EXPECT_EQ(got, want);
  EXPECT_FALSE(want.empty());
  grid.ray_cast(Vec3(-1, 2, 1), Vec3(20, 0, 0), 1, got);
  reference.ray_cast(Vec3(-1, 2, 1), Vec3(20, 0, 0), 1, want);
  EXPECT_EQ(got, want);
  EXPECT_FALSE(want.empty());
  // [-1e-17, 1]: the extent rounds to exactly 1 = s_0 (level 0), but the box touches cells -1,
  // 0 and 1 there; it moves up to level 1, where it spans 2.
  HierarchicalGridBroadPhase rounding(1.0);
  rounding.insert(0, {Vec3(-1e-17, 0, 0), Vec3(1, 0.5, 0.5)}, false);
  rounding.insert(1, {Vec3(0.9, 0, 0), Vec3(1.5, 0.5, 0.5)}, false);
  std::vector<ProxyPair> pairs_found;
  rounding.find_pairs(pairs_found);
  EXPECT_EQ(rounding.level_of(0), 1);
  EXPECT_EQ(pairs_found, (std::vector<ProxyPair>{{0, 1}}));
}

// s0 1000x smaller than the boxes (they sit ten levels up) and 1000x larger (all on level 0,
// all in a handful of cells).
TEST(HierarchicalGrid, BaseCellMuchSmallerOrLargerThanBoxes) {
  for (const Real s0 : {1e-3, 1000.0}) {
    SCOPED_TRACE(s0);
    const PropertyOptions options{.bodies = 200, .steps = 40};
    for (Layout layout : {Layout::uniform, Layout::mixed_sizes, Layout::one_huge}) {
      check_against_brute_force([s0] { return std::make_unique<HierarchicalGridBroadPhase>(s0); },
                                layout, options);
    }
    HierarchicalGridBroadPhase grid(s0);
    grid.insert(0, cube(Vec3::Zero(), 1), false);
    grid.insert(1, cube(Vec3(1.5, 0, 0), 1), false);
    std::vector<ProxyPair> pairs;
    grid.find_pairs(pairs);
    EXPECT_EQ(pairs, (std::vector<ProxyPair>{{0, 1}}));
    EXPECT_EQ(grid.base_cell(), s0);
    EXPECT_EQ(grid.level_of(0), s0 < 1 ? 11 : 0);  // 2 / 1e-3 = 2000 <= 2^11
  }
}

// Boxes spread over 1e6 m with s0 = 1 micrometre: tiny boxes far out have cell coordinates past
// the +-2^30 clamp and share the clamped boundary cells; the hash tables still hold only the
// cells in use, and the answer stays exact.
TEST(HierarchicalGrid, FarSpreadWithTinyCellsStaysExact) {
  HierarchicalGridBroadPhase grid(1e-6);
  BruteForceBroadPhase reference;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<Real> spread(-5e5, 5e5);
  std::uniform_real_distribution<Real> near(-1, 1);
  int id = 0;
  std::vector<Vec3> centres;
  for (int cluster = 0; cluster < 40; ++cluster) {
    centres.emplace_back(spread(rng), spread(rng), spread(rng));
    for (int i = 0; i < 10; ++i, ++id) {
      const Real half = i % 2 == 0 ? 0.4 : 2e-7;  // level 20 or level 0
      const Aabb b = cube(centres.back() + Real(i % 4 == 1 ? 0 : 1) * Vec3(near(rng), 0, 0), half);
      grid.insert(id, b, id % 7 == 0);
      reference.insert(id, b, id % 7 == 0);
    }
  }
  const std::size_t pairs = expect_same(grid, reference, 4, 5e5, 1e4);
  EXPECT_GT(pairs, 40u);
  EXPECT_EQ(grid.level_of(1), 0);
  std::vector<std::int32_t> got, want;
  for (const Vec3& c : centres) {
    grid.query(cube(c, 0.5), got);
    reference.query(cube(c, 0.5), want);
    EXPECT_EQ(got, want);
    EXPECT_FALSE(want.empty());
    grid.ray_cast(c - Vec3(3, 2, 1), Vec3(6, 4, 2), 1, got);
    reference.ray_cast(c - Vec3(3, 2, 1), Vec3(6, 4, 2), 1, want);
    EXPECT_EQ(got, want);
    EXPECT_FALSE(want.empty());
  }
}

// A dynamic box far coarser than many static boxes finds them by looking down their levels:
// through their cells when it covers few, by testing them all when it covers many.
TEST(HierarchicalGrid, DynamicBoxFindsFinerStaticBoxes) {
  HierarchicalGridBroadPhase grid;
  BruteForceBroadPhase reference;
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<Real> u(-10, 10);
  int id = 0;
  for (; id < 3000; ++id) {
    const Aabb b = cube(Vec3(u(rng), u(rng), u(rng)), id % 2 == 0 ? 0.05 : 0.4);
    grid.insert(id, b, true);
    reference.insert(id, b, true);
  }
  // s0 = 0.125 (r = 0.1). Half-size 3: level 6, covers 49^3 level-0 cells, more than the 1500
  // boxes there: tests them all. Half-size 0.3: level 3, covers about 6^3 level-0 cells: looks
  // them up.
  grid.insert(id, cube(Vec3::Zero(), 3), false);
  reference.insert(id, cube(Vec3::Zero(), 3), false);
  grid.insert(id + 1, cube(Vec3(5, 0, 0), 0.3), false);
  reference.insert(id + 1, cube(Vec3(5, 0, 0), 0.3), false);
  const std::size_t pairs = expect_same(grid, reference, 5, 10);
  EXPECT_GT(pairs, 60u);
  EXPECT_EQ(grid.base_cell(), 0.125);
  EXPECT_EQ(grid.level_of(id), 6);
  EXPECT_EQ(grid.level_of(id + 1), 3);
  for (int step = 0; step < 10; ++step) {
    const Aabb b = cube(Vec3(Real(step) - 5, Real(step) * 0.5, 0), 3);
    grid.update(id, b);
    reference.update(id, b);
    const Aabb c = cube(Vec3(5, Real(step) * 0.3, 0), 0.3);
    grid.update(id + 1, c);
    reference.update(id + 1, c);
    expect_same(grid, reference, 6 + step, 10);
  }
}

// When the smallest box shrinks far below s0, s0 is re-derived; the answer is exact throughout.
TEST(HierarchicalGrid, ReDerivesBaseCellWhenBoxesShrink) {
  HierarchicalGridBroadPhase grid;
  BruteForceBroadPhase reference;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<Real> u(-10, 10);
  std::vector<Vec3> centres;
  for (int i = 0; i < 300; ++i) {
    centres.emplace_back(u(rng), u(rng), u(rng));
    grid.insert(i, cube(centres.back(), 0.7), i % 10 == 0);
    reference.insert(i, cube(centres.back(), 0.7), i % 10 == 0);
  }
  expect_same(grid, reference, 6, 12);
  EXPECT_EQ(grid.base_cell(), 2.0);  // r = 1.4
  const int before = grid.base_derivations();
  for (int i = 1; i < 300; i += 2) {
    const Aabb b = cube(centres[i], 0.01);
    grid.update(i, b);
    reference.update(i, b);
  }
  expect_same(grid, reference, 7, 12);
  EXPECT_GT(grid.base_derivations(), before);
  EXPECT_EQ(grid.base_cell(), 1.0 / 32);  // r = 0.02
  // Queries between updates and find_pairs are exact too.
  for (int i = 1; i < 300; i += 3) {
    grid.update(i, cube(centres[i] * 0.5, 0.3));
    reference.update(i, cube(centres[i] * 0.5, 0.3));
  }
  std::vector<std::int32_t> got, want;
  grid.query(cube(Vec3::Zero(), 5), got);
  reference.query(cube(Vec3::Zero(), 5), want);
  EXPECT_EQ(got, want);
  EXPECT_FALSE(want.empty());
  expect_same(grid, reference, 8, 12);
}

}  // namespace
}  // namespace tumble::test
