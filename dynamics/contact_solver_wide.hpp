// The contact solver's vector kernels (internal): one table per instruction set, the widest the
// CPU runs picked at load time. All give the same bits (contact_solver_lanes.inc).
#pragma once

#include <cstddef>
#include <cstdint>

#include "dynamics/contact_solver.hpp"

namespace tumble::detail {

struct WideKernels {
  int lanes;
  std::size_t bundle_bytes;
  std::size_t bundle_alignment;
  // lane_records[b * lanes + l]: the record in lane l of bundle b, or -1 for an empty lane;
  // inverse_inertia_world[body]: each body's world inverse inertia at the start of the step.
  void (*pack)(const ContactSolver::ManifoldRecord* records, const std::int32_t* lane_records,
               int bundle_count, const Mat3* inverse_inertia_world, std::byte* bundles);
  void (*unpack)(const std::byte* bundles, const std::int32_t* lane_records, int bundle_count,
                 ContactSolver::ManifoldRecord* records);
  void (*warm_start)(const std::byte* bundles, int begin, int end,
                     ContactSolver::Velocity* velocities);
  void (*solve)(std::byte* bundles, int begin, int end, ContactSolver::Velocity* velocities,
                const ContactSolver::Coefficients& coefficients, bool use_bias,
                const ContactSolver::Motion* motions);
  void (*update_separations)(std::byte* bundles, int begin, int end,
                             const ContactSolver::Motion* motions);
  int (*resolve_impacts)(std::byte* bundles, int begin, int end,
                         ContactSolver::Velocity* velocities,
                         const ContactSolver::Coefficients& coefficients, int point_count);
  void (*apply_restitution)(std::byte* bundles, int begin, int end,
                            ContactSolver::Velocity* velocities,
                            const ContactSolver::Coefficients& coefficients);
  // Slots [begin, end) of `velocities` from their bodies (body_of_slot[slot]).
  void (*load_velocities)(const BodyState* bodies, const std::int32_t* body_of_slot, int begin,
                          int end, ContactSolver::Velocity* velocities);
};

// The table for this CPU: AVX-512 (8 lanes), AVX2 (4) or the SSE2 baseline (2).
const WideKernels& wide_kernels();
// Every table this CPU can run, widest first (for tests that compare them).
int available_wide_kernels(const WideKernels** out, int capacity);

}  // namespace tumble::detail
