// The SIMD scans of hull_support_scan.hpp against brute force written here: the first index of
// the largest v . d (of the smallest value for first_smallest), with exact ties, zero, NaN and
// infinite directions, on every instruction-set version this machine has; place_hull against
// the transform written out; and ConvexHull::support_index (which scans hulls up to
// kHullScanLimit vertices) against the brute-force maximum.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/hull_support_scan.hpp"
#include "tests/collision/oracle.hpp"
#include "tests/property_scale.hpp"

namespace tumble::testing {
namespace {

constexpr Real kInf = std::numeric_limits<Real>::infinity();
constexpr Real kNan = std::numeric_limits<Real>::quiet_NaN();

// Padded structure-of-arrays storage, filled as ConvexHull fills it (padding: vertex 0).
struct Arrays {
  std::vector<Real> data;
  int padded = 0;
  explicit Arrays(const std::vector<Vec3>& points) {
    const int n = int(points.size());
    padded = (n + kHullScanWidth - 1) / kHullScanWidth * kHullScanWidth;
    data.assign(std::size_t(3 * padded), 0);
    for (int i = 0; i < padded; ++i)
      for (int k = 0; k < 3; ++k)
        data[std::size_t(k * padded + i)] = points[std::size_t(i < n ? i : 0)][k];
  }
  HullScanArrays view() const {
    const Real* x = data.data();
    return {x, x + padded, x + 2 * padded, padded};
  }
};

// The contract, written independently: values as fma(z, dz, fma(y, dy, x dx)), the first index of
// the largest, NaN never wins, 0 when nothing is above -inf.
int first_largest(const std::vector<Vec3>& points, const Vec3& d) {
  int best = 0;
  Real best_value = -kInf;
  for (int i = 0; i < int(points.size()); ++i) {
    const Vec3& p = points[std::size_t(i)];
    const Real value = std::fma(p.z(), d.z(), std::fma(p.y(), d.y(), p.x() * d.x()));
    if (value > best_value) {
      best_value = value;
      best = i;
    }
  }
  return best;
}

// Every version of the scan this CPU can run gives `expected`.
void expect_every_version(const HullScanArrays& h, const Vec3& d, int expected) {
  EXPECT_EQ(scan_support(h, d), expected);
  EXPECT_EQ(scan_support_portable(h, d), expected);
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("fma")) {
    EXPECT_EQ(detail::scan_support_avx512(h, d), expected);
  }
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    EXPECT_EQ(detail::scan_support_avx2(h, d), expected);
  }
  const SupportPair pair = scan_support_pair(h, d, h, -d);
  EXPECT_EQ(pair.a, expected);
}

TEST(HullSupportScan, MatchesBruteForceOnRandomPointSets) {
  Rng rng(9001);
  const int sets = scaled(400);
  for (int s = 0; s < sets; ++s) {
    // 1 to 70 points, so that every padding length and block count occurs.
    const int n = 1 + s % 70;
    std::vector<Vec3> points;
    for (int i = 0; i < n; ++i)
      points.push_back(random_vector_in_box(rng, 2));
    const Arrays arrays(points);
    for (int k = 0; k < 30; ++k) {
      const Vec3 d = random_unit_vector(rng) * std::pow(10.0, double(k % 7) - 3);
      const int expected = first_largest(points, d);
      expect_every_version(arrays.view(), d, expected);
      // The other half of the pair sees the opposite direction.
      EXPECT_EQ(scan_support_pair(arrays.view(), d, arrays.view(), -d).b,
                first_largest(points, -d));
    }
  }
}

TEST(HullSupportScan, ExactTiesGoToTheFirstIndex) {
  // Box corners in an order where the tied corners are spread over lanes and blocks, with
  // repeated points: along an axis four or more values are exactly equal.
  std::vector<Vec3> points;
  for (int repeat = 0; repeat < 3; ++repeat)
    for (int v = 7; v >= 0; --v)
      points.emplace_back(v & 1 ? 1.0 : -1.0, v & 2 ? 2.0 : -2.0, v & 4 ? 3.0 : -3.0);
  const Arrays arrays(points);
  const std::vector<Vec3> directions = {{1, 0, 0},    {-1, 0, 0}, {0, 1, 0},         {0, -1, 0},
                                        {0, 0, 1},    {0, 0, -1}, {1, 1, 0},         {0, -1, 1},
                                        {-0.0, 0, 1}, {0, 0, 0},  {-0.0, -0.0, -0.0}};
  for (const Vec3& d : directions) {
    const int expected = first_largest(points, d);
    expect_every_version(arrays.view(), d, expected);
  }
  // The zero direction ties every vertex: the answer is 0.
  EXPECT_EQ(scan_support(arrays.view(), Vec3::Zero()), 0);
}

TEST(HullSupportScan, NanAndInfiniteDirectionsAgreeWithTheContract) {
  Rng rng(9002);
  std::vector<Vec3> points;
  for (int i = 0; i < 29; ++i)
    points.push_back(random_vector_in_box(rng, 1));
  points.push_back(Vec3::Zero());  // a zero coordinate makes inf * 0 = NaN
  const Arrays arrays(points);
  const std::vector<Vec3> directions = {{kNan, 0, 0},  {kNan, kNan, kNan},   {kInf, 0, 0},
                                        {-kInf, 1, 0}, {kInf, -kInf, 0},     {1, kNan, 1},
                                        {0, 0, kInf},  {1e300, 1e300, 1e300}};
  for (const Vec3& d : directions) {
    const int expected = first_largest(points, d);
    expect_every_version(arrays.view(), d, expected);
  }
  // A NaN direction makes every value NaN: nothing wins, the answer is 0.
  EXPECT_EQ(scan_support(arrays.view(), Vec3(kNan, kNan, kNan)), 0);
}

int first_smallest_reference(const std::vector<Real>& values) {
  int best = -1;
  Real best_value = kInf;
  for (int i = 0; i < int(values.size()); ++i) {
    if (values[std::size_t(i)] < best_value) {
      best_value = values[std::size_t(i)];
      best = i;
    }
  }
  return best;
}

TEST(HullSupportScan, FirstSmallestMatchesBruteForceWithGapsTiesAndNan) {
  Rng rng(9003);
  std::uniform_int_distribution<int> kind(0, 9);
  const int arrays = scaled(3000);
  for (int s = 0; s < arrays; ++s) {
    // Up to 66 blocks, past the 64 entries of one mask word several times over.
    const int padded = kHullScanWidth * (1 + s % 66);
    std::vector<Real> values(static_cast<std::size_t>(padded));
    for (Real& v : values) {
      const int k = kind(rng);
      // Free slots (+inf), NaN, exact ties among a few small integers, -0 against +0, and
      // ordinary values of both signs.
      v = k < 3    ? kInf
          : k == 3 ? kNan
          : k < 6  ? Real(int(random_vector_in_box(rng, 3).x()))
          : k == 6 ? -0.0
                   : random_vector_in_box(rng, 1e3).x();
    }
    if (s % 50 == 0)
      std::fill(values.begin(), values.end(), kInf);  // nothing live: -1
    const int expected = first_smallest_reference(values);
    EXPECT_EQ(first_smallest(values.data(), padded), expected);
    EXPECT_EQ(first_smallest_portable(values.data(), padded), expected);
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("fma")) {
      EXPECT_EQ(detail::first_smallest_avx512(values.data(), padded), expected);
    }
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
      EXPECT_EQ(detail::first_smallest_avx2(values.data(), padded), expected);
    }
  }
}

TEST(HullSupportScan, PlacedHullIsTheTransformWrittenOut) {
  Rng rng(9004);
  for (int s = 0; s < scaled(200); ++s) {
    std::vector<Vec3> points;
    for (int i = 0; i < 1 + s % 64; ++i)
      points.push_back(random_vector_in_box(rng, 5));
    const Arrays arrays(points);
    const Mat3 r = random_rotation(rng).toRotationMatrix();
    const Vec3 t = random_vector_in_box(rng, 100);
    std::vector<Real> out(std::size_t(3 * arrays.padded));
    const HullScanArrays placed = place_hull(arrays.view(), r, t, out.data());
    ASSERT_EQ(placed.padded_count, arrays.padded);
    for (int i = 0; i < arrays.padded; ++i) {
      const Vec3& p = points[std::size_t(i < int(points.size()) ? i : 0)];
      // Bit for bit: the same operations in the same order, whatever the instruction set.
      EXPECT_EQ(placed.x[i], ((r(0, 0) * p.x() + r(0, 1) * p.y()) + r(0, 2) * p.z()) + t.x());
      EXPECT_EQ(placed.y[i], ((r(1, 0) * p.x() + r(1, 1) * p.y()) + r(1, 2) * p.z()) + t.y());
      EXPECT_EQ(placed.z[i], ((r(2, 0) * p.x() + r(2, 1) * p.y()) + r(2, 2) * p.z()) + t.z());
    }
  }
}

TEST(HullSupportScan, SmallHullsSupportIndexIsTheExactMaximum) {
  Rng rng(9005);
  for (int s = 0; s < scaled(100); ++s) {
    std::vector<Vec3> points;
    for (int i = 0; i < 12 + s % 40; ++i)
      points.push_back(random_unit_vector(rng).cwiseProduct(Vec3(0.6, 0.5, 0.4)));
    const ConvexHull hull = ConvexHull::from_points(points);
    ASSERT_LE(int(hull.vertices().size()), kHullScanLimit);
    const std::vector<Vec3> vertices(hull.vertices().begin(), hull.vertices().end());
    for (int k = 0; k < 50; ++k) {
      const Vec3 d = random_unit_vector(rng);
      EXPECT_EQ(hull.support_index(d, k % int(vertices.size())), first_largest(vertices, d));
    }
  }
}

TEST(HullSupportScan, BigHullsHaveNoScanArraysAndClimb) {
  Rng rng(9006);
  std::vector<Vec3> points;
  for (int i = 0; i < 300; ++i)
    points.push_back(random_unit_vector(rng));
  const ConvexHull hull = ConvexHull::from_points(points);
  ASSERT_GT(int(hull.vertices().size()), kHullScanLimit);
  EXPECT_EQ(hull.scan_arrays().x, nullptr);
  EXPECT_EQ(hull.scan_arrays().padded_count, 0);
  for (int k = 0; k < 200; ++k) {
    const Vec3 d = random_unit_vector(rng);
    Real best = -kInf;
    for (const Vec3& v : hull.vertices())
      best = std::max(best, v.dot(d));
    // The climb's answer is a vertex of largest value (ties may pick another index).
    EXPECT_NEAR(hull.vertex(hull.support_index(d, k % 50)).dot(d), best, 1e-15);
  }
}

}  // namespace
}  // namespace tumble::testing
