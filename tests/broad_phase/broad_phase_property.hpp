// Property tests shared by every broad-phase structure: over thousands of random steps of
// moving, inserting and removing boxes in several layouts, the structure's pair set, box
// queries and ray casts must equal brute force exactly, every step, in the same order.
// Each structure's test file calls check_against_brute_force with a factory for it.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "collision/broad_phase/broad_phase.hpp"
#include "collision/broad_phase/brute_force_broad_phase.hpp"
#include "tests/property_scale.hpp"

namespace tumble::test {

// An unbounded box edge (planes and walls in the layouts).
inline constexpr Real kInf = std::numeric_limits<Real>::infinity();

using BroadPhaseFactory = std::function<std::unique_ptr<BroadPhase>()>;

// A cube of half side `half` around `centre`.
inline Aabb cube(const Vec3& centre, Real half) {
  return {centre - Vec3::Constant(half), centre + Vec3::Constant(half)};
}

// Compares pairs, 20 random box queries (half size up to probe_size * reach) and 20 random ray
// casts with brute force. Returns the number of pairs.
inline std::size_t expect_same(BroadPhase& tested, BruteForceBroadPhase& reference,
                               std::uint64_t seed, Real reach, Real probe_size = 0.1) {
  std::vector<ProxyPair> got, want;
  tested.find_pairs(got);
  reference.find_pairs(want);
  EXPECT_EQ(got, want);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<Real> u(-reach, reach);
  std::vector<std::int32_t> got_ids, want_ids;
  for (int q = 0; q < 20; ++q) {
    const Vec3 c(u(rng), u(rng), u(rng));
    const Aabb probe = cube(c, std::abs(u(rng)) * probe_size);
    tested.query(probe, got_ids);
    reference.query(probe, want_ids);
    EXPECT_EQ(got_ids, want_ids) << "query " << q;
    const Vec3 d(u(rng), u(rng), u(rng));
    tested.ray_cast(c, 2 * d, 1, got_ids);
    reference.ray_cast(c, 2 * d, 1, want_ids);
    EXPECT_EQ(got_ids, want_ids) << "ray " << q;
  }
  return want.size();
}

// Compares pairs, three fixed box queries (one an infinite slab) and three fixed ray casts with
// brute force; `when` names the moment in the failure message.
inline void expect_same(BroadPhase& tested, BruteForceBroadPhase& reference, const char* when) {
  SCOPED_TRACE(when);
  constexpr Real kInfinity = std::numeric_limits<Real>::infinity();
  std::vector<ProxyPair> got, want;
  tested.find_pairs(got);
  reference.find_pairs(want);
  EXPECT_EQ(got, want);
  std::vector<std::int32_t> gq, wq;
  const Aabb probes[] = {cube(Vec3::Zero(), 3),
                         cube(Vec3(5, -2, 1), 10),
                         {Vec3(-kInfinity, -1, -1), Vec3(kInfinity, 1, 1)}};
  for (const Aabb& p : probes) {
    tested.query(p, gq);
    reference.query(p, wq);
    EXPECT_EQ(gq, wq);
  }
  const Vec3 origins[] = {Vec3(-20, 0.1, 0.2), Vec3(0, 0, 30), Vec3(3, 3, 3)};
  const Vec3 dirs[] = {Vec3(40, 0, 0), Vec3(0.1, -0.2, -60), Vec3(-1, -1, -1)};
  for (int i = 0; i < 3; ++i) {
    tested.ray_cast(origins[i], dirs[i], 1, gq);
    reference.ray_cast(origins[i], dirs[i], 1, wq);
    EXPECT_EQ(gq, wq);
  }
}

enum class Layout {
  uniform,          // boxes of similar size spread evenly
  clustered,        // a few dense clusters
  mixed_sizes,      // sizes over four orders of magnitude
  one_huge,         // one box spanning everything among many tiny ones
  on_a_line,        // all centres on one line
  at_one_point,     // all boxes around the same point (every pair overlaps)
  far_from_origin,  // uniform, but 1e5 m from the origin
};

inline const char* layout_name(Layout l) {
  switch (l) {
    case Layout::uniform:
      return "uniform";
    case Layout::clustered:
      return "clustered";
    case Layout::mixed_sizes:
      return "mixed_sizes";
    case Layout::one_huge:
      return "one_huge";
    case Layout::on_a_line:
      return "on_a_line";
    case Layout::at_one_point:
      return "at_one_point";
    case Layout::far_from_origin:
      return "far_from_origin";
  }
  return "?";
}

inline const std::vector<Layout>& all_layouts() {
  static const std::vector<Layout> layouts = {
      Layout::uniform,   Layout::clustered,    Layout::mixed_sizes,    Layout::one_huge,
      Layout::on_a_line, Layout::at_one_point, Layout::far_from_origin};
  return layouts;
}

struct PropertyOptions {
  int bodies = 300;          // proxies alive at the start
  int steps = 300;           // random steps
  int queries_per_step = 3;  // box queries and ray casts checked per step
  std::uint64_t seed = 1;
};

namespace detail {

class RandomWorld {
 public:
  // The region grows with the cube root of the count so that each box overlaps about one
  // other on average, whatever the count.
  RandomWorld(Layout layout, std::uint64_t seed, int bodies)
      : layout_(layout), rng_(seed), extent_(Real(2.5) * std::cbrt(Real(bodies))) {}

  Real extent() const { return extent_; }

  Real uniform(Real a, Real b) { return std::uniform_real_distribution<Real>(a, b)(rng_); }
  int integer(int n) { return static_cast<int>(rng_() % static_cast<std::uint64_t>(n)); }

  Vec3 centre() {
    const Vec3 offset = layout_ == Layout::far_from_origin ? Vec3(1e5, -1e5, 1e5) : Vec3::Zero();
    switch (layout_) {
      case Layout::clustered: {
        const Real e = extent_;
        const Vec3 clusters[3] = {Vec3(-e, 0, 0), Vec3(e, e, 0), Vec3(0, -e, e)};
        return clusters[integer(3)] + Vec3(uniform(-3, 3), uniform(-3, 3), uniform(-3, 3));
      }
      case Layout::on_a_line:
        return Vec3(uniform(-extent_, extent_) * extent_, 0, 0);
      case Layout::at_one_point:
        return Vec3(uniform(-0.01, 0.01), uniform(-0.01, 0.01), uniform(-0.01, 0.01));
      default:
        return offset + Vec3(uniform(-extent_, extent_), uniform(-extent_, extent_),
                             uniform(-extent_, extent_));
    }
  }

  Vec3 half_size(int id) {
    switch (layout_) {
      case Layout::mixed_sizes: {
        const Real s = std::pow(Real(10), uniform(-2, 2));
        return Vec3(s * uniform(0.5, 1), s * uniform(0.5, 1), s * uniform(0.5, 1));
      }
      case Layout::one_huge:
        return id == 0 ? Vec3::Constant(extent_) : Vec3::Constant(uniform(0.05, 0.3));
      default:
        return Vec3(uniform(0.3, 2), uniform(0.3, 2), uniform(0.3, 2));
    }
  }

  Aabb box(int id) {
    const Vec3 c = centre();
    const Vec3 h = half_size(id);
    return {c - h, c + h};
  }

  // Coherent motion most of the time, a teleport now and then (large moves must work too).
  Aabb moved(const Aabb& b, int id) {
    if (integer(50) == 0)
      return box(id);
    const Vec3 d(uniform(-0.5, 0.5), uniform(-0.5, 0.5), uniform(-0.5, 0.5));
    return {b.min + d, b.max + d};
  }

 private:
  Layout layout_;
  std::mt19937_64 rng_;
  Real extent_;
};

}  // namespace detail

// Runs the random scenario and compares every output with brute force. Returns the number of
// pairs compared in total, so callers can assert the scenario was not trivial.
inline std::int64_t check_against_brute_force(const BroadPhaseFactory& make, Layout layout,
                                              const PropertyOptions& options = {}) {
  SCOPED_TRACE(std::string("layout ") + layout_name(layout));
  // With every box at one point every pair overlaps: n^2 / 2 pairs a step. 200 boxes give
  // 20,000 pairs, plenty to check, without making the suite quadratic in the body count.
  PropertyOptions capped = options;
  if (layout == Layout::at_one_point)
    capped.bodies = std::min(options.bodies, 200);
  capped.steps = std::max(4, static_cast<int>(options.steps * property_scale()));
  const PropertyOptions& opts = capped;
  detail::RandomWorld world(layout, opts.seed, opts.bodies);
  auto tested = make();
  BruteForceBroadPhase reference;
  std::vector<Aabb> boxes;
  std::vector<bool> alive;
  std::vector<bool> is_static;
  auto add = [&](int id) {
    const Aabb b = world.box(id);
    const bool s = world.integer(8) == 0;
    if (static_cast<std::size_t>(id) >= boxes.size()) {
      boxes.resize(id + 1);
      alive.resize(id + 1, false);
      is_static.resize(id + 1, false);
    }
    boxes[id] = b;
    alive[id] = true;
    is_static[id] = s;
    tested->insert(id, b, s);
    reference.insert(id, b, s);
  };
  for (int i = 0; i < opts.bodies; ++i)
    add(i);

  std::vector<ProxyPair> got, want;
  std::vector<std::int32_t> got_ids, want_ids;
  std::int64_t compared = 0;
  for (int step = 0; step < opts.steps; ++step) {
    // Move every dynamic proxy; remove one and insert one now and then (ids are reused).
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      if (!alive[i] || is_static[i])
        continue;
      boxes[i] = world.moved(boxes[i], static_cast<int>(i));
      tested->update(static_cast<std::int32_t>(i), boxes[i]);
      reference.update(static_cast<std::int32_t>(i), boxes[i]);
    }
    if (world.integer(4) == 0) {
      const int victim = world.integer(static_cast<int>(boxes.size()));
      if (alive[victim]) {
        tested->remove(victim);
        reference.remove(victim);
        alive[victim] = false;
      } else {
        add(victim);
      }
    }
    if (world.integer(10) == 0)
      add(static_cast<int>(boxes.size()));

    tested->find_pairs(got);
    reference.find_pairs(want);
    EXPECT_EQ(got, want) << "pairs differ at step " << step;
    if (got != want)
      return compared;
    compared += static_cast<std::int64_t>(want.size());

    for (int q = 0; q < opts.queries_per_step; ++q) {
      const Aabb probe = world.box(-1);
      tested->query(probe, got_ids);
      reference.query(probe, want_ids);
      EXPECT_EQ(got_ids, want_ids) << "box query differs at step " << step;
      const Vec3 origin = world.centre();
      const Real reach = 2 * world.extent();
      const Vec3 direction(world.uniform(-reach, reach), world.uniform(-reach, reach),
                           world.uniform(-reach, reach));
      tested->ray_cast(origin, direction, 1, got_ids);
      reference.ray_cast(origin, direction, 1, want_ids);
      EXPECT_EQ(got_ids, want_ids) << "ray cast differs at step " << step;
    }
  }
  return compared;
}

// The whole suite: every layout, with enough pairs that the check means something.
inline void check_every_layout(const BroadPhaseFactory& make, const PropertyOptions& options = {}) {
  for (Layout layout : all_layouts()) {
    const std::int64_t compared = check_against_brute_force(make, layout, options);
    EXPECT_GT(compared, options.steps * property_scale())
        << layout_name(layout) << ": too few pairs to mean much";
  }
}

}  // namespace tumble::test
