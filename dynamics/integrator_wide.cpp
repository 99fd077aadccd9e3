// The integrator's lanes (integrator_lanes.inc), compiled once per instruction set: GCC vector
// extensions as wide as the target's registers, 8 doubles for AVX-512, 4 for AVX2, 2 (SSE2) for
// the baseline. The target pragma makes every function of the file, the helpers included, code
// for that instruction set.
#include "dynamics/integrator_wide.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include <Eigen/LU>

// A vector's ABI depends on the instruction set, and GCC warns about it (-Wpsabi) even for
// functions of internal linkage; every function here that takes or returns one is inlined.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

#define TUMBLE_LANES_INLINE [[gnu::always_inline]] inline
#define TUMBLE_LAMBDA_INLINE __attribute__((always_inline))

namespace tumble {

namespace {
namespace lanes8 {
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx512f"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f")
#endif
constexpr int kLanes = 8;
#include "dynamics/integrator_lanes.inc"
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
}  // namespace lanes8
}  // namespace

namespace {
namespace lanes4 {
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
constexpr int kLanes = 4;
#include "dynamics/integrator_lanes.inc"
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
}  // namespace lanes4
}  // namespace

namespace {
namespace lanes2 {
constexpr int kLanes = 2;
#include "dynamics/integrator_lanes.inc"
}  // namespace lanes2
}  // namespace

namespace detail {

int available_integrator_kernels(const IntegratorKernels** out, int capacity) {
  __builtin_cpu_init();
  int n = 0;
  if (n < capacity && __builtin_cpu_supports("avx512f"))
    out[n++] = &lanes8::kKernels;
  if (n < capacity && __builtin_cpu_supports("avx2"))
    out[n++] = &lanes4::kKernels;
  if (n < capacity)
    out[n++] = &lanes2::kKernels;
  return n;
}

const IntegratorKernels& integrator_kernels() {
  static const IntegratorKernels* chosen = [] {
    const IntegratorKernels* best[3];
    available_integrator_kernels(best, 3);
    return best[0];
  }();
  return *chosen;
}

}  // namespace detail
}  // namespace tumble
