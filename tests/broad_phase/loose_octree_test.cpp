// The loose octree against brute force, plus its own rules: the level a box's size
// implies (Ulrich), pairs across neighbouring cells, a world that grows and shrinks, and
// infinite boxes.
#include <cmath>
#include <limits>
#include <random>

#include "collision/broad_phase/loose_octree_broad_phase.hpp"
#include "tests/broad_phase/broad_phase_property.hpp"

namespace tumble::test {
namespace {

BroadPhaseFactory octree(Real k, int n_max = 32, int d_max = 20) {
  return [=] { return std::make_unique<LooseOctreeBroadPhase>(k, n_max, d_max); };
}

bool contains(const Aabb& outer, const Aabb& inner) {
  return (inner.min.array() >= outer.min.array()).all() &&
         (inner.max.array() <= outer.max.array()).all();
}

TEST(LooseOctree, EqualsBruteForceEveryLayoutK1) {
  check_every_layout(octree(1.0));
}

// The tight end of the range k in [0.5, 1]: a box sits one level higher than with k = 1, and loose
// bounds of neighbouring cells overlap less.
TEST(LooseOctree, EqualsBruteForceEveryLayoutKHalf) {
  check_every_layout(octree(0.5), {.bodies = 300, .steps = 120});
}

TEST(LooseOctree, EqualsBruteForceManyBodies) {
  check_every_layout(octree(1.0), {.bodies = 2000, .steps = 60});
}

// n_max = 1 splits at every second proxy and d_max = 4 caps the depth, so crowded nodes at the
// depth limit and deep trees with many small nodes are both exercised.
TEST(LooseOctree, EqualsBruteForceExtremeSubdivision) {
  check_every_layout(octree(0.75, 1, 20), {.bodies = 200, .steps = 60});
  check_every_layout(octree(1.0, 2, 4), {.bodies = 200, .steps = 60});
}

// Ulrich's rule: a box of largest half extent r sits at the deepest level L whose cells' loose
// bounds hold it wherever its centre is, r <= k H / 2^L; for k = 1, L = floor(log2(H / r)).
// With n_max = 0 every occupied node splits, so every box reaches the level its size implies.
TEST(LooseOctree, BoxIsStoredAtTheLevelItsSizeImplies) {
  for (const Real k : {Real(1), Real(0.5)}) {
    SCOPED_TRACE(k);
    const int d_max = 30;
    LooseOctreeBroadPhase tree(k, 0, d_max);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<Real> pos(-50, 50), lg(-2, 1.5), aspect(0.3, 1);
    std::vector<Aabb> boxes;
    for (int i = 0; i < 400; ++i) {
      const Real r = std::pow(Real(10), lg(rng));
      const Vec3 c(pos(rng), pos(rng), pos(rng));
      const Vec3 h(r, r * aspect(rng), r * aspect(rng));  // largest half extent exactly r
      boxes.push_back({c - h, c + h});
      tree.insert(i, boxes.back(), false);
    }
    const Real big_h = tree.root_half_size();
    int checked = 0;
    for (int i = 0; i < 400; ++i) {
      const Real r = Real(0.5) * (boxes[i].max - boxes[i].min).maxCoeff();
      const Real exact = std::log2(k * big_h / r);
      if (std::abs(exact - std::round(exact)) < 1e-9)
        continue;  // on a level boundary: rounding may go either way
      const int want = std::min(d_max, static_cast<int>(std::floor(exact)));
      EXPECT_EQ(tree.level_of(i), want) << "box " << i << " r " << r;
      EXPECT_EQ(tree.size_level(boxes[i]), want);
      EXPECT_TRUE(contains(tree.loose_bound_of(i), boxes[i])) << "box " << i;
      ++checked;
    }
    EXPECT_GT(checked, 390);
    // The rule is about size: moving a box coherently (without a size change) keeps its level
    // as long as it stays in its loose bound; a shrunk box goes deeper.
    const Aabb small = cube(Vec3(1, 2, 3), 1e-3);
    tree.update(0, small);
    EXPECT_EQ(tree.level_of(0),
              std::min(d_max, static_cast<int>(std::floor(std::log2(k * big_h / 1e-3)))));
  }
}

// Two boxes in neighbouring cells of the same level touching across the cell boundary: neither
// node is an ancestor of the other, and the pair must still be found exactly once.
TEST(LooseOctree, FindsPairsAcrossNeighbouringCells) {
  LooseOctreeBroadPhase tree(1.0, 0, 20);
  BruteForceBroadPhase ref;
  int id = 0;
  // Spread boxes so the cells get deep, then put touching pairs across many cell faces.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<Real> pos(-40, 40);
  for (int i = 0; i < 300; ++i) {
    const Vec3 c(pos(rng), pos(rng), pos(rng));
    const Aabb a = cube(c, 0.4);
    // The second box touches the first's +x face exactly (closed intervals).
    const Aabb b{Vec3(a.max.x(), c.y() - 0.2, c.z() - 0.2),
                 Vec3(a.max.x() + 0.3, c.y() + 0.2, c.z() + 0.2)};
    tree.insert(id, a, false);
    ref.insert(id++, a, false);
    tree.insert(id, b, i % 3 == 0);
    ref.insert(id++, b, i % 3 == 0);
  }
  std::vector<ProxyPair> got, want;
  tree.find_pairs(got);
  ref.find_pairs(want);
  EXPECT_EQ(got, want);
  EXPECT_GE(want.size(), 300u);
  // And at least some of those pairs really are in different, unrelated nodes.
  int unrelated = 0;
  for (int i = 0; i < 600; i += 2) {
    const Aabb la = tree.loose_bound_of(i);
    const Aabb lb = tree.loose_bound_of(i + 1);
    if (!contains(la, lb) && !contains(lb, la))
      ++unrelated;
  }
  EXPECT_GT(unrelated, 10);
}

TEST(LooseOctree, WorldGrowsWhenABoxMovesFarAwayAndShrinksBack) {
  LooseOctreeBroadPhase tree(1.0, 4, 20);
  BruteForceBroadPhase ref;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<Real> pos(-10, 10);
  for (int i = 0; i < 100; ++i) {
    const Aabb b = cube(Vec3(pos(rng), pos(rng), pos(rng)), 0.8);
    tree.insert(i, b, i % 10 == 0);
    ref.insert(i, b, i % 10 == 0);
  }
  expect_same(tree, ref, "initial");
  const Real h0 = tree.root_half_size();
  EXPECT_LT(h0, 64);

  // Teleport body 5 far away, next to body 6 which follows it there.
  const Aabb far_a = cube(Vec3(5e4, -3e4, 1e3), 1);
  const Aabb far_b = cube(Vec3(5e4 + 1.5, -3e4, 1e3), 1);
  tree.update(5, far_a);
  ref.update(5, far_a);
  tree.update(6, far_b);
  ref.update(6, far_b);
  const Real grown = tree.root_half_size();
  EXPECT_GE(grown, 5e4 / 2);
  EXPECT_TRUE(contains(tree.loose_bound_of(5), far_a));
  expect_same(tree, ref, "far away");

  // Come back: the far branch empties and the root shrinks again after a find_pairs.
  const Aabb back_a = cube(Vec3(1, 1, 1), 0.8);
  const Aabb back_b = cube(Vec3(2, 1, 1), 0.8);
  tree.update(5, back_a);
  ref.update(5, back_a);
  tree.update(6, back_b);
  ref.update(6, back_b);
  expect_same(tree, ref, "back");
  EXPECT_LE(tree.root_half_size(), 4 * h0);
  EXPECT_LT(tree.root_half_size(), grown);
}

// A ground plane (z <= 0, infinite in x and y) among finite boxes, static and dynamic; it also
// turns finite and back. No crash, no NaN, and the same answers as brute force.
TEST(LooseOctree, InfiniteBoxAmongFiniteOnes) {
  for (const bool plane_static : {true, false}) {
    LooseOctreeBroadPhase tree;
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
    // A second unbounded proxy: a wall x >= 3.
    const Aabb wall{Vec3(3, -kInf, -kInf), Vec3(kInf, kInf, kInf)};
    tree.insert(80, wall, false);
    ref.insert(80, wall, false);
    EXPECT_EQ(tree.stats().unbounded, 2);
    expect_same(tree, ref, "with planes");
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

// Sparse, large and reused ids.
TEST(LooseOctree, SparseAndReusedIds) {
  LooseOctreeBroadPhase tree;
  BruteForceBroadPhase ref;
  for (int i = 0; i < 50; ++i) {
    const int id = i * 997;
    const Aabb b = cube(Vec3(i % 5, (i / 5) % 5, i / 25), 0.6);
    tree.insert(id, b, false);
    ref.insert(id, b, false);
  }
  expect_same(tree, ref, "sparse");
  for (int i = 0; i < 50; i += 3) {
    tree.remove(i * 997);
    ref.remove(i * 997);
  }
  for (int i = 0; i < 50; i += 6) {
    const Aabb b = cube(Vec3(2, 2, 1), 1.5);
    tree.insert(i * 997, b, i % 4 == 0);
    ref.insert(i * 997, b, i % 4 == 0);
  }
  expect_same(tree, ref, "reused");
}

}  // namespace
}  // namespace tumble::test
