// The contact solver's vector versions (AVX-512, AVX2, the SSE2 baseline) give the same bits, and
// the colours it solves side by side never share a moving body.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <random>
#include <set>

#include "dynamics/contact_graph.hpp"
#include "dynamics/contact_solver_wide.hpp"
#include "engine/simulation.hpp"
#include "tests/physics/scene_fixture.hpp"

namespace tumble::test {
namespace {

bool same_bits(const Vec3& a, const Vec3& b) {
  return std::memcmp(a.data(), b.data(), sizeof(Real) * 3) == 0;
}

// Contacts of a real scene (resting, tumbling and bouncing bodies of every shape), solved through
// a substep's passes by each version: the velocities and the stored impulses agree bit for bit.
TEST(ContactLanes, EveryInstructionSetGivesTheSameBits) {
  const detail::WideKernels* versions[3];
  const int count = detail::available_wide_kernels(versions, 3);
  ASSERT_GE(count, 1);
  std::printf("[lanes] %d versions on this CPU, widest %d lanes\n", count, versions[0]->lanes);
  int compared = 0;
  for (const char* file : {"demo.yaml", "bench/pyramid_20.yaml", "shapes_drop.yaml"}) {
    Simulation world(shipped_scene(file));
    for (int k = 0; k < 90; ++k)
      world.step();
    const std::vector<PairContact> contacts(world.contacts().begin(), world.contacts().end());
    ASSERT_FALSE(contacts.empty()) << file;
    ContactSolverSettings settings;
    settings.substep = world.scene().world.dt / 4;
    std::vector<std::vector<BodyState>> results;
    std::vector<std::vector<CachedManifold>> caches;
    for (int v = 0; v < count; ++v) {
      std::vector<BodyState> bodies = world.state().bodies;
      std::vector<BodyMass> masses;
      for (std::size_t i = 0; i < bodies.size(); ++i)
        masses.push_back(world.mass(int(i)));
      ContactSolver solver(*versions[v]);
      solver.prepare(contacts, world.state().contacts, bodies, masses, settings);
      solver.resolve_impacts(bodies);
      solver.warm_start(bodies);
      for (int pass = 0; pass < 3; ++pass)
        solver.solve(bodies, true);
      for (BodyState& b : bodies)
        b.position += settings.substep * b.velocity;
      solver.solve(bodies, false);
      solver.apply_restitution(bodies);
      std::vector<CachedManifold> cache;
      solver.store(cache);
      results.push_back(bodies);
      caches.push_back(cache);
    }
    for (int v = 1; v < count; ++v) {
      for (std::size_t i = 0; i < results[0].size(); ++i) {
        EXPECT_TRUE(same_bits(results[0][i].velocity, results[std::size_t(v)][i].velocity))
            << file << " body " << i << " lanes " << versions[v]->lanes;
        EXPECT_TRUE(
            same_bits(results[0][i].angular_velocity, results[std::size_t(v)][i].angular_velocity))
            << file << " body " << i;
      }
      for (std::size_t m = 0; m < caches[0].size(); ++m) {
        for (int p = 0; p < caches[0][m].count; ++p) {
          EXPECT_EQ(
              std::bit_cast<std::uint64_t>(caches[0][m].points[p].normal_impulse),
              std::bit_cast<std::uint64_t>(caches[std::size_t(v)][m].points[p].normal_impulse))
              << file << " manifold " << m;
        }
      }
      ++compared;
    }
    // Something happened: the passes changed velocities.
    bool moved = false;
    for (std::size_t i = 0; i < results[0].size(); ++i)
      moved = moved || !same_bits(results[0][i].velocity, world.state().bodies[i].velocity);
    EXPECT_TRUE(moved) << file;
  }
  if (count == 1)
    GTEST_SKIP() << "only the baseline runs on this CPU: nothing to compare";
  EXPECT_GT(compared, 0);
}

// Random pair sets, some with a body in far more pairs than there are colours: every pair is
// visited once, no two pairs of a colour share a moving slot (slot 0, static, may repeat), and
// the overflow holds exactly the pairs that found no colour.
// The pack computes the tangent masses and the normal rows' coupling terms in the lanes with the
// sums associated as Eigen's 3x3 product and dot product associate them (times_whole and dot in
// dynamics/contact_solver_lanes.inc), so that moving them out of the scalar build changed no bit.
// Should Eigen's summation change (another version, a vectorisation switch, FMA in its packets),
// this test says why the golden hashes moved.
TEST(ContactLanes, EigenSumsThreeByThreeProductsAsThePackAssumes) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<Real> unit(-1, 1);
  for (int k = 0; k < 20000; ++k) {
    Mat3 m;
    Vec3 v, w;
    for (int e = 0; e < 9; ++e) {
      const Real entry = unit(random) * Real(e + 1);
      m(e / 3, e % 3) = entry;
    }
    for (int c = 0; c < 3; ++c) {
      const Real x = unit(random) * Real(10);
      v[c] = x;
      const Real y = unit(random);
      w[c] = y;
    }
    const Vec3 product = m * v;
    const Real p[3][3] = {{m(0, 0) * v[0], m(0, 1) * v[1], m(0, 2) * v[2]},
                          {m(1, 0) * v[0], m(1, 1) * v[1], m(1, 2) * v[2]},
                          {m(2, 0) * v[0], m(2, 1) * v[1], m(2, 2) * v[2]}};
    ASSERT_EQ(std::bit_cast<std::uint64_t>(product[0]),
              std::bit_cast<std::uint64_t>((p[0][0] + p[0][1]) + p[0][2]));
    ASSERT_EQ(std::bit_cast<std::uint64_t>(product[1]),
              std::bit_cast<std::uint64_t>((p[1][0] + p[1][1]) + p[1][2]));
    ASSERT_EQ(std::bit_cast<std::uint64_t>(product[2]),
              std::bit_cast<std::uint64_t>(p[2][0] + (p[2][1] + p[2][2])));
    ASSERT_EQ(std::bit_cast<std::uint64_t>(v.dot(w)),
              std::bit_cast<std::uint64_t>((v[0] * w[0] + v[1] * w[1]) + v[2] * w[2]));
  }
}

TEST(ContactGraph, ColoursNeverShareAMovingBodyAndCoverEveryPairOnce) {
  std::mt19937 random(20261125);
  ContactGraph graph;
  for (int trial = 0; trial < 2000; ++trial) {
    const int slots = 2 + int(random() % 200);
    const int pairs = int(random() % 600);
    const bool star = trial % 10 == 0;  // one body in every pair: forces the overflow
    std::vector<std::int32_t> a(static_cast<std::size_t>(pairs));
    std::vector<std::int32_t> b(static_cast<std::size_t>(pairs));
    for (int i = 0; i < pairs; ++i) {
      a[std::size_t(i)] = star ? 1 : std::int32_t(random() % std::uint32_t(slots));
      do {
        b[std::size_t(i)] = std::int32_t(random() % std::uint32_t(slots));
      } while (b[std::size_t(i)] == a[std::size_t(i)] ||
               (a[std::size_t(i)] == 0 && b[std::size_t(i)] == 0));
    }
    graph.build(a, b, slots);
    std::vector<int> seen(std::size_t(pairs), 0);
    int overflow = 0;
    for (const ContactGraph::Group& g : graph.groups()) {
      std::set<std::int32_t> used;
      for (std::int32_t k = g.begin; k < g.end; ++k) {
        const std::int32_t p = graph.order()[std::size_t(k)];
        ++seen[std::size_t(p)];
        if (g.sequential) {
          ++overflow;
          continue;
        }
        for (std::int32_t s : {a[std::size_t(p)], b[std::size_t(p)]}) {
          if (s != 0) {
            ASSERT_TRUE(used.insert(s).second)
                << "trial " << trial << ": slot " << s << " twice in one colour";
          }
        }
      }
    }
    for (int i = 0; i < pairs; ++i)
      ASSERT_EQ(seen[std::size_t(i)], 1) << "trial " << trial << " pair " << i;
    EXPECT_EQ(overflow, graph.overflow_pairs());
    if (star && pairs > ContactGraph::kColors) {
      EXPECT_EQ(overflow, pairs - ContactGraph::kColors) << "trial " << trial;
    }
    EXPECT_LE(graph.color_count(), ContactGraph::kColors);
  }
}

}  // namespace
}  // namespace tumble::test
