#include "engine/step_statistics.hpp"

#include <algorithm>

namespace tumble {

std::string_view stage_name(Stage stage) {
  switch (stage) {
    case Stage::integrate_velocities:
      return "integrate_velocities";
    case Stage::bounds:
      return "bounds";
    case Stage::broad_phase:
      return "broad_phase";
    case Stage::narrow_phase:
      return "narrow_phase";
    case Stage::continuous:
      return "continuous";
    case Stage::solve:
      return "solve";
    case Stage::integrate_positions:
      return "integrate_positions";
  }
  return "unknown";
}

std::string_view solve_phase_name(SolvePhase phase) {
  switch (phase) {
    case SolvePhase::prepare:
      return "prepare";
    case SolvePhase::warm_start:
      return "warm_start";
    case SolvePhase::soft_passes:
      return "soft_passes";
    case SolvePhase::relax_passes:
      return "relax_passes";
    case SolvePhase::restitution:
      return "restitution";
    case SolvePhase::store_impulses:
      return "store_impulses";
    case SolvePhase::islands_and_sleep:
      return "islands_and_sleep";
  }
  return "unknown";
}

void StepStatistics::accumulate(const StepStatistics& o) {
  for (int i = 0; i < kStageCount; ++i) {
    seconds[i] += o.seconds[i];
    ran[i] = ran[i] || o.ran[i];
  }
  for (int i = 0; i < kSolvePhaseCount; ++i)
    solve_phase_seconds[i] += o.solve_phase_seconds[i];
  candidate_pairs += o.candidate_pairs;
  touching_pairs += o.touching_pairs;
  recycled_pairs += o.recycled_pairs;
  recomputed_pairs += o.recomputed_pairs;
  resting_pairs += o.resting_pairs;
  axis_cache_tries += o.axis_cache_tries;
  axis_cache_hits += o.axis_cache_hits;
  gjk_warm_starts += o.gjk_warm_starts;
  sdf_refinements += o.sdf_refinements;
  sdf_refinements_capped += o.sdf_refinements_capped;
  recycle_seconds += o.recycle_seconds;
  recompute_seconds += o.recompute_seconds;
  contact_points += o.contact_points;
  solver_iterations += o.solver_iterations;
  point_passes += o.point_passes;
  swept_bodies += o.swept_bodies;
  stopped_bodies += o.stopped_bodies;
  impact_rounds += o.impact_rounds;
  ccd_candidate_pairs += o.ccd_candidate_pairs;
  split_loops += o.split_loops;
  lines_asked_ahead += o.lines_asked_ahead;
  max_substeps = std::max(max_substeps, o.max_substeps);
}

}  // namespace tumble
