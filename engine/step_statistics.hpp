// What one step did and how long each phase took (like Box2D's b2Profile; docs/architecture.md,
// "One step"). Timings are wall-clock and vary from run to run; they never feed back into the
// simulation.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace tumble {

enum class Stage : std::uint8_t {
  integrate_velocities,
  bounds,
  broad_phase,
  narrow_phase,
  continuous,
  solve,
  integrate_positions,
};
inline constexpr int kStageCount = 7;

// The phases of the solve stage (Box2D's b2Profile splits its solver the same way), whose times
// add up to the stage's.
enum class SolvePhase : std::uint8_t {
  prepare,            // constraints built, coloured, packed (penalty: springs set up)
  warm_start,         // last step's impulses applied, and the pairwise impacts
  soft_passes,        // the passes with the push-out spring (penalty: to convergence)
  relax_passes,       // separations updated, rigid passes
  restitution,        // bounces applied
  store_impulses,     // impulses written to the cache
  islands_and_sleep,  // islands, substeps per island, waking, falling asleep
};
inline constexpr int kSolvePhaseCount = 7;

std::string_view stage_name(Stage stage);
std::string_view solve_phase_name(SolvePhase phase);

struct StepStatistics {
  std::array<double, kStageCount> seconds{};                   // wall time per stage [s]
  std::array<bool, kStageCount> ran{};                         // whether the stage ran at all
  std::array<double, kSolvePhaseCount> solve_phase_seconds{};  // the solve stage, split [s]
  std::int64_t candidate_pairs = 0;                            // broad-phase output
  std::int64_t touching_pairs = 0;                             // pairs with a manifold
  std::int64_t recycled_pairs = 0;    // candidate pairs that reused their kept manifold
  std::int64_t recomputed_pairs = 0;  // candidate pairs collided afresh
  // Candidate pairs of two resting bodies, taken from the last narrow phase
  // (State::resting_touches).
  std::int64_t resting_pairs = 0;
  // Box and hull pairs whose cached separating axis was tried, and of those, the ones it still
  // kept apart (no query run; collision/narrow_phase/box_axis_cache.hpp,
  // collision/narrow_phase/hull_axis_cache.hpp).
  std::int64_t axis_cache_tries = 0;
  std::int64_t axis_cache_hits = 0;
  // Pairs answered by GJK that started from last step's separating axis.
  std::int64_t gjk_warm_starts = 0;
  // Field contacts' surface walks (collision/narrow_phase/pairs/sdf_pairs.cpp) in the pairs
  // collided afresh that touch, and of those the walks that stopped at their step cap.
  std::int64_t sdf_refinements = 0;
  std::int64_t sdf_refinements_capped = 0;
  // Of the narrow phase's time: sorting the candidates while recycling the kept manifolds, and
  // the queries of the pairs collided afresh [s].
  double recycle_seconds = 0;
  double recompute_seconds = 0;
  std::int64_t contact_points = 0;
  std::int64_t solver_iterations = 0;
  std::int64_t point_passes = 0;         // contact points times the soft and relax passes over them
  std::int64_t swept_bodies = 0;         // bodies swept by continuous collision detection
  std::int64_t stopped_bodies = 0;       // of those, stopped at a time of impact
  std::int64_t impact_rounds = 0;        // rounds that swept bodies on after impacts
  std::int64_t ccd_candidate_pairs = 0;  // pairs with a swept body whose motion boxes overlap
  std::int64_t split_loops = 0;          // loops of the step split over several threads
  std::int64_t lines_asked_ahead = 0;    // cache lines of a batch's next world asked for
  int max_substeps = 0;                  // the most substeps any island took (the largest seen)

  void accumulate(const StepStatistics& other);
};

}  // namespace tumble
