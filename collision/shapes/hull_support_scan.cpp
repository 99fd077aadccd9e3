// SIMD support scan (see hull_support_scan.hpp).
#include "collision/shapes/hull_support_scan.hpp"

// GCC 12's AVX-512 headers start some intrinsics from _mm512_undefined_pd(), which
// -Wuninitialized reports as a use of an uninitialised value (GCC bug 105593, fixed in 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#if defined(__clang__)
// clang counts a version of a multi-versioned function in an anonymous namespace as unused
// (only the dispatcher reaches it).
#pragma clang diagnostic ignored "-Wunused-function"
#else
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace tumble {
namespace {

constexpr Real kLowest = -std::numeric_limits<Real>::infinity();
constexpr Real kHighest = std::numeric_limits<Real>::infinity();

// Each version finds the extreme value first and its index after: a max (or min) over the
// blocks in two accumulators (even and odd blocks, to halve the chain), then across the lanes,
// which leaves the extreme in every lane; then each block is compared with it for equality and
// the first set bit of the combined masks is the answer. Against carrying (value, index) pairs
// through the reduction this takes one instruction per block instead of three, and the merges
// of the lanes are a shuffle and a max each. Up to 64 entries the blocks stay in registers;
// past that (EPA's closest face on a big polytope) the comparisons recompute them. MAX and MIN
// return their second operand when either is NaN, and the accumulator (never NaN) is always the
// second: a NaN never enters, and never equals the extreme. -0 and +0 compare equal, so they tie
// and the first wins, as in the portable loops.

// The values of eight (four) consecutive entries: v . d of vertices, or an array's entries.
struct DotValues {
  const HullScanArrays& h;
  const Vec3& d;
  __attribute__((target("avx512f,fma"), always_inline)) __m512d at8(int i, __m512d dx, __m512d dy,
                                                                    __m512d dz) const {
    const __m512d xy =
        _mm512_fmadd_pd(_mm512_loadu_pd(h.y + i), dy, _mm512_mul_pd(_mm512_loadu_pd(h.x + i), dx));
    return _mm512_fmadd_pd(_mm512_loadu_pd(h.z + i), dz, xy);
  }
  __attribute__((target("avx2,fma"), always_inline)) __m256d at4(int i, __m256d dx, __m256d dy,
                                                                 __m256d dz) const {
    const __m256d xy =
        _mm256_fmadd_pd(_mm256_loadu_pd(h.y + i), dy, _mm256_mul_pd(_mm256_loadu_pd(h.x + i), dx));
    return _mm256_fmadd_pd(_mm256_loadu_pd(h.z + i), dz, xy);
  }
  // Each coordinate read on its own: a copy of the Vec3 was loaded as one pair, which waits
  // for the stores when the caller has just written the direction coordinate by coordinate.
  Real dx() const { return d.x(); }
  Real dy() const { return d.y(); }
  Real dz() const { return d.z(); }
  int count() const { return h.padded_count; }
};

struct ArrayValues {
  const Real* values;
  int padded_count;
  __attribute__((target("avx512f,fma"), always_inline)) __m512d at8(int i, __m512d, __m512d,
                                                                    __m512d) const {
    return _mm512_loadu_pd(values + i);
  }
  __attribute__((target("avx2,fma"), always_inline)) __m256d at4(int i, __m256d, __m256d,
                                                                 __m256d) const {
    return _mm256_loadu_pd(values + i);
  }
  Real dx() const { return 0; }
  Real dy() const { return 0; }
  Real dz() const { return 0; }
  int count() const { return padded_count; }
};

// The extreme: the largest (kLargest) or the smallest entry.
template <bool kLargest>
__attribute__((target("avx512f,fma"), always_inline)) inline __m512d extreme8(__m512d value,
                                                                              __m512d accumulator) {
  return kLargest ? _mm512_max_pd(value, accumulator) : _mm512_min_pd(value, accumulator);
}

// first_extreme8 on at most 64 entries (every scanned hull, and EPA's closest face up to 64
// faces), unrolled: the blocks' values stay in registers for the comparisons, and the masks are
// combined with constant shifts. No branch depends on the data (it would mispredict, and it
// kept the two scans of a pair from overlapping). An extreme still at the start value means
// nothing was found.
template <bool kLargest, class Values>
__attribute__((target("avx512f,fma"), always_inline)) inline int first_extreme8_upto64(
    const Values& values, __m512d dx, __m512d dy, __m512d dz) {
  constexpr Real kStart = kLargest ? kLowest : kHighest;
  const __m512d start = _mm512_set1_pd(kStart);
  const int count = values.count();
  // Blocks past the count are skipped by branches on the count alone (the same on every call
  // for a hull, so predicted): the zmm instructions, which only two ports run, bound the scan.
  __m512d block[8];
#pragma GCC unroll 8
  for (int k = 0; k < 8; ++k)
    block[k] = 8 * k < count ? values.at8(8 * k, dx, dy, dz) : start;
  __m512d even = extreme8<kLargest>(block[0], start);
  __m512d odd = count > 8 ? extreme8<kLargest>(block[1], start) : start;
#pragma GCC unroll 3
  for (int k = 2; k < 8; k += 2) {
    if (8 * k < count)
      even = extreme8<kLargest>(block[k], even);
    if (8 * k + 8 < count)
      odd = extreme8<kLargest>(block[k + 1], odd);
  }
  __m512d best = extreme8<kLargest>(odd, even);
  best = extreme8<kLargest>(_mm512_shuffle_f64x2(best, best, 0x4E), best);
  best = extreme8<kLargest>(_mm512_shuffle_f64x2(best, best, 0xB1), best);
  best = extreme8<kLargest>(_mm512_permute_pd(best, 0x55), best);
  std::uint64_t equal = 0;
#pragma GCC unroll 8
  for (int k = 0; k < 8; ++k)
    if (8 * k < count)
      equal |= std::uint64_t(_mm512_cmp_pd_mask(block[k], best, _CMP_EQ_OQ)) << (8 * k);
  return _mm512_cvtsd_f64(best) != kStart ? std::countr_zero(equal) : -1;
}

// The first index of the extreme value, or -1 when nothing is above -inf (for the largest) or
// below +inf (for the smallest): every entry NaN or that infinity.
template <bool kLargest, class Values>
__attribute__((target("avx512f,fma"), always_inline)) inline int first_extreme8(
    const Values& values) {
  constexpr Real kStart = kLargest ? kLowest : kHighest;
  const __m512d dx = _mm512_set1_pd(values.dx());
  const __m512d dy = _mm512_set1_pd(values.dy());
  const __m512d dz = _mm512_set1_pd(values.dz());
  const int count = values.count();
  if (count <= 64)
    return first_extreme8_upto64<kLargest>(values, dx, dy, dz);
  __m512d best0 = _mm512_set1_pd(kStart);
  __m512d best1 = best0;
  int i = 0;
  for (; i + 16 <= count; i += 16) {
    best0 = extreme8<kLargest>(values.at8(i, dx, dy, dz), best0);
    best1 = extreme8<kLargest>(values.at8(i + 8, dx, dy, dz), best1);
  }
  if (i < count)
    best0 = extreme8<kLargest>(values.at8(i, dx, dy, dz), best0);
  __m512d best = extreme8<kLargest>(best1, best0);
  best = extreme8<kLargest>(_mm512_shuffle_f64x2(best, best, 0x4E), best);
  best = extreme8<kLargest>(_mm512_shuffle_f64x2(best, best, 0xB1), best);
  best = extreme8<kLargest>(_mm512_permute_pd(best, 0x55), best);
  // Past 64 entries (EPA's closest face on a big polytope): the first 64-entry word that holds
  // the extreme.
  if (_mm512_cvtsd_f64(best) == kStart)
    return -1;
  for (int base = 0;; base += 64) {
    const int end = count < base + 64 ? count : base + 64;
    std::uint64_t equal = 0;
    for (int j = base; j < end; j += 8)
      equal |= std::uint64_t(_mm512_cmp_pd_mask(values.at8(j, dx, dy, dz), best, _CMP_EQ_OQ))
               << (j - base);
    if (equal != 0 || end == count)
      return equal != 0 ? base + std::countr_zero(equal) : -1;
  }
}

template <bool kLargest>
__attribute__((target("avx2,fma"), always_inline)) inline __m256d extreme4(__m256d value,
                                                                           __m256d accumulator) {
  return kLargest ? _mm256_max_pd(value, accumulator) : _mm256_min_pd(value, accumulator);
}

// first_extreme8_upto64 with four lanes: sixteen blocks, absent ones holding the start value and
// taking part (skipping them was measured only on the AVX-512 version, which this machine runs).
template <bool kLargest, class Values>
__attribute__((target("avx2,fma"), always_inline)) inline int first_extreme4_upto64(
    const Values& values, __m256d dx, __m256d dy, __m256d dz) {
  constexpr Real kStart = kLargest ? kLowest : kHighest;
  const __m256d start = _mm256_set1_pd(kStart);
  const int count = values.count();
  __m256d block[16];
#pragma GCC unroll 16
  for (int k = 0; k < 16; ++k)
    block[k] = 4 * k < count ? values.at4(4 * k, dx, dy, dz) : start;
  __m256d even = extreme4<kLargest>(block[0], start);
  __m256d odd = extreme4<kLargest>(block[1], start);
#pragma GCC unroll 7
  for (int k = 2; k < 16; k += 2) {
    even = extreme4<kLargest>(block[k], even);
    odd = extreme4<kLargest>(block[k + 1], odd);
  }
  __m256d best = extreme4<kLargest>(odd, even);
  best = extreme4<kLargest>(_mm256_permute2f128_pd(best, best, 0x01), best);
  best = extreme4<kLargest>(_mm256_permute_pd(best, 0x5), best);
  std::uint64_t equal = 0;
#pragma GCC unroll 16
  for (int k = 0; k < 16; ++k)
    equal |= std::uint64_t(_mm256_movemask_pd(_mm256_cmp_pd(block[k], best, _CMP_EQ_OQ)))
             << (4 * k);
  return _mm256_cvtsd_f64(best) != kStart ? std::countr_zero(equal) : -1;
}

template <bool kLargest, class Values>
__attribute__((target("avx2,fma"), always_inline)) inline int first_extreme4(const Values& values) {
  constexpr Real kStart = kLargest ? kLowest : kHighest;
  const __m256d dx = _mm256_set1_pd(values.dx());
  const __m256d dy = _mm256_set1_pd(values.dy());
  const __m256d dz = _mm256_set1_pd(values.dz());
  const int count = values.count();  // a multiple of 8
  if (count <= 64)
    return first_extreme4_upto64<kLargest>(values, dx, dy, dz);
  __m256d best0 = _mm256_set1_pd(kStart);
  __m256d best1 = best0;
  for (int i = 0; i < count; i += 8) {
    best0 = extreme4<kLargest>(values.at4(i, dx, dy, dz), best0);
    best1 = extreme4<kLargest>(values.at4(i + 4, dx, dy, dz), best1);
  }
  __m256d best = extreme4<kLargest>(best1, best0);
  best = extreme4<kLargest>(_mm256_permute2f128_pd(best, best, 0x01), best);
  best = extreme4<kLargest>(_mm256_permute_pd(best, 0x5), best);
  if (_mm256_cvtsd_f64(best) == kStart)
    return -1;
  for (int base = 0;; base += 64) {
    const int end = count < base + 64 ? count : base + 64;
    std::uint64_t equal = 0;
    for (int j = base; j < end; j += 4)
      equal |= std::uint64_t(
                   _mm256_movemask_pd(_mm256_cmp_pd(values.at4(j, dx, dy, dz), best, _CMP_EQ_OQ)))
               << (j - base);
    if (equal != 0 || end == count)
      return equal != 0 ? base + std::countr_zero(equal) : -1;
  }
}

// 0 when nothing is above -inf.
__attribute__((target("avx512f,fma"), always_inline)) inline int scan8(const HullScanArrays& h,
                                                                       const Vec3& d) {
  return std::max(first_extreme8<true>(DotValues{h, d}), 0);
}

__attribute__((target("avx2,fma"), always_inline)) inline int scan4(const HullScanArrays& h,
                                                                    const Vec3& d) {
  return std::max(first_extreme4<true>(DotValues{h, d}), 0);
}

// -1 when nothing is below +inf (every slot free, or NaN).
__attribute__((target("avx512f,fma"), always_inline)) inline int smallest8(const Real* values,
                                                                           int padded_count) {
  return first_extreme8<false>(ArrayValues{values, padded_count});
}

__attribute__((target("avx2,fma"), always_inline)) inline int smallest4(const Real* values,
                                                                        int padded_count) {
  return first_extreme4<false>(ArrayValues{values, padded_count});
}

// One scan, and two in one body: GJK and EPA need the support points of A and B together,
// and the two independent chains interleave.
__attribute__((target("avx512f,fma"))) int scan(const HullScanArrays& h, const Vec3& d) {
  return scan8(h, d);
}
__attribute__((target("avx512f,fma"))) SupportPair scan_pair(const HullScanArrays& a,
                                                             const Vec3& da,
                                                             const HullScanArrays& b,
                                                             const Vec3& db) {
  return {scan8(a, da), scan8(b, db)};
}
__attribute__((target("avx2,fma"))) int scan(const HullScanArrays& h, const Vec3& d) {
  return scan4(h, d);
}
__attribute__((target("avx2,fma"))) SupportPair scan_pair(const HullScanArrays& a, const Vec3& da,
                                                          const HullScanArrays& b, const Vec3& db) {
  return {scan4(a, da), scan4(b, db)};
}

__attribute__((target("avx512f,fma"))) int smallest(const Real* values, int padded_count) {
  return smallest8(values, padded_count);
}
__attribute__((target("avx2,fma"))) int smallest(const Real* values, int padded_count) {
  return smallest4(values, padded_count);
}

// The baseline (SSE2): the portable loop.
__attribute__((target("default"))) int scan(const HullScanArrays& h, const Vec3& d) {
  return scan_support_portable(h, d);
}
__attribute__((target("default"))) int smallest(const Real* values, int padded_count) {
  return first_smallest_portable(values, padded_count);
}

// Element-wise arithmetic only, in a fixed order: the same bits from every version.
__attribute__((target_clones("avx512f", "avx2", "default"))) void place(
    const Real* __restrict x, const Real* __restrict y, const Real* __restrict z, int count,
    const Real* __restrict r, const Real* __restrict t, Real* __restrict out) {
  Real* __restrict ox = out;
  Real* __restrict oy = out + count;
  Real* __restrict oz = out + 2 * count;
  for (int i = 0; i < count; ++i) {
    ox[i] = ((r[0] * x[i] + r[3] * y[i]) + r[6] * z[i]) + t[0];
    oy[i] = ((r[1] * x[i] + r[4] * y[i]) + r[7] * z[i]) + t[1];
    oz[i] = ((r[2] * x[i] + r[5] * y[i]) + r[8] * z[i]) + t[2];
  }
}

__attribute__((target("default"))) SupportPair scan_pair(const HullScanArrays& a, const Vec3& da,
                                                         const HullScanArrays& b, const Vec3& db) {
  return {scan_support_portable(a, da), scan_support_portable(b, db)};
}

}  // namespace

// Outside the anonymous namespace and before the pragma pop: the per-version entry points for
// tests.
namespace detail {

__attribute__((target("avx512f,fma"))) int scan_support_avx512(const HullScanArrays& h,
                                                               const Vec3& d) {
  return scan8(h, d);
}
__attribute__((target("avx2,fma"))) int scan_support_avx2(const HullScanArrays& h, const Vec3& d) {
  return scan4(h, d);
}
__attribute__((target("avx512f,fma"))) int first_smallest_avx512(const Real* values, int count) {
  return smallest8(values, count);
}
__attribute__((target("avx2,fma"))) int first_smallest_avx2(const Real* values, int count) {
  return smallest4(values, count);
}

}  // namespace detail

#pragma GCC diagnostic pop

int scan_support_portable(const HullScanArrays& h, const Vec3& d) {
  Real best = kLowest;
  int best_index = 0;
  for (int i = 0; i < h.padded_count; ++i) {
    const Real value = std::fma(h.z[i], d.z(), std::fma(h.y[i], d.y(), h.x[i] * d.x()));
    if (value > best) {
      best = value;
      best_index = i;
    }
  }
  return best_index;
}

// GCC function multi-versioning: the three `scan`s above become one function whose version the
// dynamic loader picks from the CPU (an ifunc), before any static initialiser runs.
int scan_support(const HullScanArrays& hull, const Vec3& d) {
  return scan(hull, d);
}

SupportPair scan_support_pair(const HullScanArrays& a, const Vec3& da, const HullScanArrays& b,
                              const Vec3& db) {
  return scan_pair(a, da, b, db);
}

int first_smallest_portable(const Real* values, int padded_count) {
  Real best = kHighest;
  int best_index = -1;
  for (int i = 0; i < padded_count; ++i) {
    if (values[i] < best) {
      best = values[i];
      best_index = i;
    }
  }
  return best_index;
}

int first_smallest(const Real* values, int padded_count) {
  return smallest(values, padded_count);
}

HullScanArrays place_hull(const HullScanArrays& hull, const Mat3& r, const Vec3& t, Real* out) {
  // Mat3 is column-major: r.data()[3 * column + row].
  place(hull.x, hull.y, hull.z, hull.padded_count, r.data(), t.data(), out);
  const int m = hull.padded_count;
  return {out, out + m, out + 2 * m, m};
}

}  // namespace tumble
