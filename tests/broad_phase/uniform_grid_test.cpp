// Uniform grid: the shared property suite, plus the cases particular to a dense grid (cell faces,
// cell sizes far from the box sizes, the memory cap, boxes spanning many cells, layout changes).
#include <limits>
#include <random>

#include "collision/broad_phase/uniform_grid_broad_phase.hpp"
#include "tests/broad_phase/broad_phase_property.hpp"

namespace tumble::test {
namespace {

TEST(UniformGrid, AgreesWithBruteForceInEveryLayout) {
  check_every_layout([] { return std::make_unique<UniformGridBroadPhase>(); });
}

TEST(UniformGrid, AgreesWithBruteForceWithManyBodies) {
  check_every_layout([] { return std::make_unique<UniformGridBroadPhase>(); },
                     {.bodies = 2000, .steps = 60});
}

// A ground plane (infinite in x and y, z <= 0) among finite boxes, some resting on it exactly.
TEST(UniformGrid, InfiniteBoxAmongFiniteOnes) {
  UniformGridBroadPhase grid;
  BruteForceBroadPhase reference;
  const Aabb ground{Vec3(-kInf, -kInf, -kInf), Vec3(kInf, kInf, 0)};
  grid.insert(0, ground, true);
  reference.insert(0, ground, true);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<Real> u(-10, 10);
  for (int i = 1; i <= 200; ++i) {
    const Vec3 c(u(rng), u(rng), i % 3 == 0 ? Real(0.5) : u(rng));  // every third touches z = 0
    grid.insert(i, cube(c, 0.5), false);
    reference.insert(i, cube(c, 0.5), false);
  }
  // A dynamic infinite slab too: it must pair with the static ground and everything it crosses.
  const Aabb slab{Vec3(-kInf, 2, -kInf), Vec3(kInf, 3, kInf)};
  grid.insert(500, slab, false);
  reference.insert(500, slab, false);
  const std::size_t pairs = expect_same(grid, reference, 1, 12);
  EXPECT_GT(pairs, 60u);
  EXPECT_EQ(grid.oversized_count(), 2);
  // Sliding down through the plane, step by step.
  for (int step = 0; step < 20; ++step) {
    for (int i = 1; i <= 200; i += 7) {
      const Vec3 c(Real(i % 17) - 8, Real(i % 13) - 6, Real(2) - Real(0.2) * step);
      grid.update(i, cube(c, 0.5));
      reference.update(i, cube(c, 0.5));
    }
    expect_same(grid, reference, 100 + step, 12);
  }
}

// Boxes whose faces lie exactly on cell faces, and pairs that only touch there: each touching
// pair is reported once, though the two boxes share a whole row of cells.
TEST(UniformGrid, BoxesExactlyOnCellBoundaries) {
  UniformGridBroadPhase grid(1.0);
  BruteForceBroadPhase reference;
  int id = 0;
  for (int x = 0; x < 6; ++x) {
    for (int y = 0; y < 6; ++y) {
      // Unit and double cubes at integer corners: neighbours touch face, edge or corner.
      const Real size = (x + y) % 2 == 0 ? 1 : 2;
      const Aabb b{Vec3(x, y, 0), Vec3(x + size, y + size, size)};
      grid.insert(id, b, id % 5 == 0);
      reference.insert(id, b, id % 5 == 0);
      ++id;
    }
  }
  const std::size_t pairs = expect_same(grid, reference, 2, 6);
  EXPECT_GT(pairs, 100u);
  EXPECT_EQ(grid.cell_size(), 1.0);
  // The query box's faces on cell faces too.
  std::vector<std::int32_t> got, want;
  const Aabb probe{Vec3(2, 2, 1), Vec3(3, 3, 1)};
  grid.query(probe, got);
  reference.query(probe, want);
  EXPECT_EQ(got, want);
  EXPECT_FALSE(want.empty());
  // A ray running exactly along a cell face (y = 2, z = 1).
  grid.ray_cast(Vec3(-1, 2, 1), Vec3(10, 0, 0), 1, got);
  reference.ray_cast(Vec3(-1, 2, 1), Vec3(10, 0, 0), 1, want);
  EXPECT_EQ(got, want);
  EXPECT_FALSE(want.empty());
}

// A box spanning many cells (but not enough to be oversized) with many small boxes inside it:
// it shares up to 64 cells with each of them, and each pair is still reported once.
TEST(UniformGrid, BoxSpanningManyCellsReportsEachPairOnce) {
  UniformGridSettings settings;
  settings.cell_size = 1;
  settings.max_cells_per_box = 1000;
  UniformGridBroadPhase grid(settings);
  BruteForceBroadPhase reference;
  const Aabb big{Vec3(-4.5, -4.5, -4.5), Vec3(4.5, 4.5, 4.5)};  // 10 x 10 x 10 cells
  grid.insert(0, big, false);
  reference.insert(0, big, false);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<Real> u(-6, 6);
  for (int i = 1; i < 300; ++i) {
    const Aabb b = cube(Vec3(u(rng), u(rng), u(rng)), 1.2);  // up to 3 x 3 x 3 cells
    grid.insert(i, b, false);
    reference.insert(i, b, false);
  }
  const std::size_t pairs = expect_same(grid, reference, 3, 6);
  EXPECT_GT(pairs, 200u);
  EXPECT_EQ(grid.oversized_count(), 0);
}

// Cells 100x smaller than the boxes (everything is oversized: the grid falls back to the
// oversized list) and 1000x larger (everything shares one cell): both still exact.
TEST(UniformGrid, CellMuchSmallerOrLargerThanBoxes) {
  for (const Real cell : {0.01, 1000.0}) {
    SCOPED_TRACE(cell);
    const PropertyOptions options{.bodies = 200, .steps = 40};
    for (Layout layout : {Layout::uniform, Layout::mixed_sizes, Layout::one_huge}) {
      check_against_brute_force([cell] { return std::make_unique<UniformGridBroadPhase>(cell); },
                                layout, options);
    }
    UniformGridBroadPhase grid(cell);
    grid.insert(0, cube(Vec3::Zero(), 1), false);
    grid.insert(1, cube(Vec3(1.5, 0, 0), 1), false);
    std::vector<ProxyPair> pairs;
    grid.find_pairs(pairs);
    EXPECT_EQ(pairs, (std::vector<ProxyPair>{{0, 1}}));
    if (cell < 1)
      EXPECT_EQ(grid.oversized_count(), 2);
    else
      EXPECT_EQ(grid.oversized_count(), 0);
  }
}

// Boxes spread over 1e6 m with 1 mm cells would need 1e27 cells: the cap grows the cell size
// instead, and the result is still exact.
TEST(UniformGrid, MemoryCapGrowsCellsAndStaysExact) {
  UniformGridSettings settings;
  settings.cell_size = 1e-3;
  UniformGridBroadPhase grid(settings);
  BruteForceBroadPhase reference;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<Real> spread(-5e5, 5e5);
  std::uniform_real_distribution<Real> near(-1, 1);
  int id = 0;
  std::vector<Vec3> centres;
  std::vector<Vec3> first_boxes;  // the first box's centre in each cluster, which the rays cross
  // One draw per statement: a call's arguments are evaluated in an order the compiler picks.
  const auto draw = [&](auto& distribution) {
    const Real x = distribution(rng), y = distribution(rng), z = distribution(rng);
    return Vec3(x, y, z);
  };
  for (int cluster = 0; cluster < 40; ++cluster) {
    centres.push_back(draw(spread));
    for (int i = 0; i < 10; ++i, ++id) {
      const Vec3 centre = centres.back() + draw(near);
      if (i == 0)
        first_boxes.push_back(centre);
      const Aabb b = cube(centre, 0.4);
      grid.insert(id, b, false);
      reference.insert(id, b, false);
    }
  }
  const std::size_t pairs = expect_same(grid, reference, 4, 5e5);
  EXPECT_GT(pairs, 40u);
  EXPECT_LE(grid.cell_count(), std::max(settings.min_cells, settings.cells_per_box_cap * id));
  EXPECT_GT(grid.cell_size(), 1e2);
  // Queries and rays where the boxes are.
  std::vector<std::int32_t> got, want;
  for (const Vec3& c : centres) {
    grid.query(cube(c, 0.5), got);
    reference.query(cube(c, 0.5), want);
    EXPECT_EQ(got, want);
    grid.ray_cast(c - Vec3(3, 2, 1), Vec3(6, 4, 2), 1, got);
    reference.ray_cast(c - Vec3(3, 2, 1), Vec3(6, 4, 2), 1, want);
    EXPECT_EQ(got, want);
  }
  for (const Vec3& c : first_boxes) {
    grid.ray_cast(c - Vec3(3, 2, 1), Vec3(6, 4, 2), 1, got);
    reference.ray_cast(c - Vec3(3, 2, 1), Vec3(6, 4, 2), 1, want);
    EXPECT_EQ(got, want);
    EXPECT_FALSE(want.empty());  // it crosses that box
  }
}

// When every box jumps far away the layout is re-derived, and the answer stays exact before
// and after.
TEST(UniformGrid, ReDerivesTheLayoutWhenBoxesMoveAway) {
  UniformGridBroadPhase grid;
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
  const int before = grid.layout_derivations();
  for (int i = 0; i < 300; ++i) {
    if (i % 10 == 0)
      continue;
    const Aabb b = cube(centres[i] * 3 + Vec3(1e4, 0, 0), 0.7 * (1 + i % 3));
    grid.update(i, b);
    reference.update(i, b);
  }
  expect_same(grid, reference, 7, 1e4);
  EXPECT_GT(grid.layout_derivations(), before);
  // Queries made before find_pairs, after updates, must be exact as well.
  for (int i = 1; i < 300; i += 3) {
    const Aabb b = cube(centres[i], 0.7);
    grid.update(i, b);
    reference.update(i, b);
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
