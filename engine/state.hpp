// A State is everything a step changes: time, poses, velocities and the warm-start cache. It
// is flat and copyable, so reset, copy, replay and batches of worlds are plain assignments.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/narrow_phase/box_axis_cache.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/hull_axis_cache.hpp"
#include "collision/narrow_phase/manifold_recycling.hpp"
#include "dynamics/contact_cache.hpp"
#include "dynamics/rigid_body.hpp"
#include "tumble/scene.hpp"

namespace tumble {

// GJK's warm start of one pair (collision/narrow_phase/narrow_phase.hpp, collide() with a
// GjkCache).
struct PairGjkCache {
  std::int32_t body_a = 0;  // body_a < body_b
  std::int32_t body_b = 0;
  GjkCache cache;
};

// A touching pair of resting bodies (State::resting_touches).
struct RestingTouch {
  std::int32_t body_a = 0;  // body_a < body_b
  std::int32_t body_b = 0;
};

struct State {
  Real time = 0;                         // s
  std::int64_t step = 0;                 // steps taken
  std::vector<BodyState> bodies;         // one per Scene::bodies entry, same order
  std::vector<CachedManifold> contacts;  // sorted by (body_a, body_b)
  // The touching pairs' manifolds in their bodies' frames, for contact recycling (sorted by
  // pair; collision/narrow_phase/manifold_recycling.hpp).
  std::vector<RecyclableManifold> manifolds;
  // The box pairs that were apart last step with the axis that separated them, sorted by pair
  // (collision/narrow_phase/box_axis_cache.hpp).
  std::vector<CachedBoxAxis> box_axes;
  // The pairs collide() answers by GJK that were apart last step, with GJK's last separating
  // axis and support vertices, sorted by pair: this step's query starts from them.
  std::vector<PairGjkCache> gjk_caches;
  // The hull pairs that were apart last step with a direction that separated them, sorted by
  // pair (collision/narrow_phase/hull_axis_cache.hpp).
  std::vector<CachedHullAxis> hull_axes;
  // Sleeping (WorldSettings::sleeping): how long each body has been slower than the sleep
  // speed [s], and whether it is awake (0), asleep (1), or asleep with its contacts found where it
  // now rests (2: it has been through a narrow phase asleep, and cannot have moved since). One
  // per body; all zero when sleeping is off.
  std::vector<Real> slow_time;
  std::vector<std::uint8_t> asleep;
  // The pairs of sleeping (or static) bodies that touched when the narrow phase last looked at
  // them, sorted by pair. While both bodies of a pair rest (asleep at 2, or static) and nothing
  // awake touches their island, the narrow phase takes the pair's contact from here instead of
  // colliding it again (docs/architecture.md, "Sleeping").
  std::vector<RestingTouch> resting_touches;
  // The warm-start impulses of the pairs of sleeping (or fixed) bodies, which the solver leaves
  // out, sorted by pair: an island that wakes starts from the impulses it fell asleep with.
  std::vector<CachedManifold> sleeping_contacts;
  // Substeps per island (docs/architecture.md): each body's island ran the scene's substeps
  // times 2^substep_level last step, and keeps that level for substep_hold more steps before it
  // may step down. One each per body.
  std::vector<std::uint8_t> substep_level;
  std::vector<std::uint8_t> substep_hold;
};

// The state a scene starts in: bodies where the scene puts them, an empty contact cache.
State initial_state(const Scene& scene);
// The same, written into `state` (its arrays keep their storage: a world's reset allocates
// nothing here).
void initial_state_into(const Scene& scene, State& state);

// A stable 64-bit hash of the state (FNV-1a over the bit patterns of every field, in a fixed
// order and byte order), equal across runs, thread counts and machines with IEEE doubles.
std::uint64_t state_hash(const State& state);

}  // namespace tumble
