// The brute-force broad phase is the reference the other structures will be checked against,
// so it is itself checked against the definition of box overlap, written independently here.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "collision/broad_phase/brute_force_broad_phase.hpp"
#include "tests/property_scale.hpp"

namespace tumble {
namespace {

bool intervals_overlap(Real a0, Real a1, Real b0, Real b1) {
  return !(a1 < b0 || b1 < a0);
}

Aabb random_box(std::mt19937_64& rng) {
  std::uniform_real_distribution<Real> centre(-10, 10);
  std::uniform_real_distribution<Real> size(0.01, 3);
  const Vec3 c(centre(rng), centre(rng), centre(rng));
  const Vec3 h(size(rng), size(rng), size(rng));
  return {c - h, c + h};
}

TEST(BruteForceBroadPhase, PairsMatchDefinitionOverRandomSteps) {
  std::mt19937_64 rng(7);
  BruteForceBroadPhase bp;
  std::vector<Aabb> boxes;
  std::vector<bool> is_static, alive;
  for (int i = 0; i < 200; ++i) {
    boxes.push_back(random_box(rng));
    is_static.push_back(i % 7 == 0);
    alive.push_back(true);
    bp.insert(i, boxes[i], is_static[i]);
  }
  std::vector<ProxyPair> pairs;
  for (int step = 0; step < 50; ++step) {
    for (int i = 0; i < 200; ++i) {
      if (is_static[i] || !alive[i])
        continue;
      boxes[i] = random_box(rng);
      bp.update(i, boxes[i]);
    }
    const int victim = static_cast<int>(rng() % 200);
    if (alive[victim]) {
      bp.remove(victim);
      alive[victim] = false;
    }
    bp.find_pairs(pairs);
    std::vector<ProxyPair> expected;
    for (int i = 0; i < 200; ++i) {
      for (int j = i + 1; j < 200; ++j) {
        if (!alive[i] || !alive[j] || (is_static[i] && is_static[j]))
          continue;
        bool overlap = true;
        for (int k = 0; k < 3; ++k) {
          overlap = overlap && intervals_overlap(boxes[i].min[k], boxes[i].max[k], boxes[j].min[k],
                                                 boxes[j].max[k]);
        }
        if (overlap)
          expected.push_back({i, j});
      }
    }
    ASSERT_EQ(pairs, expected) << "step " << step;
  }
}

TEST(BruteForceBroadPhase, TouchingBoxesOverlap) {
  BruteForceBroadPhase bp;
  bp.insert(0, {Vec3(0, 0, 0), Vec3(1, 1, 1)}, false);
  bp.insert(1, {Vec3(1, 0, 0), Vec3(2, 1, 1)}, false);
  std::vector<ProxyPair> pairs;
  bp.find_pairs(pairs);
  ASSERT_EQ(pairs.size(), 1u);
}

// Ray casts against a fine sampling of the segment: every box a sample lies in is reported,
// and every reported box comes within a sample spacing of the segment. 300 rays (a quarter in
// the sanitizer run, TUMBLE_PROPERTY_SCALE: 120 million point-box checks took 47 s there).
TEST(BruteForceBroadPhase, RayCastMatchesSampling) {
  std::mt19937_64 rng(11);
  BruteForceBroadPhase bp;
  std::vector<Aabb> boxes;
  for (int i = 0; i < 100; ++i) {
    boxes.push_back(random_box(rng));
    bp.insert(i, boxes.back(), false);
  }
  std::uniform_real_distribution<Real> u(-12, 12);
  std::vector<std::int32_t> hits;
  const int trials = scaled(300);
  for (int trial = 0; trial < trials; ++trial) {
    const Vec3 origin(u(rng), u(rng), u(rng));
    Vec3 direction(u(rng), u(rng), u(rng));
    if (trial % 10 == 0)
      direction.x() = 0;  // parallel to a slab
    bp.ray_cast(origin, direction, 1.0, hits);
    const std::set<std::int32_t> reported(hits.begin(), hits.end());
    constexpr int kSamples = 4000;
    const Real spacing = direction.norm() / kSamples;
    for (int i = 0; i < 100; ++i) {
      bool sampled = false;
      Real closest = std::numeric_limits<Real>::infinity();
      for (int s = 0; s <= kSamples; ++s) {
        const Vec3 p = origin + direction * (Real(s) / kSamples);
        sampled = sampled || boxes[i].contains(p);
        const Vec3 d = (boxes[i].min - p).cwiseMax(p - boxes[i].max).cwiseMax(Vec3::Zero());
        closest = std::min(closest, d.norm());
      }
      if (sampled) {
        EXPECT_TRUE(reported.count(i)) << "trial " << trial << " box " << i;
      }
      if (reported.count(i)) {
        EXPECT_LE(closest, spacing) << "trial " << trial << " box " << i;
      }
    }
  }
  // Query by box equals the overlap definition.
  const Aabb probe{Vec3(-2, -2, -2), Vec3(2, 2, 2)};
  std::vector<std::int32_t> found;
  bp.query(probe, found);
  std::vector<std::int32_t> expected;
  for (int i = 0; i < 100; ++i) {
    bool overlap = true;
    for (int k = 0; k < 3; ++k) {
      overlap = overlap &&
                intervals_overlap(boxes[i].min[k], boxes[i].max[k], probe.min[k], probe.max[k]);
    }
    if (overlap)
      expected.push_back(i);
  }
  EXPECT_EQ(found, expected);
}

}  // namespace
}  // namespace tumble
