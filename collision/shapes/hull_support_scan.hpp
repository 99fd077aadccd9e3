// SIMD scans for GJK and EPA on small convex hulls (up to kHullScanLimit vertices).
//
// scan_support: the support vertex by scanning every vertex, the argmax of v . d over
// structure-of-arrays coordinates, eight (AVX-512) or four (AVX2) vertices per instruction.
// GJK and EPA make about 20 support calls per query on each hull; on hulls of a few dozen
// vertices a branch-free scan beats hill climbing, whose comparisons mispredict (Bullet's
// btConvexHullShape also scans, with its SIMD "maxdot"). place_hull moves a hull's vertices into
// another frame once, so that EPA's support calls on B need no rotation; first_smallest is
// EPA's closest-face search.
//
// The version is picked once at load time from the CPU (GCC function multi-versioning): AVX-512
// with FMA, AVX2 with FMA, or the portable loop. Every version computes each value as
// fma(z, dz, fma(y, dy, x dx)) (the portable loop with std::fma, which rounds the same) and
// returns the first index of the largest value (NaN never wins; 0 when nothing is above -inf),
// so the answer is the same on every machine. The fused form takes three vector instructions
// per block instead of five, and the scans are bound by those (two ports run 512-bit
// instructions): GJK+EPA on the benchmark's 43-vertex hulls took 4% less time with it.
#pragma once

#include "collision/math.hpp"

namespace tumble {

// Vertex coordinates as three arrays of `padded_count` entries each (a multiple of
// kHullScanWidth, padded with copies of vertex 0, which never beat vertex 0 itself).
struct HullScanArrays {
  const Real* x = nullptr;
  const Real* y = nullptr;
  const Real* z = nullptr;
  int padded_count = 0;
};

inline constexpr int kHullScanWidth = 8;

// Index of the first vertex with the largest v . d (see above for NaN).
int scan_support(const HullScanArrays& hull, const Vec3& d);

// scan_support on two hulls at once (GJK's and EPA's support of A - B): the same answers.
struct SupportPair {
  int a;
  int b;
};
SupportPair scan_support_pair(const HullScanArrays& a, const Vec3& da, const HullScanArrays& b,
                              const Vec3& db);

// Writes the hull's vertices moved by x -> r x + t into out (three blocks of
// hull.padded_count, x, y, z), each coordinate as ((r_i0 x + r_i1 y) + r_i2 z) + t_i; returns
// the moved arrays. EPA places B in A's frame with it once per query.
HullScanArrays place_hull(const HullScanArrays& hull, const Mat3& r, const Vec3& t, Real* out);

// Index of the first of the smallest of values[0, padded_count) (padded_count a multiple of
// kHullScanWidth), or -1 when none is below +inf (NaN never counts): EPA's closest face, over
// a packed array of face keys with +inf for free slots.
int first_smallest(const Real* values, int padded_count);
int first_smallest_portable(const Real* values, int padded_count);

// The portable version, for tests: the same answer as scan_support on any machine.
int scan_support_portable(const HullScanArrays& hull, const Vec3& d);

namespace detail {
// Each instruction-set version on its own, for tests on machines that have it (calling one on
// a CPU without its instructions is an illegal instruction).
int scan_support_avx512(const HullScanArrays& hull, const Vec3& d);
int scan_support_avx2(const HullScanArrays& hull, const Vec3& d);
int first_smallest_avx512(const Real* values, int padded_count);
int first_smallest_avx2(const Real* values, int padded_count);
}  // namespace detail

}  // namespace tumble
