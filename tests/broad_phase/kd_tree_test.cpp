// The k-d tree against brute force, plus its own rules: leaves obey the leaf size and
// the cost rule, straddlers are found and do not cost quadratic work, the rebuild trigger fires
// when the tree degrades and not under coherent motion, and infinite boxes.
#include <cmath>
#include <limits>
#include <random>

#include "collision/broad_phase/kd_tree_broad_phase.hpp"
#include "tests/broad_phase/broad_phase_property.hpp"

namespace tumble::test {
namespace {

BroadPhaseFactory kd_tree(KdTreeOptions options = {}) {
  return [=] { return std::make_unique<KdTreeBroadPhase>(options); };
}

TEST(KdTree, EqualsBruteForceEveryLayout) {
  check_every_layout(kd_tree());
}

TEST(KdTree, EqualsBruteForceManyBodies) {
  check_every_layout(kd_tree(), {.bodies = 2000, .steps = 60});
}

// Rebuilding every step, and a tiny leaf size with few bins (deep trees, many straddlers).
TEST(KdTree, EqualsBruteForceOtherPolicies) {
  KdTreeOptions every_step;
  every_step.rebuild = KdTreeOptions::Rebuild::every_step;
  check_every_layout(kd_tree(every_step), {.bodies = 200, .steps = 60});
  KdTreeOptions tiny;
  tiny.leaf_size = 1;
  tiny.bins = 4;
  check_every_layout(kd_tree(tiny), {.bodies = 200, .steps = 60});
}

// After a build, every leaf holds at most leaf_size proxies unless no candidate plane pays
// (checked with the tree's own cost rule on the leaf's boxes), and no node holding at most
// leaf_size proxies was split.
TEST(KdTree, LeavesRespectLeafSizeAndCostRule) {
  KdTreeOptions options;
  options.leaf_size = 6;
  KdTreeBroadPhase tree(options);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<Real> pos(-30, 30), size(0.05, 0.5);
  std::vector<Aabb> boxes;
  for (int i = 0; i < 3000; ++i) {
    boxes.push_back(cube(Vec3(pos(rng), pos(rng), pos(rng)), size(rng)));
    tree.insert(i, boxes.back(), false);
  }
  tree.rebuild();
  const auto infos = tree.node_infos();
  int leaves = 0;
  for (const auto& n : infos) {
    if (n.leaf) {
      ++leaves;
      EXPECT_LE(n.own, options.leaf_size);  // sparse small boxes: splitting always pays
    } else {
      EXPECT_GT(n.subtree, options.leaf_size);
    }
  }
  EXPECT_GT(leaves, 3000 / options.leaf_size / 2);
  EXPECT_LT(tree.stats().depth, 40);

  // Boxes that no plane can separate (all the same box): splitting never pays, so the whole set
  // is one leaf however many there are.
  KdTreeBroadPhase same(options);
  std::vector<Aabb> copies(50, cube(Vec3(1, 2, 3), 0.5));
  for (int i = 0; i < 50; ++i)
    same.insert(i, copies[i], false);
  same.rebuild();
  EXPECT_EQ(same.node_infos().size(), 1u);
  const auto choice = same.best_split(copies);
  EXPECT_GE(choice.cost, choice.leaf_cost);

  // Two such stacks far apart: the root split between them pays, the stacks themselves do not.
  KdTreeBroadPhase two(options);
  for (int i = 0; i < 40; ++i)
    two.insert(i, cube(i < 20 ? Vec3(-10, 0, 0) : Vec3(10, 0, 0), 0.5), false);
  two.rebuild();
  const auto infos2 = two.node_infos();
  ASSERT_EQ(infos2.size(), 3u);
  EXPECT_FALSE(infos2[0].leaf);
  EXPECT_EQ(infos2[0].axis, 0);
  EXPECT_EQ(infos2[1].own, 20);
  EXPECT_EQ(infos2[2].own, 20);
}

// Rods along x, y and z spanning the whole region cross every plane: most proxies are
// straddlers. Pairs, queries and rays must still equal brute force, and the work must stay far
// below all pairs (the straddler list must not turn the search quadratic).
TEST(KdTree, ManyStraddlersEqualBruteForceAndStaySubquadratic) {
  KdTreeBroadPhase tree;
  BruteForceBroadPhase ref;
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<Real> pos(-40, 40), small(0.1, 0.4);
  const int rods = 150, dots = 1500;
  std::vector<Aabb> boxes;
  for (int i = 0; i < rods; ++i) {
    const int axis = i % 3;
    Vec3 c(pos(rng), pos(rng), pos(rng));
    Vec3 h = Vec3::Constant(0.2);
    c[axis] = 0;
    h[axis] = 40;
    boxes.push_back({c - h, c + h});
  }
  for (int i = 0; i < dots; ++i)
    boxes.push_back(cube(Vec3(pos(rng), pos(rng), pos(rng)), small(rng)));
  for (int i = 0; i < rods + dots; ++i) {
    tree.insert(i, boxes[i], i % 5 == 0);
    ref.insert(i, boxes[i], i % 5 == 0);
  }
  expect_same(tree, ref, "built");
  EXPECT_GT(tree.stats().straddlers, rods / 2);
  std::uniform_real_distribution<Real> jitter(-0.3, 0.3);
  std::vector<ProxyPair> pairs;
  for (int step = 0; step < 20; ++step) {
    for (int i = 0; i < rods + dots; ++i) {
      if (i % 5 == 0)
        continue;
      const Vec3 d(jitter(rng), jitter(rng), jitter(rng));
      boxes[i] = {boxes[i].min + d, boxes[i].max + d};
      tree.update(i, boxes[i]);
      ref.update(i, boxes[i]);
    }
    expect_same(tree, ref, "moving");
  }
  tree.find_pairs(pairs);
  const auto s = tree.stats();
  const double n = rods + dots;
  // Brute force would do n(n-1)/2 ~ 1.4e6 tests here.
  EXPECT_LT(double(s.box_tests), 0.1 * n * (n - 1) / 2) << "pairs " << pairs.size();
}

// Under small coherent motion the planes stay good and the tree is not rebuilt every step; when
// everything gathers into one corner, the measured work rises and the tree is rebuilt.
TEST(KdTree, RebuildTriggerFiresOnDegradationOnly) {
  KdTreeBroadPhase tree;
  BruteForceBroadPhase ref;
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<Real> pos(-30, 30), jitter(-0.05, 0.05);
  std::vector<Vec3> centres;
  for (int i = 0; i < 2000; ++i) {
    centres.emplace_back(pos(rng), pos(rng), pos(rng));
    tree.insert(i, cube(centres[i], 0.6), false);
    ref.insert(i, cube(centres[i], 0.6), false);
  }
  std::vector<ProxyPair> pairs;
  tree.find_pairs(pairs);
  const auto after_build = tree.stats().rebuilds;
  for (int step = 0; step < 40; ++step) {
    for (int i = 0; i < 2000; ++i) {
      centres[i] += Vec3(jitter(rng), jitter(rng), jitter(rng));
      tree.update(i, cube(centres[i], 0.6));
    }
    tree.find_pairs(pairs);
  }
  EXPECT_LE(tree.stats().rebuilds - after_build, 1);
  // Gather: every box moves 20% of the way to one corner per step, so the density grows ~64x
  // over six steps and the old leaves fill up.
  std::int64_t gathering_rebuilds = 0;
  for (int step = 0; step < 6; ++step) {
    for (int i = 0; i < 2000; ++i) {
      centres[i] = Vec3(25, 25, 25) + Real(0.8) * (centres[i] - Vec3(25, 25, 25));
      tree.update(i, cube(centres[i], 0.6));
      ref.update(i, cube(centres[i], 0.6));
    }
    const auto before = tree.stats().rebuilds;
    expect_same(tree, ref, "gathering");
    gathering_rebuilds += tree.stats().rebuilds - before;
  }
  EXPECT_GE(gathering_rebuilds, 1);
  // And the kept tree is not far from a fresh one (the trigger bounds the degradation).
  tree.find_pairs(pairs);
  const auto kept = tree.stats();
  tree.rebuild();
  tree.find_pairs(pairs);
  const auto fresh = tree.stats();
  EXPECT_LT(kept.box_tests + kept.node_visits, 3 * (fresh.box_tests + fresh.node_visits));
}

// A ground plane (z <= 0, infinite in x and y) among finite boxes, static and dynamic; it also
// turns finite and back. No crash, no NaN, and the same answers as brute force.
TEST(KdTree, InfiniteBoxAmongFiniteOnes) {
  for (const bool plane_static : {true, false}) {
    KdTreeBroadPhase tree;
    BruteForceBroadPhase ref;
    const Aabb plane{Vec3(-kInf, -kInf, -kInf), Vec3(kInf, kInf, 0)};
    tree.insert(0, plane, plane_static);
    ref.insert(0, plane, plane_static);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<Real> pos(-8, 8);
    for (int i = 1; i < 80; ++i) {
      const Aabb b = cube(Vec3(pos(rng), pos(rng), pos(rng)), 0.7);
      tree.insert(i, b, i % 7 == 0);
      ref.insert(i, b, i % 7 == 0);
    }
    const Aabb wall{Vec3(3, -kInf, -kInf), Vec3(kInf, kInf, kInf)};
    tree.insert(80, wall, false);
    ref.insert(80, wall, false);
    expect_same(tree, ref, "with planes");
    EXPECT_EQ(tree.stats().unbounded, 2);
    for (int step = 0; step < 20; ++step) {
      for (int i = 1; i < 80; ++i) {
        if (i % 7 == 0)
          continue;
        const Aabb b = cube(Vec3(pos(rng), pos(rng), pos(rng)), 0.7);
        tree.update(i, b);
        ref.update(i, b);
      }
      expect_same(tree, ref, "moving");
    }
    const Aabb finite_floor{Vec3(-5, -5, -1), Vec3(5, 5, 0)};
    tree.update(0, finite_floor);
    ref.update(0, finite_floor);
    expect_same(tree, ref, "plane made finite");
    tree.update(0, plane);
    ref.update(0, plane);
    expect_same(tree, ref, "plane again");
    tree.remove(80);
    ref.remove(80);
    expect_same(tree, ref, "wall removed");
  }
}

}  // namespace
}  // namespace tumble::test
