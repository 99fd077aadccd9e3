// The contact solver's lanes (contact_solver_lanes.inc), compiled once per instruction set
// (collision/simd/lane_versions.inc), and the version this CPU runs.
#include "dynamics/contact_solver_wide.hpp"

#include <immintrin.h>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "collision/simd/lane_versions.hpp"

namespace tumble {

#define TUMBLE_LANES_FILE "dynamics/contact_solver_lanes.inc"
#include "collision/simd/lane_versions.inc"
#undef TUMBLE_LANES_FILE

namespace detail {

int available_wide_kernels(const WideKernels** out, int capacity) {
  return simd::available_versions(lanes8::kKernels, lanes4::kKernels, lanes2::kKernels, out,
                                  capacity);
}

const WideKernels& wide_kernels() {
  static const WideKernels& chosen =
      simd::widest_version(lanes8::kKernels, lanes4::kKernels, lanes2::kKernels);
  return chosen;
}

}  // namespace detail
}  // namespace tumble
