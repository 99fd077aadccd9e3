// Sweep and prune against brute force: the shared random layouts, both update paths (insertion
// sort and remove/reinsert) forced on their own, endpoints that tie exactly, and planes.
#include "collision/broad_phase/sweep_and_prune_broad_phase.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "collision/broad_phase/brute_force_broad_phase.hpp"
#include "tests/broad_phase/broad_phase_property.hpp"

namespace tumble::test {
namespace {

// Which update path moves take: chosen by the structure, or forced one way.
enum class Path { automatic, always_reinsert, always_sort };

SweepAndPruneSettings settings_for(Path path) {
  switch (path) {
    case Path::always_reinsert:
      return {.large_move_crossings = 0, .window_weight = 0};
    case Path::always_sort:
      return {.large_move_crossings = kInf};
    default:
      return {};
  }
}

const char* path_name(Path path) {
  return path == Path::automatic         ? "automatic"
         : path == Path::always_reinsert ? "reinsert"
                                         : "sort";
}

BroadPhaseFactory sap(Path path = Path::automatic) {
  return [path] { return std::make_unique<SweepAndPruneBroadPhase>(settings_for(path)); };
}

// Two structures fed the same calls; compare() checks pairs, a few box queries and ray casts.
struct SapLockstep {
  SweepAndPruneBroadPhase tested;
  BruteForceBroadPhase reference;
  std::vector<ProxyPair> got, want;
  std::vector<std::int32_t> got_ids, want_ids;

  explicit SapLockstep(const SweepAndPruneSettings& s = {}) : tested(s) {}
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
  // Returns the number of pairs, so a caller can check the case was not trivial.
  std::size_t compare(const std::vector<Aabb>& probes, const std::vector<Vec3>& ray_points) {
    tested.find_pairs(got);
    reference.find_pairs(want);
    EXPECT_EQ(got, want);
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
    return want.size();
  }
};

TEST(SweepAndPrune, AgreesWithBruteForceInEveryLayout) {
  check_every_layout(sap());
}

TEST(SweepAndPrune, AgreesWithBruteForceWithManyBodies) {
  check_every_layout(sap(), {.bodies = 2000, .steps = 60});
}

// Every move that changes a box is a remove and reinsert.
TEST(SweepAndPrune, RemoveAndReinsertPathAgreesInEveryLayout) {
  check_every_layout(sap(Path::always_reinsert), {.bodies = 300, .steps = 100});
}

// Teleports too go through insertion sort, crossing hundreds of endpoints.
TEST(SweepAndPrune, InsertionSortPathAgreesInEveryLayout) {
  check_every_layout(sap(Path::always_sort), {.bodies = 300, .steps = 100});
}

// The two paths are really taken: coherent moves sort, teleports reinsert (default threshold).
TEST(SweepAndPrune, TeleportsTakeTheLargeMovePathAndAgree) {
  SapLockstep s;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<Real> u(-20, 20);
  std::uniform_real_distribution<Real> small(-0.05, 0.05);
  std::vector<Aabb> boxes;
  for (int i = 0; i < 500; ++i) {
    const Vec3 c(u(rng), u(rng), u(rng));
    boxes.push_back({c - Vec3::Constant(1), c + Vec3::Constant(1)});
    s.insert(i, boxes.back(), i % 10 == 0);
  }
  s.compare({}, {});
  for (int step = 0; step < 40; ++step) {
    for (int i = 0; i < 500; ++i) {
      if (i % 10 == 0)
        continue;  // static
      if ((i + step) % 7 == 0) {
        const Vec3 c(u(rng), u(rng), u(rng));  // teleport across the world
        boxes[i] = {c - Vec3::Constant(1), c + Vec3::Constant(1)};
      } else {
        const Vec3 d(small(rng), small(rng), small(rng));
        boxes[i] = {boxes[i].min + d, boxes[i].max + d};
      }
      s.update(i, boxes[i]);
    }
    const Aabb probe{Vec3::Constant(-3), Vec3::Constant(4)};
    EXPECT_GT(s.compare({probe}, {Vec3(-20, -20, -20), Vec3(20, 20, 20)}), 20u);
  }
  const auto& c = s.tested.counters();
  EXPECT_GT(c.large_moves, 40 * 450 / 7 / 2);
  EXPECT_GT(c.small_moves, 40 * 450 / 2);
  EXPECT_GT(c.swaps, 0);
}

// Unit cubes on an integer grid: every face touches its neighbour's, so many endpoints tie
// exactly (min of one == max of the other, and mins equal to mins); moves by whole units keep
// them tied. Touching boxes overlap (closed intervals), so the tie order matters.
void check_grid_with_ties(Path path) {
  SCOPED_TRACE(path_name(path));
  SapLockstep s(settings_for(path));
  std::mt19937_64 rng(3);
  const int n = 6;
  std::vector<Aabb> boxes;
  for (int x = 0; x < n; ++x) {
    for (int y = 0; y < n; ++y) {
      for (int z = 0; z < n; ++z) {
        const Vec3 lo(x, y, z);
        boxes.push_back({lo, lo + Vec3::Ones()});
        s.insert(static_cast<int>(boxes.size()) - 1, boxes.back(), (x + y + z) % 11 == 0);
      }
    }
  }
  // Every touching neighbour (faces, edges, corners): 26-neighbourhood pairs on a 6^3 grid.
  EXPECT_GT(s.compare({}, {}), 1000u);
  for (int step = 0; step < 60; ++step) {
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      if (rng() % 3 != 0)
        continue;
      const int k = static_cast<int>(rng() % 3);
      const Real d = static_cast<Real>(static_cast<int>(rng() % 5) - 2);  // -2 .. 2 units
      Vec3 shift = Vec3::Zero();
      shift[k] = d;
      boxes[i] = {boxes[i].min + shift, boxes[i].max + shift};
      s.update(static_cast<int>(i), boxes[i]);
    }
    // Probes and rays that end exactly on box faces.
    const Real a = static_cast<Real>(rng() % 6);
    const std::vector<Aabb> probes = {{Vec3(a, a, a), Vec3(a + 1, a + 1, a + 1)},
                                      {Vec3(a, 0, 0), Vec3(a, 6, 6)}};
    const std::vector<Vec3> rays = {Vec3(0, a, a), Vec3(6, a, a), Vec3(a, 0, 0), Vec3(a, 6, 6)};
    EXPECT_GT(s.compare(probes, rays), 100u) << "step " << step;
    if (::testing::Test::HasFailure())
      return;
  }
}

TEST(SweepAndPrune, ExactlyEqualCoordinatesAgree) {
  check_grid_with_ties(Path::automatic);
  check_grid_with_ties(Path::always_reinsert);
  check_grid_with_ties(Path::always_sort);
}

// A ground plane (x, y infinite, z in (-inf, 0]) and an infinite wall among finite boxes that
// fall through it, rest exactly on it, and leave it.
TEST(SweepAndPrune, InfiniteBoxesAgree) {
  for (Path path : {Path::automatic, Path::always_reinsert, Path::always_sort}) {
    SCOPED_TRACE(path_name(path));
    SapLockstep s(settings_for(path));
    s.insert(1000, {Vec3(-kInf, -kInf, -kInf), Vec3(kInf, kInf, 0)}, true);     // ground
    s.insert(1001, {Vec3(5, -kInf, -kInf), Vec3(kInf, kInf, kInf)}, false);     // wall x >= 5
    s.insert(1002, {Vec3(-kInf, -kInf, -kInf), Vec3(kInf, kInf, kInf)}, true);  // everything
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
    for (int step = 0; step < 30; ++step) {
      for (int i = 0; i < 100; ++i) {
        const Vec3 d(Real(0.25) * ((i + step) % 3 - 1), 0, -0.25);
        boxes[i] = {boxes[i].min + d, boxes[i].max + d};
        s.update(i, boxes[i]);
      }
      if (step == 10) {
        s.update(1001, {Vec3(-kInf, -kInf, 2), Vec3(kInf, kInf, kInf)});  // the wall turns
      }
      if (step == 20) {
        s.remove(1002);
      }
      EXPECT_GT(s.compare(probes, rays), 50u) << "step " << step;
      if (::testing::Test::HasFailure())
        return;
    }
  }
}

// Ids large and sparse, removed and reused, and a proxy removed in the same step it moved.
TEST(SweepAndPrune, SparseReusedIdsAgree) {
  SapLockstep s;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<Real> u(-5, 5);
  std::vector<int> ids;
  std::vector<Aabb> boxes;
  for (int i = 0; i < 200; ++i) {
    ids.push_back(i * 13 + 5);
    const Vec3 c(u(rng), u(rng), u(rng));
    boxes.push_back({c - Vec3::Constant(0.7), c + Vec3::Constant(0.7)});
    s.insert(ids.back(), boxes.back());
  }
  for (int step = 0; step < 50; ++step) {
    for (int i = 0; i < 200; ++i) {
      const Vec3 c(u(rng), u(rng), u(rng));
      boxes[i] = step % 2 == 0 ? Aabb{boxes[i].min + c * 0.01, boxes[i].max + c * 0.01}
                               : Aabb{c - Vec3::Constant(0.7), c + Vec3::Constant(0.7)};
      s.update(ids[i], boxes[i]);
    }
    for (int r = 0; r < 10; ++r) {
      const int i = static_cast<int>(rng() % 200);
      s.remove(ids[i]);
      s.insert(ids[i], boxes[i], r == 0);
    }
    EXPECT_GT(s.compare({{Vec3(-2, -2, -2), Vec3(2, 2, 2)}}, {Vec3(-5, 0, 0), Vec3(5, 1, 1)}), 50u);
  }
}

// Queries asked after updates, inserts and removes but before the next find_pairs: pending
// inserts, dead endpoints still in the arrays, and reinserted teleports must all be seen as
// they are now.
TEST(SweepAndPrune, QueriesBetweenFindPairsSeeTheCurrentBoxes) {
  SapLockstep s;
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
  auto compare_queries = [&] {
    for (const Aabb& p : probes) {
      s.tested.query(p, s.got_ids);
      s.reference.query(p, s.want_ids);
      EXPECT_EQ(s.got_ids, s.want_ids);
    }
    for (std::size_t i = 0; i + 1 < rays.size(); i += 2) {
      s.tested.ray_cast(rays[i], rays[i + 1] - rays[i], 1, s.got_ids);
      s.reference.ray_cast(rays[i], rays[i + 1] - rays[i], 1, s.want_ids);
      EXPECT_EQ(s.got_ids, s.want_ids);
    }
  };
  compare_queries();  // everything pending
  for (int step = 0; step < 10; ++step) {
    s.compare(probes, rays);
    for (int i = step; i < 300; i += 3) {
      const Vec3 c = step % 2 == 0 ? Vec3(u(rng), u(rng), u(rng))  // teleports
                                   : Vec3((boxes[i].min + boxes[i].max) / 2 + Vec3::Constant(0.1));
      boxes[i] = {c - Vec3::Constant(1), c + Vec3::Constant(1)};
      s.update(i, boxes[i]);
    }
    s.remove(step * 7);
    s.insert(step * 7, boxes[step * 7], step % 2 == 0);
    s.remove(step * 7 + 1);
    s.insert(300 + step, boxes[step * 7 + 1]);
    compare_queries();
    s.remove(300 + step);
    s.insert(step * 7 + 1, boxes[step * 7 + 1]);
  }
}

// The query bound keeps one huge box out of every window instead of widening them all.
TEST(SweepAndPrune, HugeBoxGoesToTheWideList) {
  SweepAndPruneBroadPhase sap_bp;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<Real> u(-30, 30);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 c(u(rng), u(rng), u(rng));
    sap_bp.insert(i, {c - Vec3::Constant(0.5), c + Vec3::Constant(0.5)}, false);
  }
  sap_bp.insert(2000, {Vec3::Constant(-40), Vec3::Constant(40)}, false);
  std::vector<ProxyPair> pairs;
  sap_bp.find_pairs(pairs);
  EXPECT_GE(pairs.size(), 2000u);
  EXPECT_GE(sap_bp.wide_count(), 1u);
  EXPECT_LT(sap_bp.wide_count(), 50u);
}

}  // namespace
}  // namespace tumble::test
