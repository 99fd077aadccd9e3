// SIMD support scan (see hull_support_scan.hpp).
#include "collision/hull_support_scan.hpp"

// GCC 12's AVX-512 headers start some intrinsics from _mm512_undefined_pd(), which
// -Wuninitialized reports as a use of an uninitialised value (GCC bug 105593, fixed in 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>

#include <limits>

namespace tumble {
namespace {

constexpr Real kLowest = -std::numeric_limits<Real>::infinity();
constexpr Real kHighest = std::numeric_limits<Real>::infinity();

// Each version keeps, per lane, the largest value seen and the index where it was first seen
// (a strict "greater" keeps the earlier index on ties), in two accumulators (even and odd
// blocks) to halve the chain of compares; the accumulators and then the lanes are merged
// pairwise by largest value and, among equal values, smallest index, which leaves the first
// index of the largest value overall. The merge is branch-free too (its comparisons would
// mispredict as the scan's would), and merging (value, index) pairs in one pass is shorter
// than a max-reduction followed by an index search. The indices are kept as doubles, exact up
// to 2^53. No lane ever holds a NaN (a NaN is never "greater").

// The better of two (value, index) lanes: the larger value, or the smaller index on a tie.
__attribute__((target("avx512f"), always_inline)) inline void keep_better8(__m512d& value,
                                                                           __m512d& index,
                                                                           __m512d other_value,
                                                                           __m512d other_index) {
  const __mmask8 take = _mm512_cmp_pd_mask(other_value, value, _CMP_GT_OQ) |
                        (_mm512_cmp_pd_mask(other_value, value, _CMP_EQ_OQ) &
                         _mm512_cmp_pd_mask(other_index, index, _CMP_LT_OQ));
  value = _mm512_mask_blend_pd(take, value, other_value);
  index = _mm512_mask_blend_pd(take, index, other_index);
}

// The values of eight (four) consecutive entries: v . d of vertices, or the negated entries of
// an array (so that the first smallest entry is the first largest value).
struct DotValues {
  const HullScanArrays& h;
  const Vec3& d;
  __attribute__((target("avx512f"), always_inline)) __m512d at8(int i, __m512d dx, __m512d dy,
                                                                __m512d dz) const {
    const __m512d xy = _mm512_add_pd(_mm512_mul_pd(_mm512_loadu_pd(h.x + i), dx),
                                     _mm512_mul_pd(_mm512_loadu_pd(h.y + i), dy));
    return _mm512_add_pd(xy, _mm512_mul_pd(_mm512_loadu_pd(h.z + i), dz));
  }
  __attribute__((target("avx2"), always_inline)) __m256d at4(int i, __m256d dx, __m256d dy,
                                                             __m256d dz) const {
    const __m256d xy = _mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(h.x + i), dx),
                                     _mm256_mul_pd(_mm256_loadu_pd(h.y + i), dy));
    return _mm256_add_pd(xy, _mm256_mul_pd(_mm256_loadu_pd(h.z + i), dz));
  }
  Vec3 direction() const { return d; }
  int count() const { return h.padded_count; }
};

struct NegatedValues {
  const Real* values;
  int padded_count;
  __attribute__((target("avx512f"), always_inline)) __m512d at8(int i, __m512d, __m512d,
                                                                __m512d) const {
    return _mm512_sub_pd(_mm512_setzero_pd(), _mm512_loadu_pd(values + i));
  }
  __attribute__((target("avx2"), always_inline)) __m256d at4(int i, __m256d, __m256d,
                                                             __m256d) const {
    return _mm256_sub_pd(_mm256_setzero_pd(), _mm256_loadu_pd(values + i));
  }
  Vec3 direction() const { return Vec3::Zero(); }
  int count() const { return padded_count; }
};

// One block of eight values into one accumulator.
__attribute__((target("avx512f"), always_inline)) inline void keep_higher8(__m512d value,
                                                                           __m512d index,
                                                                           __m512d& best,
                                                                           __m512d& best_index) {
  const __mmask8 higher = _mm512_cmp_pd_mask(value, best, _CMP_GT_OQ);
  best = _mm512_mask_blend_pd(higher, best, value);
  best_index = _mm512_mask_blend_pd(higher, best_index, index);
}

// The first index of the largest value, and that value in `largest`.
template <class Values>
__attribute__((target("avx512f"), always_inline)) inline int first_largest8(const Values& values,
                                                                            Real& largest) {
  const Vec3 d = values.direction();
  const __m512d dx = _mm512_set1_pd(d.x());
  const __m512d dy = _mm512_set1_pd(d.y());
  const __m512d dz = _mm512_set1_pd(d.z());
  const int count = values.count();
  __m512d best0 = _mm512_set1_pd(kLowest);
  __m512d best1 = best0;
  __m512d best_index0 = _mm512_setzero_pd();
  __m512d best_index1 = best_index0;
  __m512d index = _mm512_set_pd(7, 6, 5, 4, 3, 2, 1, 0);
  const __m512d step = _mm512_set1_pd(8);
  int i = 0;
  for (; i + 16 <= count; i += 16) {
    keep_higher8(values.at8(i, dx, dy, dz), index, best0, best_index0);
    index = _mm512_add_pd(index, step);
    keep_higher8(values.at8(i + 8, dx, dy, dz), index, best1, best_index1);
    index = _mm512_add_pd(index, step);
  }
  if (i < count)
    keep_higher8(values.at8(i, dx, dy, dz), index, best0, best_index0);
  __m512d value = best0;
  __m512d at = best_index0;
  keep_better8(value, at, best1, best_index1);
  keep_better8(value, at, _mm512_shuffle_f64x2(value, value, 0x4E),
               _mm512_shuffle_f64x2(at, at, 0x4E));
  keep_better8(value, at, _mm512_shuffle_f64x2(value, value, 0xB1),
               _mm512_shuffle_f64x2(at, at, 0xB1));
  keep_better8(value, at, _mm512_permute_pd(value, 0x55), _mm512_permute_pd(at, 0x55));
  largest = _mm512_cvtsd_f64(value);
  return int(_mm512_cvtsd_f64(at));
}

__attribute__((target("avx2"), always_inline)) inline void keep_better4(__m256d& value,
                                                                        __m256d& index,
                                                                        __m256d other_value,
                                                                        __m256d other_index) {
  const __m256d take = _mm256_or_pd(_mm256_cmp_pd(other_value, value, _CMP_GT_OQ),
                                    _mm256_and_pd(_mm256_cmp_pd(other_value, value, _CMP_EQ_OQ),
                                                  _mm256_cmp_pd(other_index, index, _CMP_LT_OQ)));
  value = _mm256_blendv_pd(value, other_value, take);
  index = _mm256_blendv_pd(index, other_index, take);
}

template <class Values>
__attribute__((target("avx2"), always_inline)) inline int first_largest4(const Values& values,
                                                                         Real& largest) {
  const Vec3 d = values.direction();
  const __m256d dx = _mm256_set1_pd(d.x());
  const __m256d dy = _mm256_set1_pd(d.y());
  const __m256d dz = _mm256_set1_pd(d.z());
  // Two accumulators of four lanes: the second holds indices 4 to 7 modulo 8.
  __m256d best[2] = {_mm256_set1_pd(kLowest), _mm256_set1_pd(kLowest)};
  __m256d best_index[2] = {_mm256_setzero_pd(), _mm256_setzero_pd()};
  __m256d index[2] = {_mm256_set_pd(3, 2, 1, 0), _mm256_set_pd(7, 6, 5, 4)};
  const __m256d step = _mm256_set1_pd(8);
  for (int i = 0; i < values.count(); i += 8) {
    for (int half = 0; half < 2; ++half) {
      const __m256d value = values.at4(i + 4 * half, dx, dy, dz);
      const __m256d higher = _mm256_cmp_pd(value, best[half], _CMP_GT_OQ);
      best[half] = _mm256_blendv_pd(best[half], value, higher);
      best_index[half] = _mm256_blendv_pd(best_index[half], index[half], higher);
      index[half] = _mm256_add_pd(index[half], step);
    }
  }
  __m256d value = best[0];
  __m256d at = best_index[0];
  keep_better4(value, at, best[1], best_index[1]);
  keep_better4(value, at, _mm256_permute2f128_pd(value, value, 0x01),
               _mm256_permute2f128_pd(at, at, 0x01));
  keep_better4(value, at, _mm256_permute_pd(value, 0x5), _mm256_permute_pd(at, 0x5));
  largest = _mm256_cvtsd_f64(value);
  return int(_mm256_cvtsd_f64(at));
}

__attribute__((target("avx512f"), always_inline)) inline int scan8(const HullScanArrays& h,
                                                                   const Vec3& d) {
  Real largest;
  return first_largest8(DotValues{h, d}, largest);
}

__attribute__((target("avx2"), always_inline)) inline int scan4(const HullScanArrays& h,
                                                                const Vec3& d) {
  Real largest;
  return first_largest4(DotValues{h, d}, largest);
}

// The first smallest entry is the first largest negated one; +inf (a free slot) becomes -inf,
// which is never "greater", and -0 and +0 both become +0 and tie, as they compare equal.
__attribute__((target("avx512f"), always_inline)) inline int smallest8(const Real* values,
                                                                       int padded_count) {
  Real largest;
  const int at = first_largest8(NegatedValues{values, padded_count}, largest);
  return largest > kLowest ? at : -1;
}

__attribute__((target("avx2"), always_inline)) inline int smallest4(const Real* values,
                                                                    int padded_count) {
  Real largest;
  const int at = first_largest4(NegatedValues{values, padded_count}, largest);
  return largest > kLowest ? at : -1;
}

// One scan, and two in one body: GJK and EPA need the support points of A and B together,
// and the two independent chains interleave.
__attribute__((target("avx512f"))) int scan(const HullScanArrays& h, const Vec3& d) {
  return scan8(h, d);
}
__attribute__((target("avx512f"))) SupportPair scan_pair(const HullScanArrays& a, const Vec3& da,
                                                         const HullScanArrays& b, const Vec3& db) {
  return {scan8(a, da), scan8(b, db)};
}
__attribute__((target("avx2"))) int scan(const HullScanArrays& h, const Vec3& d) {
  return scan4(h, d);
}
__attribute__((target("avx2"))) SupportPair scan_pair(const HullScanArrays& a, const Vec3& da,
                                                      const HullScanArrays& b, const Vec3& db) {
  return {scan4(a, da), scan4(b, db)};
}

__attribute__((target("avx512f"))) int smallest(const Real* values, int padded_count) {
  return smallest8(values, padded_count);
}
__attribute__((target("avx2"))) int smallest(const Real* values, int padded_count) {
  return smallest4(values, padded_count);
}

}  // namespace

// Outside the anonymous namespace and before the pragma pop: the per-version entry points for
// tests.
namespace detail {

__attribute__((target("avx512f"))) int scan_support_avx512(const HullScanArrays& h, const Vec3& d) {
  return scan8(h, d);
}
__attribute__((target("avx2"))) int scan_support_avx2(const HullScanArrays& h, const Vec3& d) {
  return scan4(h, d);
}
__attribute__((target("avx512f"))) int first_smallest_avx512(const Real* values, int count) {
  return smallest8(values, count);
}
__attribute__((target("avx2"))) int first_smallest_avx2(const Real* values, int count) {
  return smallest4(values, count);
}

}  // namespace detail

namespace {

#pragma GCC diagnostic pop

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

int scan_support_portable(const HullScanArrays& h, const Vec3& d) {
  Real best = kLowest;
  int best_index = 0;
  for (int i = 0; i < h.padded_count; ++i) {
    const Real value = (h.x[i] * d.x() + h.y[i] * d.y()) + h.z[i] * d.z();
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
