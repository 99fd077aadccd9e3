// Many worlds of one model stepped at once, for reinforcement learning: each world on one thread,
// the worlds spread over the threads (environment-level parallelism), with no synchronisation
// between them. Observations, actions and contact forces live in contiguous arrays the caller
// reads and writes in place (the Python module hands them to numpy without copies).
//
// World i of a batch is bit-identical to a lone World of the same model given the same actions,
// whatever the thread count. docs/api.md ("Batches of worlds") and docs/python.md describe it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "tumble/model.hpp"
#include "tumble/scene.hpp"
#include "tumble/world.hpp"

namespace tumble {

class BatchWorld {
 public:
  // Per body: position (3), orientation w x y z (4), velocity (3), angular velocity (3), world
  // frame: the column order of trajectory.csv.
  static constexpr int kObservationWidth = 13;
  // A kinematic target: position (3), orientation w x y z (4).
  static constexpr int kTargetWidth = 7;

  // `num_worlds` worlds (1 to 1,000,000) of the model on `threads` threads (<= 0: the machine's
  // cores). Throws Error for counts out of range, SceneError for a scene that fails its check.
  //
  // If the scene has a `randomize` block (tumble/randomization.hpp), every world draws its own
  // scene when it is made and at each reset: world i's k-th draw (k = 0 when made) uses the seed
  // draw_seed(seed, i, k), and is the scene randomized(scene, that seed), so a lone
  // World(randomized(scene, batch.seed(i))) is the same world bit for bit.
  //
  // `first_world` makes the batch a shard of a larger one (a rank's part of a batch spread over
  // processes): its world i draws as world first_world + i, so the shards together step the
  // same worlds as one batch of them all.
  BatchWorld(std::shared_ptr<const Model> model, int num_worlds, int threads = 0,
             std::uint64_t seed = 0, int first_world = 0);
  BatchWorld(std::shared_ptr<const Scene> scene, int num_worlds, int threads = 0,
             std::uint64_t seed = 0, int first_world = 0);
  ~BatchWorld();
  BatchWorld(BatchWorld&&) noexcept;
  BatchWorld& operator=(BatchWorld&&) noexcept;
  BatchWorld(const BatchWorld&) = delete;
  BatchWorld& operator=(const BatchWorld&) = delete;

  int size() const;
  int body_count() const;  // per world
  int threads() const;
  void set_threads(int threads);
  // Heap bytes of the scratch arrays the batch lends its worlds' steps: one set per step running
  // at once, shared by all the worlds (a world itself keeps only its state).
  std::size_t scratch_bytes() const;

  // [world][body][kObservationWidth], as of the last step or reset.
  std::span<const Real> observations() const;
  // Actions, [world][body][3] in N and N m (world frame, at the centre of mass). They stay until
  // the caller changes them (like MuJoCo's xfrc_applied), act on dynamic bodies only, and must
  // be zero on the others.
  std::span<Real> forces();
  std::span<Real> torques();
  // [world][body][kTargetWidth]: where each kinematic body should be at the end of the next
  // step, for the bodies whose flag in kinematic_target_set() ([world][body]) is 1. A flag is
  // cleared when its target has been reached.
  std::span<Real> kinematic_targets();
  std::span<std::uint8_t> kinematic_target_set();

  // Steps every world n times with the current actions. Throws Error naming the world, the body
  // and the value for an action that is not finite, a force on a body that is not dynamic, or a
  // target on one that is not kinematic; nothing is stepped then.
  void step(int n = 1);
  // Back to the initial state (with an empty contact cache), for the worlds listed or all.
  // Throws Error for an index out of range. A randomized scene draws anew: each listed world's
  // next draw, or the draw of the seed given for it (`seeds` as long as `worlds`). The worlds of
  // one call are reset on the batch's threads (so a scene's mixing rules, evaluated as each draw
  // is compiled, may be called from several threads at once); a draw that fails its checks
  // throws, leaving that world as it was.
  void reset(std::span<const int> worlds);
  void reset(std::span<const int> worlds, std::span<const std::uint64_t> seeds);
  void reset();
  // The seed of world i's current draw (see the constructor), and the rule that makes it.
  std::uint64_t seed(int world) const;
  static std::uint64_t draw_seed(std::uint64_t seed, int world, std::uint64_t draw);

  // [world][body][3], N: the contact force on each body over the last step (the impulses of its
  // contacts divided by dt), and [world][body] the number of bodies it touched. Pairs of an
  // island that sleeps (world.sleeping) are not solved, so they count neither.
  std::span<const Real> contact_forces() const;
  std::span<const std::int32_t> contact_counts() const;

  std::uint64_t state_hash(int world) const;
  // One world of the batch, for anything the arrays do not cover (Error for a bad index).
  World& world(int index);
  const World& world(int index) const;

 private:
  void reset_worlds(std::span<const int> worlds, std::span<const std::uint64_t> seeds);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tumble
