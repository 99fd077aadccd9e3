// The scratch arrays of one step: what the narrow phase and the contact solver build and use up
// within a step, and nothing a later step reads. A lone world owns one; a batch of worlds lends
// one per thread to the worlds it steps, so that a world keeps only its own state between steps
// (docs/rl.md, "Memory": a world of 20 boxes held about 100 KB of such arrays, which a batch of a
// thousand worlds streamed from memory at every step).
//
// Every array is written before it is read within a step, so which workspace a step borrows, and
// what another world left in it, never changes a bit of the result; each keeps its capacity, so
// that once capacities settle a step allocates nothing.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/cache_prefetch.hpp"
#include "collision/narrow_phase/box_axis_cache.hpp"
#include "collision/narrow_phase/box_batch.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/hull_axis_cache.hpp"
#include "collision/narrow_phase/manifold_recycling.hpp"
#include "collision/narrow_phase/sphere_batch.hpp"
#include "dynamics/contact_solver.hpp"
#include "dynamics/integrator.hpp"
#include "engine/islands.hpp"
#include "engine/state.hpp"

namespace tumble {

struct StepWorkspace {
  // The box-box candidate pairs to collide in the batch, in order, their candidate indices and
  // their manifolds.
  std::vector<BoxPairQuery> box_queries;
  std::vector<std::int32_t> box_candidates;
  std::vector<Manifold> box_manifolds;
  // The sphere-sphere candidate pairs to collide: two spheres per pair as arrays, the pairs, and
  // their candidate indices; the batch's answers (7 arrays of one value per pair).
  std::vector<Real> sphere_x, sphere_y, sphere_z, sphere_radius;
  std::vector<SpherePair> sphere_pairs;
  std::vector<std::int32_t> sphere_candidates;
  std::vector<Real> sphere_out;
  std::vector<std::int32_t> other_candidates;        // the candidates collide() answers one by one
  std::vector<Manifold> candidate_manifolds;         // per candidate pair
  std::vector<std::int32_t> candidate_kept;          // per candidate: its recycled entry, or -1
  std::vector<std::uint8_t> candidate_route;         // per candidate: how it is answered
  std::vector<std::uint8_t> candidate_axis;          // per candidate: the axis that separated it
  std::vector<std::uint8_t> box_axes_found;          // per box query: the axis that separated it
  std::vector<std::uint8_t> candidate_uses_gjk;      // per candidate: collide() answers it by GJK
  std::vector<GjkCache> candidate_gjk;               // and its warm start, updated by the query
  std::vector<std::uint8_t> candidate_is_hull_pair;  // per candidate: two hulls
  std::vector<HullAxis> candidate_hull_axis;         // and the direction that keeps them apart
  std::vector<std::uint8_t> hull_hits;  // per other candidate: skipped by its cached direction
  // The caches the step builds for the next one; swapped into the State at the end of the
  // narrow phase (the State's old arrays come back here, to be cleared and refilled).
  std::vector<RecyclableManifold> next_manifolds;
  std::vector<CachedBoxAxis> next_box_axes;
  std::vector<PairGjkCache> next_gjk_caches;
  std::vector<CachedHullAxis> next_hull_axes;
  std::vector<RestingTouch> next_resting_touches;
  ContactSolver solver;
  // The stepper's own tables of the step (engine/simulation.cpp): each body's pose at the start
  // of the step, the gyroscopic carry from the velocity to the position update, and the islands
  // and substep levels choose_substeps works out: written and used up within the step, like the
  // rest of the workspace, so a world no longer holds them.
  std::vector<Transform> shape_poses;
  std::vector<GyroscopicCarry> carries;
  Islands islands;
  std::vector<std::int32_t> root_of;           // per body: its island's root
  std::vector<std::int32_t> substeps_of_root;  // per island root: its substeps
  std::vector<std::int32_t> group_of_root;     // per island root: its substep group, or -1
  std::vector<std::int32_t> group_fill;
  std::vector<std::int32_t> contacts_wanting;  // per island root and substep level
  std::vector<std::uint8_t> level_needed, level_before, hold_before;  // per island root
  std::vector<std::uint8_t> weighed_level;                            // per island root
  std::vector<Real> island_mass;                                      // per island root
  // The lines of the world a batch steps next, recorded before this step and asked for during it
  // (Simulation::prefetch_step_arrays); empty for a lone world. Holds no heap memory.
  CachePrefetch next_world;

  // Heap bytes held (capacities), for the benchmark's memory figures.
  std::size_t bytes_reserved() const;
};

}  // namespace tumble
