// The batched box-box path against collide(), the per-pair narrow phase it stands in for, on
// 130,000 random pairs in seven regimes (deep and shallow random poses, boxes resting face on face
// with a random turn and tilt, the same exactly aligned, resting boxes apart by up to 1 cm within
// a 2 cm margin, equal boxes with corners and edges on each other's, and all of it 1e6 m from the
// origin), with and without a margin:
//   - the same number of points, the same normal and the same deepest depth in every pair;
//   - in all but a few pairs the same points with the same feature ids; where the four points are
//     chosen among more and the choice has ties (points on an edge parallel to the line through
//     the first two), another tied vertex may be kept: then every point must still lie on both
//     boxes' surfaces (the point on A on A's boundary, the point on B on B's);
// and the instruction-set versions give the same bits, so do a pair alone and the pair among
// others (whichever order of passes its chunk takes), swapping the boxes flips the normal and
// nothing else, non-finite poses give a valid manifold, and a too-small output an error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "collision/narrow_phase/box_batch.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"
#include "tests/collision/oracle.hpp"
#include "tests/property_scale.hpp"

namespace tumble::testing {
namespace {

enum class Regime { deep, shallow, resting, aligned, far, gap, coincident };

std::vector<BoxPairQuery> random_pairs(Regime regime, int count, std::uint64_t seed,
                                       Real margin = 0) {
  Rng rng(seed);
  std::vector<BoxPairQuery> pairs;
  for (int i = 0; i < count; ++i) {
    const Vec3 ha(uniform(rng, 0.05, 1), uniform(rng, 0.05, 1), uniform(rng, 0.05, 1));
    const Vec3 hb =
        i % 4 == 0 ? ha : Vec3(uniform(rng, 0.05, 1), uniform(rng, 0.05, 1), uniform(rng, 0.05, 1));
    Transform a{Vec3::Zero(), random_rotation(rng)};
    Transform b;
    const Real reach = ha.norm() + hb.norm();
    if (regime == Regime::coincident) {
      // Equal boxes face on face, turned by 0 or 90 degrees, shifted along one face axis or not
      // at all: corners on the other face's corners and edges on its edges, where the clipper
      // finds some vertices twice and merges them.
      const Vec3 same(ha.x(), ha.x(), ha.z());
      const int kind = i % 4;
      const Quat turn(Eigen::AngleAxis<Real>(kind == 3 ? Real(M_PI / 2) : Real(0), Vec3::UnitZ()));
      const Real shift = uniform(rng, -1, 1) * same.x();
      const Vec3 offset(kind == 1 ? shift : 0, kind == 2 ? shift : 0,
                        2 * same.z() - uniform(rng, 0, 0.01));
      pairs.push_back({same, a, same, {a.rotation * offset, a.rotation * turn}});
      continue;
    }
    if (regime == Regime::deep) {
      b = {random_unit_vector(rng) * reach * uniform(rng, 0.1, 0.8), random_rotation(rng)};
    } else if (regime == Regime::shallow) {
      b = {random_unit_vector(rng) * reach * uniform(rng, 0.6, 1.2), random_rotation(rng)};
    } else {
      const bool aligned = regime == Regime::aligned;
      const Quat turn(
          Eigen::AngleAxis<Real>(aligned ? Real(0) : uniform(rng, -M_PI, M_PI), Vec3::UnitZ()));
      const Quat tilt(Eigen::AngleAxis<Real>(aligned ? Real(0) : uniform(rng, 0, 0.01),
                                             random_unit_vector(rng)));
      // `gap`: apart by up to 1 cm, within the margin the test gives.
      const Real sink = regime == Regime::gap ? -uniform(rng, 0, 0.01) : uniform(rng, 0, 0.01);
      const Vec3 offset(uniform(rng, -0.3, 0.3), uniform(rng, -0.3, 0.3), ha.z() + hb.z() - sink);
      b = {a.rotation * offset, a.rotation * tilt * turn};
    }
    if (regime == Regime::far) {
      a.translation += Vec3(1e6, -1e6, 1e6);
      b.translation += Vec3(1e6, -1e6, 1e6);
    }
    pairs.push_back({ha, a, hb, b, margin});
  }
  return pairs;
}

Manifold collide_one(const BoxPairQuery& q) {
  Manifold m;
  collide(Shape::box(q.half_a), q.pose_a, Shape::box(q.half_b), q.pose_b, q.margin, m);
  return m;
}

// Index of the point of `m` at `position` (within `tolerance`), or -1.
int point_at(const Manifold& m, const Vec3& position, Real tolerance) {
  for (int p = 0; p < m.count; ++p) {
    if ((m.points[p].position - position).norm() <= tolerance)
      return p;
  }
  return -1;
}

void expect_matches_collide(Regime regime, Real margin, std::uint64_t seed) {
  const int count = scaled(10000);
  const std::vector<BoxPairQuery> pairs = random_pairs(regime, count, seed, margin);
  std::vector<Manifold> batch(pairs.size());
  collide_box_pairs(pairs, batch);
  int contacts = 0;
  int other_choice = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    SCOPED_TRACE("pair " + std::to_string(i));
    const BoxPairQuery& q = pairs[i];
    const Manifold expected = collide_one(q);
    const Manifold& got = batch[i];
    ASSERT_EQ(got.count, expected.count);
    if (expected.count == 0)
      continue;
    ++contacts;
    const Real size = q.half_a.norm() + q.half_b.norm();
    const Real tolerance = (regime == Regime::far ? 1e-9 : 1e-12) * (1 + size);
    EXPECT_GT(got.normal.dot(expected.normal), 1 - 1e-12);
    Real deepest_expected = -std::numeric_limits<Real>::infinity();
    Real deepest_got = -std::numeric_limits<Real>::infinity();
    for (int p = 0; p < expected.count; ++p) {
      deepest_expected = std::max(deepest_expected, expected.points[p].depth);
      deepest_got = std::max(deepest_got, got.points[p].depth);
    }
    EXPECT_NEAR(deepest_got, deepest_expected, tolerance);
    bool same_points = true;
    for (int p = 0; p < got.count; ++p) {
      const int match = point_at(expected, got.points[p].position, tolerance);
      if (match < 0) {
        same_points = false;
        continue;
      }
      EXPECT_NEAR(got.points[p].depth, expected.points[match].depth, tolerance);
      EXPECT_EQ(got.points[p].feature, expected.points[match].feature);
    }
    if (same_points)
      continue;
    ++other_choice;
    // Another tied vertex: every point joins the two surfaces.
    const Shape a = Shape::box(q.half_a);
    const Shape b = Shape::box(q.half_b);
    for (int p = 0; p < got.count; ++p) {
      const ContactPoint& c = got.points[p];
      EXPECT_NEAR(signed_distance_to_shape(a, q.pose_a, c.point_on_a(got.normal)), 0,
                  1e3 * tolerance);
      EXPECT_NEAR(signed_distance_to_shape(b, q.pose_b, c.point_on_b(got.normal)), 0,
                  1e3 * tolerance);
    }
  }
  EXPECT_GT(contacts, count / 10);
  EXPECT_LE(other_choice, contacts / 100);
  std::printf(
      "[ stats    ] box batch vs collide, regime %d, margin %g: %d pairs, %d in contact, "
      "%d with another tied choice of points\n",
      int(regime), margin, count, contacts, other_choice);
}

struct RegimeCase {
  const char* name;
  Regime regime;
  Real margin;
  std::uint64_t seed;
};

class BoxBatchRegime : public ::testing::TestWithParam<RegimeCase> {};

TEST_P(BoxBatchRegime, MatchesCollide) {
  expect_matches_collide(GetParam().regime, GetParam().margin, GetParam().seed);
}

INSTANTIATE_TEST_SUITE_P(
    BoxBatch, BoxBatchRegime,
    ::testing::Values(RegimeCase{"deep", Regime::deep, 0, 11},
                      RegimeCase{"deep_margin", Regime::deep, 0.01, 12},
                      RegimeCase{"shallow", Regime::shallow, 0, 13},
                      RegimeCase{"shallow_margin", Regime::shallow, 0.01, 14},
                      RegimeCase{"resting", Regime::resting, 0, 15},
                      RegimeCase{"resting_margin", Regime::resting, 0.01, 16},
                      RegimeCase{"aligned", Regime::aligned, 0, 17},
                      RegimeCase{"aligned_margin", Regime::aligned, 0.01, 18},
                      RegimeCase{"far", Regime::far, 0, 19},
                      RegimeCase{"apart_within_margin", Regime::gap, 0.02, 23},
                      RegimeCase{"coincident", Regime::coincident, 0, 25},
                      RegimeCase{"coincident_margin", Regime::coincident, 0.01, 26}),
    [](const ::testing::TestParamInfo<RegimeCase>& info) { return std::string(info.param.name); });

bool same_bits(const Manifold& a, const Manifold& b) {
  if (a.count != b.count || std::memcmp(a.normal.data(), b.normal.data(), 3 * sizeof(Real)) != 0)
    return false;
  for (int p = 0; p < a.count; ++p) {
    const ContactPoint& x = a.points[p];
    const ContactPoint& y = b.points[p];
    if (std::memcmp(x.position.data(), y.position.data(), 3 * sizeof(Real)) != 0 ||
        std::memcmp(&x.depth, &y.depth, sizeof(Real)) != 0 || !(x.feature == y.feature)) {
      return false;
    }
  }
  return true;
}

TEST(BoxBatch, EveryInstructionSetGivesTheSameBits) {
  std::vector<BoxPairQuery> pairs;
  for (Regime regime : {Regime::deep, Regime::shallow, Regime::resting, Regime::aligned,
                        Regime::far, Regime::gap}) {
    // Margins of 0 and 0.01 and, every fifth pair, one that differs pair by pair.
    auto some = random_pairs(regime, scaled(2000) + 3, 20 + std::uint64_t(regime), 0.01);
    for (std::size_t i = 0; i < some.size(); ++i)
      some[i].margin = i % 5 == 0 ? Real(0.002) * Real(i % 7) : (i % 2 == 0 ? 0 : 0.01);
    pairs.insert(pairs.end(), some.begin(), some.end());
  }
  std::vector<Manifold> portable(pairs.size());
  detail::collide_box_pairs_portable(pairs, portable);
  __builtin_cpu_init();
  struct Version {
    const char* name;
    bool supported;
    int (*run)(std::span<const BoxPairQuery>, std::span<Manifold>);
  };
  const Version vector_versions[] = {
      {"AVX2", __builtin_cpu_supports("avx2") != 0, detail::collide_box_pairs_avx2},
      {"AVX-512", __builtin_cpu_supports("avx512f") != 0, detail::collide_box_pairs_avx512}};
  int versions = 0;
  for (const Version& version : vector_versions) {
    if (!version.supported)
      continue;
    std::vector<Manifold> out(pairs.size());
    version.run(pairs, out);
    for (std::size_t i = 0; i < pairs.size(); ++i)
      ASSERT_TRUE(same_bits(out[i], portable[i])) << version.name << ", pair " << i;
    ++versions;
  }
  std::vector<Manifold> dispatched(pairs.size());
  collide_box_pairs(pairs, dispatched);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    ASSERT_TRUE(same_bits(dispatched[i], portable[i])) << "dispatched, pair " << i;
    ASSERT_EQ(dispatched[i].count, collide_one(pairs[i]).count) << "pair " << i;
  }
  std::printf(
      "[ stats    ] box batch: %zu pairs, %d vector versions besides the portable one "
      "compared bit for bit\n",
      pairs.size(), versions);
}

// A chunk of pairs takes either order of passes: sorted by the separating-axis test first (apart
// pairs done, face pairs to the face pass, edge pairs to the edge pass, each testing only its
// own axes), or the face pass first, which leaves the edge pairs to the edge pass. The order must
// not change any answer, in any version: every version in every order gives the bits of the
// baseline version in its own (adaptive) order, and a pair alone gives the bits it gets among
// others.
TEST(BoxBatch, ThePassOrderDoesNotChangeAnAnswer) {
  std::vector<BoxPairQuery> pairs;
  int edge_contacts = 0;
  int face_contacts = 0;
  for (Regime regime : {Regime::deep, Regime::resting, Regime::shallow, Regime::gap,
                        Regime::coincident, Regime::far}) {
    auto some = random_pairs(regime, scaled(1500), 70 + std::uint64_t(regime), 0.01);
    for (std::size_t i = 0; i < some.size(); ++i)
      some[i].margin = i % 3 == 0 ? 0 : Real(0.001) * Real(i % 11);
    for (const BoxPairQuery& q : some) {
      const Manifold m = collide_one(q);
      const auto is_edge = [](std::uint16_t f) {
        return f >= detail::feature::kBoxFirstEdge && f < detail::feature::kBoxFirstFace;
      };
      const bool edge =
          m.count == 1 && is_edge(m.points[0].feature.a) && is_edge(m.points[0].feature.b);
      edge_contacts += edge ? 1 : 0;
      face_contacts += m.count >= 2 ? 1 : 0;
    }
    pairs.insert(pairs.end(), some.begin(), some.end());
  }
  EXPECT_GT(edge_contacts, scaled(1500) / 4);
  EXPECT_GT(face_contacts, scaled(1500) * 2);
  std::vector<Manifold> reference(pairs.size());
  detail::collide_box_pairs_in_order(pairs, reference, 2, detail::BoxBatchOrder::adaptive);
  __builtin_cpu_init();
  std::vector<int> widths = {2};
  if (__builtin_cpu_supports("avx2"))
    widths.push_back(4);
  if (__builtin_cpu_supports("avx512f"))
    widths.push_back(8);
  for (int lanes : widths) {
    for (detail::BoxBatchOrder order :
         {detail::BoxBatchOrder::sort_first, detail::BoxBatchOrder::face_first,
          detail::BoxBatchOrder::adaptive}) {
      std::vector<Manifold> out(pairs.size());
      detail::collide_box_pairs_in_order(pairs, out, lanes, order);
      for (std::size_t i = 0; i < pairs.size(); ++i) {
        ASSERT_TRUE(same_bits(out[i], reference[i]))
            << lanes << " lanes, order " << int(order) << ", pair " << i;
      }
    }
  }
  for (std::size_t i = 0; i < pairs.size(); i += 7) {
    Manifold alone;
    collide_box_pairs(std::span(&pairs[i], 1), std::span(&alone, 1));
    ASSERT_TRUE(same_bits(alone, reference[i])) << "pair " << i << " alone";
  }
  std::vector<Manifold> out(1);
  EXPECT_THROW(detail::collide_box_pairs_in_order(pairs, out, 3, detail::BoxBatchOrder::adaptive),
               std::invalid_argument);
}

// collide()'s swap rule, for the batch: the pair given as (B, A) gets the opposite normal, the same
// points (bit for bit) and each feature id with its two sides exchanged.
TEST(BoxBatch, SwappingTheBoxesFlipsTheNormalAndNothingElse) {
  std::vector<BoxPairQuery> pairs;
  for (Regime regime : {Regime::deep, Regime::shallow, Regime::resting, Regime::aligned,
                        Regime::gap, Regime::coincident, Regime::far}) {
    const auto some = random_pairs(regime, scaled(3000), 90 + std::uint64_t(regime), 0.01);
    pairs.insert(pairs.end(), some.begin(), some.end());
  }
  std::vector<BoxPairQuery> swapped;
  for (const BoxPairQuery& q : pairs)
    swapped.push_back({q.half_b, q.pose_b, q.half_a, q.pose_a, q.margin});
  std::vector<Manifold> forward(pairs.size()), backward(pairs.size());
  collide_box_pairs(pairs, forward);
  collide_box_pairs(swapped, backward);
  int contacts = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Manifold& x = forward[i];
    const Manifold& y = backward[i];
    ASSERT_EQ(x.count, y.count) << "pair " << i;
    contacts += x.count > 0 ? 1 : 0;
    if (x.count == 0)
      continue;
    ASSERT_TRUE(x.normal == Vec3(-y.normal)) << "pair " << i;
    for (int p = 0; p < x.count; ++p) {
      ASSERT_EQ(
          std::memcmp(x.points[p].position.data(), y.points[p].position.data(), 3 * sizeof(Real)),
          0)
          << "pair " << i << " point " << p;
      ASSERT_EQ(x.points[p].depth, y.points[p].depth) << "pair " << i << " point " << p;
      ASSERT_TRUE(x.points[p].feature == y.points[p].feature.swapped())
          << "pair " << i << " point " << p;
    }
  }
  EXPECT_GT(contacts, int(pairs.size()) / 2);
}

TEST(BoxBatch, NonFinitePosesGiveAValidManifold) {
  constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();
  constexpr Real kInfinity = std::numeric_limits<Real>::infinity();
  const Vec3 half(0.5, 0.4, 0.3);
  const Transform at_origin{Vec3::Zero(), Quat::Identity()};
  const std::vector<Transform> bad = {Transform{Vec3(kNaN, 0, 0.5), Quat::Identity()},
                                      Transform{Vec3(0, 0, kInfinity), Quat::Identity()},
                                      Transform{Vec3(0, 0, 0.5), Quat(kNaN, 0, 0, 0)},
                                      Transform{Vec3(0, 0, 0.5), Quat(kInfinity, 0, 1, 0)}};
  std::vector<BoxPairQuery> pairs;
  for (const Transform& pose : bad) {
    pairs.push_back({half, at_origin, half, pose, 0.01});
    pairs.push_back({half, pose, half, at_origin, 0.01});
    pairs.push_back({half, at_origin, half, Transform{Vec3(0, 0, 0.5), Quat::Identity()}, 0.01});
  }
  std::vector<Manifold> out(pairs.size());
  collide_box_pairs(pairs, out);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Manifold expected = collide_one(pairs[i]);
    EXPECT_EQ(out[i].count, expected.count) << "pair " << i;
    EXPECT_LE(out[i].count, kMaxManifoldPoints);
    for (int p = 0; p < out[i].count; ++p) {
      EXPECT_LT(out[i].points[p].feature.a, 26);
      EXPECT_LT(out[i].points[p].feature.b, 26);
    }
  }
}

TEST(BoxBatch, BoxOrderIsCollidesOrder) {
  // detail::boxes_run_first must order two boxes as detail::runs_first orders their Shapes:
  // different sizes, equal sizes, equal sizes at one position (the pose coefficients decide).
  Rng rng(41);
  int equal_sizes = 0;
  for (int i = 0; i < scaled(20000); ++i) {
    const Vec3 ha(uniform(rng, 0.1, 1), uniform(rng, 0.1, 1), uniform(rng, 0.1, 1));
    const Vec3 hb = i % 3 == 0 ? ha : Vec3(ha.x(), i % 3 == 1 ? uniform(rng, 0.1, 1) : ha.y(), 0.5);
    const Transform a{random_vector_in_box(rng, 2), random_rotation(rng)};
    const Transform b{i % 5 == 0 ? a.translation : random_vector_in_box(rng, 2),
                      random_rotation(rng)};
    EXPECT_EQ(detail::boxes_run_first(ha, a, hb, b),
              detail::runs_first(Shape::box(ha), a, Shape::box(hb), b))
        << "case " << i;
    equal_sizes += ha == hb ? 1 : 0;
  }
  EXPECT_GT(equal_sizes, scaled(20000) / 4);
}

TEST(BoxBatch, AnyNumberOfPairsAndATooSmallOutput) {
  const auto pairs = random_pairs(Regime::deep, 13, 31);
  std::vector<Manifold> out(pairs.size());
  collide_box_pairs(pairs, out);
  for (std::size_t i = 0; i < pairs.size(); ++i)
    EXPECT_EQ(out[i].count, collide_one(pairs[i]).count) << "pair " << i;
  EXPECT_EQ(collide_box_pairs({}, {}), 0);
  std::vector<Manifold> short_out(pairs.size() - 1);
  EXPECT_THROW(collide_box_pairs(pairs, short_out), std::invalid_argument);
}

}  // namespace
}  // namespace tumble::testing
