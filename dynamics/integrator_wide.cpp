// The integrator's lanes (integrator_lanes.inc), compiled once per instruction set
// (collision/simd/lane_versions.inc), and the version this CPU runs.
#include "dynamics/integrator_wide.hpp"

#include <immintrin.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include <Eigen/LU>

#include "collision/simd/lane_versions.hpp"

namespace tumble {

#define TUMBLE_LANES_FILE "dynamics/integrator_lanes.inc"
#include "collision/simd/lane_versions.inc"
#undef TUMBLE_LANES_FILE

namespace detail {

int available_integrator_kernels(const IntegratorKernels** out, int capacity) {
  return simd::available_versions(lanes8::kKernels, lanes4::kKernels, lanes2::kKernels, out,
                                  capacity);
}

const IntegratorKernels& integrator_kernels() {
  static const IntegratorKernels& chosen =
      simd::widest_version(lanes8::kKernels, lanes4::kKernels, lanes2::kKernels);
  return chosen;
}

}  // namespace detail
}  // namespace tumble
