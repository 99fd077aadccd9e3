// LinearBvhBroadPhase with both builders: the shared property suite against brute force, Morton
// codes of known points, the Karras topology of the paper's own example, the structure of the
// hierarchies both builders produce, and infinite boxes.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "collision/broad_phase/linear_bvh_broad_phase.hpp"
#include "tests/broad_phase/broad_phase_property.hpp"

namespace tumble::test {
namespace {

using Builder = LinearBvhBroadPhase::Builder;

BroadPhaseFactory factory(Builder b) {
  return [b] { return std::make_unique<LinearBvhBroadPhase>(b); };
}

// ---- the shared contract -------------------------------------------------------------------

TEST(LinearBvhBroadPhase, MortonKarrasMatchesBruteForceInEveryLayout) {
  check_every_layout(factory(Builder::morton_karras));
}

TEST(LinearBvhBroadPhase, BinnedSahMatchesBruteForceInEveryLayout) {
  check_every_layout(factory(Builder::binned_sah));
}

// The large run once per structure; the builders share everything but the build, which the
// hierarchy tests below check on their own for both.
TEST(LinearBvhBroadPhase, MortonKarrasMatchesBruteForceWithTwoThousandBodies) {
  check_every_layout(factory(Builder::morton_karras), {.bodies = 2000, .steps = 60, .seed = 7});
}

TEST(LinearBvhBroadPhase, BinnedSahMatchesBruteForceWithThousandBodies) {
  check_every_layout(factory(Builder::binned_sah), {.bodies = 1000, .steps = 30, .seed = 8});
}

// Planes (x, y unbounded, z below 0; static) and an unbounded dynamic slab among finite boxes,
// with a box switching between finite and infinite: equal to brute force throughout.
TEST(LinearBvhBroadPhase, InfiniteBoxesAmongFiniteOnes) {
  const Real inf = std::numeric_limits<Real>::infinity();
  for (const Builder builder : {Builder::morton_karras, Builder::binned_sah}) {
    LinearBvhBroadPhase bvh(builder);
    BruteForceBroadPhase brute;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<Real> u(-1, 1);
    const Aabb floor{Vec3(-inf, -inf, -inf), Vec3(inf, inf, 0)};
    const Aabb wall{Vec3(-inf, 9, -inf), Vec3(inf, inf, inf)};  // a second static plane
    const Aabb slab{Vec3(3, -inf, -inf), Vec3(4, inf, inf)};
    bvh.insert(0, floor, true);
    brute.insert(0, floor, true);
    bvh.insert(1, slab, false);
    brute.insert(1, slab, false);
    bvh.insert(2, wall, true);
    brute.insert(2, wall, true);
    std::vector<Aabb> boxes(200);
    for (int i = 3; i < 200; ++i) {
      const Vec3 c(8 * u(rng), 8 * u(rng), 3 * u(rng));
      boxes[i] = {c - Vec3::Constant(0.5), c + Vec3::Constant(0.5)};
      bvh.insert(i, boxes[i], i % 10 == 0);
      brute.insert(i, boxes[i], i % 10 == 0);
    }
    std::vector<ProxyPair> got, want;
    std::vector<std::int32_t> got_ids, want_ids;
    std::int64_t floor_pairs = 0;
    for (int step = 0; step < 60; ++step) {
      for (int i = 3; i < 200; ++i) {
        if (i % 10 == 0)
          continue;
        const Vec3 d(0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng));
        boxes[i] = {boxes[i].min + d, boxes[i].max + d};
        bvh.update(i, boxes[i]);
        brute.update(i, boxes[i]);
      }
      const Real x = 4 * std::sin(step * 0.1);
      const Aabb moved_slab{Vec3(x, -inf, -inf), Vec3(x + 1, inf, inf)};
      bvh.update(1, moved_slab);
      brute.update(1, moved_slab);
      if (step == 20) {
        bvh.update(5, slab);
        brute.update(5, slab);
      }
      if (step == 30) {
        bvh.update(5, boxes[5]);
        brute.update(5, boxes[5]);
      }
      bvh.find_pairs(got);
      brute.find_pairs(want);
      ASSERT_EQ(got, want) << "step " << step;
      for (const ProxyPair& p : want)
        floor_pairs += p.a == 0;
      const Aabb probe{Vec3(-2, -2, -1), Vec3(2, 2, 1)};
      bvh.query(probe, got_ids);
      brute.query(probe, want_ids);
      ASSERT_EQ(got_ids, want_ids);
      const Vec3 origin(8 * u(rng), 8 * u(rng), 4);
      const Vec3 dir(4 * u(rng), 4 * u(rng), -8);
      bvh.ray_cast(origin, dir, 1, got_ids);
      brute.ray_cast(origin, dir, 1, want_ids);
      ASSERT_EQ(got_ids, want_ids);
    }
    EXPECT_GT(floor_pairs, 500);
  }
}

// query() and ray_cast() between update() and find_pairs see the new boxes (they fall back to a
// scan while the hierarchies are stale).
TEST(LinearBvhBroadPhase, QueriesBetweenUpdateAndFindPairsSeeNewBoxes) {
  LinearBvhBroadPhase bvh;
  BruteForceBroadPhase brute;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<Real> u(-1, 1);
  std::vector<Aabb> boxes(300);
  for (int i = 0; i < 300; ++i) {
    const Vec3 c(12 * u(rng), 12 * u(rng), 12 * u(rng));
    boxes[i] = {c - Vec3::Constant(0.7), c + Vec3::Constant(0.7)};
    bvh.insert(i, boxes[i], i % 5 == 0);
    brute.insert(i, boxes[i], i % 5 == 0);
  }
  std::vector<ProxyPair> pairs;
  std::vector<std::int32_t> got, want;
  std::int64_t hits = 0;
  for (int step = 0; step < 20; ++step) {
    for (int i = 0; i < 300; ++i) {
      const Vec3 d = Vec3(u(rng), u(rng), u(rng)) * 2;
      boxes[i] = {boxes[i].min + d, boxes[i].max + d};
      bvh.update(i, boxes[i]);  // statics move too: the static hierarchy must be rebuilt
      brute.update(i, boxes[i]);
    }
    for (int q = 0; q < 10; ++q) {
      const Vec3 c(12 * u(rng), 12 * u(rng), 12 * u(rng));
      bvh.query({c - Vec3::Constant(3), c + Vec3::Constant(3)}, got);
      brute.query({c - Vec3::Constant(3), c + Vec3::Constant(3)}, want);
      ASSERT_EQ(got, want);
      hits += static_cast<std::int64_t>(want.size());
      const Vec3 dir(25 * u(rng), 25 * u(rng), 25 * u(rng));
      bvh.ray_cast(c, dir, 1, got);
      brute.ray_cast(c, dir, 1, want);
      ASSERT_EQ(got, want);
    }
    std::vector<ProxyPair> want_pairs;
    bvh.find_pairs(pairs);
    brute.find_pairs(want_pairs);
    ASSERT_EQ(pairs, want_pairs);
  }
  EXPECT_GT(hits, 300);
}

// A pile where every box overlaps every other: after the first call the structure switches to
// enumerating all pairs in order (no hierarchy can prune); the pairs stay exact, also when the
// pile spreads out again and the hierarchies come back.
TEST(LinearBvhBroadPhase, DensePileSwitchesToAllPairsAndBack) {
  for (const Builder builder : {Builder::morton_karras, Builder::binned_sah}) {
    LinearBvhBroadPhase bvh(builder);
    BruteForceBroadPhase brute;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<Real> u(-1, 1);
    std::vector<Aabb> boxes(150);
    for (int i = 0; i < 150; ++i) {
      const Vec3 c = 0.1 * Vec3(u(rng), u(rng), u(rng));
      boxes[i] = {c - Vec3::Constant(1), c + Vec3::Constant(1)};
      bvh.insert(i, boxes[i], i % 6 == 0);
      brute.insert(i, boxes[i], i % 6 == 0);
    }
    std::vector<ProxyPair> got, want;
    for (int step = 0; step < 12; ++step) {
      if (step >= 6) {  // spread out: far fewer pairs, back to the hierarchies
        for (int i = 0; i < 150; ++i) {
          if (i % 6 == 0)
            continue;
          const Vec3 d = 8 * Vec3(u(rng), u(rng), u(rng));
          boxes[i] = {boxes[i].min + d, boxes[i].max + d};
          bvh.update(i, boxes[i]);
          brute.update(i, boxes[i]);
        }
      }
      bvh.find_pairs(got);
      brute.find_pairs(want);
      ASSERT_EQ(got, want) << "step " << step;
    }
    EXPECT_GE(bvh.stats().dense, 4);
    EXPECT_GE(bvh.stats().builds, 4);
  }
}

// ---- Morton codes --------------------------------------------------------------------------

TEST(LinearBvhMorton, CodesOfKnownCells) {
  EXPECT_EQ(lbvh::morton_code(0, 0, 0), 0u);
  EXPECT_EQ(lbvh::morton_code(1, 0, 0), 0b100u);
  EXPECT_EQ(lbvh::morton_code(0, 1, 0), 0b010u);
  EXPECT_EQ(lbvh::morton_code(0, 0, 1), 0b001u);
  EXPECT_EQ(lbvh::morton_code(2, 0, 0), 0b100000u);
  EXPECT_EQ(lbvh::morton_code(3, 5, 6), 0b011'101'110u);  // x=011 y=101 z=110, interleaved
  EXPECT_EQ(lbvh::morton_code(1023, 1023, 1023), (1u << 30) - 1);
  EXPECT_EQ(lbvh::morton_code(512, 0, 0), 1u << 29);  // top bit of x is bit 29
  EXPECT_EQ(lbvh::morton_code(0, 0, 512), 1u << 27);
  EXPECT_EQ(lbvh::expand_bits_10(0x3ff), 0x09249249u);
  // Only 10 bits per axis: higher bits are ignored, not smeared into the other axes.
  EXPECT_EQ(lbvh::morton_code(1024, 0, 0), 0u);
}

TEST(LinearBvhMorton, CellsOfKnownPoints) {
  // Scene bounds [-10, 10] on an axis: 1024 cells of 20/1024.
  const Real lo = -10;
  const Real scale = 1024.0 / 20.0;
  EXPECT_EQ(lbvh::morton_cell(-10, lo, scale), 0u);
  EXPECT_EQ(lbvh::morton_cell(10, lo, scale), 1023u);  // the upper bound is clamped into range
  EXPECT_EQ(lbvh::morton_cell(0, lo, scale), 512u);
  EXPECT_EQ(lbvh::morton_cell(-10 + 20.0 / 1024 * 3.5, lo, scale), 3u);
  EXPECT_EQ(lbvh::morton_cell(-1e300, lo, scale), 0u);  // far outside, and NaN, clamp to 0
  EXPECT_EQ(lbvh::morton_cell(std::numeric_limits<Real>::quiet_NaN(), lo, scale), 0u);
  EXPECT_EQ(lbvh::morton_cell(5, 5, 0), 0u);  // flat axis
  // The point (0, 10, -10) in the cube [-10, 10]^3: cells (512, 1023, 0).
  const std::uint32_t code =
      lbvh::morton_code(lbvh::morton_cell(0, lo, scale), lbvh::morton_cell(10, lo, scale),
                        lbvh::morton_cell(-10, lo, scale));
  EXPECT_EQ(code, lbvh::morton_code(512, 1023, 0));
  EXPECT_EQ(code >> 27, 0b110u);  // top triple: x=1, y=1, z=0
}

// ---- hierarchies ---------------------------------------------------------------------------

// Karras 2012, figure 3: eight 5-bit keys. Expected tree (internal nodes by index, leaves as
// L#): 0 -> (3, 4); 3 -> (1, 2); 1 -> (L0, L1); 2 -> (L2, L3); 4 -> (L4, 5); 5 -> (6, L7);
// 6 -> (L5, L6).
TEST(LinearBvhKarras, TopologyOfThePapersExample) {
  const std::uint32_t codes[8] = {0b00001, 0b00010, 0b00100, 0b00101,
                                  0b10011, 0b11000, 0b11001, 0b11110};
  lbvh::Node nodes[7];
  std::int32_t parents[15];
  lbvh::karras_topology(codes, 8, nodes, parents);
  const auto leaf = [](int i) { return ~i; };
  const std::int32_t expected[7][2] = {{3, 4},       {leaf(0), leaf(1)}, {leaf(2), leaf(3)}, {1, 2},
                                       {leaf(4), 5}, {6, leaf(7)},       {leaf(5), leaf(6)}};
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(nodes[i].left, expected[i][0]) << "node " << i;
    EXPECT_EQ(nodes[i].right, expected[i][1]) << "node " << i;
  }
  EXPECT_EQ(parents[0], -1);
  EXPECT_EQ(parents[3], 0);
  EXPECT_EQ(parents[6], 5);
  EXPECT_EQ(parents[7 + 4], 4);  // leaf 4
  EXPECT_EQ(parents[7 + 7], 5);  // leaf 7
}

// Duplicate codes (all points in one cell) still give a valid, balanced tree: ties are broken by
// index, so the tree over equal keys is the radix tree of the indices.
TEST(LinearBvhKarras, EqualCodesGiveABalancedTree) {
  std::vector<std::uint32_t> codes(64, 12345u);
  std::vector<lbvh::Node> nodes(63);
  std::vector<std::int32_t> parents(127);
  lbvh::karras_topology(codes.data(), 64, nodes.data(), parents.data());
  // Depth of every leaf is log2(64) = 6.
  for (int l = 0; l < 64; ++l) {
    int depth = 0;
    for (std::int32_t p = parents[63 + l]; p >= 0; p = parents[p])
      ++depth;
    EXPECT_EQ(depth, 6) << "leaf " << l;
  }
}

// Walks a hierarchy: every internal node has two children, each internal node and leaf is
// reached exactly once, and every node's box contains its children's boxes. Returns the height.
int check_hierarchy(const lbvh::Hierarchy& h, std::vector<std::int32_t> expected_ids) {
  const auto n = static_cast<std::int32_t>(h.leaves.size());
  EXPECT_EQ(static_cast<std::int32_t>(h.nodes.size()), std::max(n - 1, 0));
  if (n == 0)
    return 0;
  std::vector<int> node_seen(h.nodes.size(), 0), leaf_seen(h.leaves.size(), 0);
  std::vector<std::pair<std::int32_t, int>> stack = {{h.root(), 0}};
  int height = 0;
  while (!stack.empty()) {
    const auto [r, depth] = stack.back();
    stack.pop_back();
    height = std::max(height, depth);
    if (r < 0) {
      EXPECT_LT(~r, n);
      ++leaf_seen[~r];
      continue;
    }
    EXPECT_LT(r, n - 1);
    ++node_seen[r];
    const lbvh::Node& node = h.nodes[r];
    EXPECT_TRUE(node.box.contains(h.box(node.left))) << "node " << r;
    EXPECT_TRUE(node.box.contains(h.box(node.right))) << "node " << r;
    stack.push_back({node.left, depth + 1});
    stack.push_back({node.right, depth + 1});
  }
  EXPECT_TRUE(std::all_of(node_seen.begin(), node_seen.end(), [](int s) { return s == 1; }));
  EXPECT_TRUE(std::all_of(leaf_seen.begin(), leaf_seen.end(), [](int s) { return s == 1; }));
  std::vector<std::int32_t> ids;
  for (const lbvh::Leaf& l : h.leaves)
    ids.push_back(l.id);
  std::sort(ids.begin(), ids.end());
  std::sort(expected_ids.begin(), expected_ids.end());
  EXPECT_EQ(ids, expected_ids);
  return height;
}

TEST(LinearBvhBuilders, BothBuildValidHierarchies) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<Real> u(-1, 1);
  lbvh::BuildScratch scratch;
  for (const int n : {0, 1, 2, 3, 100, 5000}) {
    for (const bool clustered : {false, true}) {
      std::vector<TreeBox> boxes(n);
      std::vector<std::int32_t> ids(n);
      for (int i = 0; i < n; ++i) {
        // Clustered: half the boxes at one point (equal Morton codes), the rest spread out.
        const Vec3 c = clustered && i % 2 == 0 ? Vec3(1, 2, 3) : Vec3(u(rng), u(rng), u(rng)) * 30;
        const Real h = 0.2 + 0.8 * (u(rng) + 1);
        boxes[i] = TreeBox::from({c - Vec3::Constant(h), c + Vec3::Constant(h)});
        ids[i] = 3 * i + 1;
      }
      for (const Builder b : {Builder::morton_karras, Builder::binned_sah}) {
        lbvh::Hierarchy h;
        if (b == Builder::morton_karras)
          lbvh::build_morton_karras(boxes.data(), ids.data(), n, h, scratch);
        else
          lbvh::build_binned_sah(boxes.data(), ids.data(), n, h, scratch);
        const int height = check_hierarchy(h, ids);
        if (n >= 100 && !clustered) {
          // Spread-out boxes: both trees stay shallow (about 2 log2 n at most).
          EXPECT_LE(height, 2 * std::log2(static_cast<double>(n)) + 2) << n;
        }
      }
    }
  }
}

// The SAH builder spends more time to get a cheaper tree: on a clustered, mixed-size set its SAH
// cost is lower than the Morton tree's.
TEST(LinearBvhBuilders, SahTreeIsCheaperThanMortonTree) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<Real> u(-1, 1);
  const int n = 4000;
  std::vector<TreeBox> boxes(n);
  std::vector<std::int32_t> ids(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 centre = Vec3(i % 3 * 40.0, 0, 0) + Vec3(u(rng), u(rng), u(rng)) * 10;
    const Real h = std::pow(10.0, u(rng));  // 0.1 .. 10
    boxes[i] = TreeBox::from({centre - Vec3::Constant(h), centre + Vec3::Constant(h)});
    ids[i] = i;
  }
  lbvh::BuildScratch scratch;
  lbvh::Hierarchy morton, sah;
  lbvh::build_morton_karras(boxes.data(), ids.data(), n, morton, scratch);
  lbvh::build_binned_sah(boxes.data(), ids.data(), n, sah, scratch);
  RecordProperty("sah_cost_morton", std::to_string(morton.sah_cost()));
  RecordProperty("sah_cost_binned_sah", std::to_string(sah.sah_cost()));
  EXPECT_LT(sah.sah_cost(), morton.sah_cost());
}

}  // namespace
}  // namespace tumble::test
