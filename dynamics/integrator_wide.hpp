// The integrator's vector kernels (internal): one table per instruction set, the widest the CPU
// runs picked at load time. All give the same bits (integrator_lanes.inc), and the one-body
// functions of dynamics/integrator.hpp run the same kernels.
#pragma once

#include <cstdint>

#include "dynamics/integrator.hpp"

namespace tumble::detail {

struct IntegratorKernels {
  int lanes;
  // Integrate bodies body[0..count), each once.
  void (*integrate_velocities)(const VelocityIntegration& in, const std::int32_t* body, int count);
  void (*integrate_positions)(const PositionIntegration& in, const std::int32_t* body, int count);
};

// The table for this CPU: AVX-512 (8 lanes), AVX2 (4) or the SSE2 baseline (2).
const IntegratorKernels& integrator_kernels();
// Every table this CPU can run, widest first (for tests that compare them).
int available_integrator_kernels(const IntegratorKernels** out, int capacity);

}  // namespace tumble::detail
