// tumble::BatchWorld (include/tumble/batch_world.hpp): one World per environment, each stepped on
// one thread; the worlds are spread over the batch's threads (dynamics/parallel_runner.hpp, a
// range of worlds per chunk, stepped in order: step_range). A world touches only its own rows of
// the shared arrays, so the results do not depend on which thread runs which world.
#include "tumble/batch_world.hpp"

#include <algorithm>
#include <limits>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "collision/cache_prefetch.hpp"
#include "dynamics/parallel_runner.hpp"
#include "engine/checked_draw.hpp"
#include "engine/draw_storage.hpp"
#include "engine/kinematic_target_check.hpp"
#include "engine/model.hpp"
#include "engine/number_text.hpp"
#include "engine/random_stream.hpp"
#include "engine/simulation.hpp"
#include "tumble/error.hpp"
#include "tumble/randomization.hpp"

namespace tumble {
namespace {

constexpr int kMostWorlds = 1000000;
constexpr Real kMostLoad = 1e15;  // N, N m

int thread_count(int threads) {
  if (threads > 0)
    return threads;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

std::string where(int world, int body, const Scene& scene) {
  const std::string& name = scene.bodies[std::size_t(body)].name;
  return "world " + std::to_string(world) + ", body " + std::to_string(body) +
         (name.empty() ? std::string() : " '" + name + "'");
}

}  // namespace

struct BatchWorld::Impl {
  std::shared_ptr<const Model> model;
  std::vector<World> worlds;
  // Domain randomization (tumble/randomization.hpp): whether the scene draws, the batch's seed,
  // and each world's current seed and number of draws so far.
  bool randomizing = false;
  std::uint64_t base_seed = 0;
  int first_world = 0;  // this batch's world 0 draws as that world of the whole batch
  std::vector<std::uint64_t> seeds, draws;
  std::vector<DrawStorage> draw_storage;  // per world, when randomizing
  int bodies = 0;
  int threads = 1;
  std::unique_ptr<ParallelRunner> runner;
  std::vector<Real> observations, forces, torques, targets, contact_forces;
  std::vector<std::uint8_t> target_set;
  // Per world, the bodies [begin, end) that check_actions found with a load or a target: the
  // step reads only those rows again (a second pass over every row of a large batch's action
  // buffers missed the cache on all of them).
  std::vector<std::int32_t> acted_begin, acted_end;
  std::vector<std::int32_t> contact_counts;
  std::vector<std::uint8_t> listed;  // reset_worlds' scratch: how often each world is listed
  // The scratch arrays the worlds' steps borrow (engine/step_workspace.hpp): one per range of
  // worlds stepping at once, so that the arrays stay in the cache of the thread that uses them, and
  // a world holds only its state. Which one a world gets does not change its results.
  std::vector<std::unique_ptr<StepWorkspace>> scratch;
  std::vector<StepWorkspace*> free_scratch;
  std::mutex scratch_mutex;
  bool ask_ahead = false;  // whether a step asks for the next world (worlds_leave_the_cache)

  StepWorkspace& take_scratch() {
    const std::lock_guard<std::mutex> lock(scratch_mutex);
    if (free_scratch.empty()) {
      scratch.push_back(std::make_unique<StepWorkspace>());
      return *scratch.back();
    }
    StepWorkspace* s = free_scratch.back();
    free_scratch.pop_back();
    return *s;
  }

  void give_scratch(StepWorkspace& s) {
    const std::lock_guard<std::mutex> lock(scratch_mutex);
    free_scratch.push_back(&s);
  }

  Real* row(std::vector<Real>& v, int world, int width) {
    return v.data() + std::size_t(world) * std::size_t(bodies) * std::size_t(width);
  }

  void observe(int w) {
    const std::vector<BodyState>& states = worlds[std::size_t(w)].simulation().state().bodies;
    Real* out = row(observations, w, kObservationWidth);
    for (const BodyState& b : states) {
      out[0] = b.position.x();
      out[1] = b.position.y();
      out[2] = b.position.z();
      out[3] = b.orientation.w();
      out[4] = b.orientation.x();
      out[5] = b.orientation.y();
      out[6] = b.orientation.z();
      out[7] = b.velocity.x();
      out[8] = b.velocity.y();
      out[9] = b.velocity.z();
      out[10] = b.angular_velocity.x();
      out[11] = b.angular_velocity.y();
      out[12] = b.angular_velocity.z();
      out += kObservationWidth;
    }
  }

  // Every action is checked before any world steps, so a bad one steps nothing.
  void check_actions() {
    const Scene& scene = model->scene();
    const Real dt = scene.world.dt;
    for (int w = 0; w < static_cast<int>(worlds.size()); ++w) {
      const Real* f = row(forces, w, 3);
      const Real* t = row(torques, w, 3);
      const Real* x = row(targets, w, kTargetWidth);
      const std::uint8_t* set = target_set.data() + std::size_t(w) * std::size_t(bodies);
      const Real* o = row(observations, w, kObservationWidth);
      std::int32_t& acted_from = acted_begin[std::size_t(w)];
      std::int32_t& acted_to = acted_end[std::size_t(w)];
      acted_from = bodies;
      acted_to = 0;
      for (int b = 0; b < bodies; ++b) {
        const Vec3 force(f[3 * b], f[3 * b + 1], f[3 * b + 2]);
        const Vec3 torque(t[3 * b], t[3 * b + 1], t[3 * b + 2]);
        if (force != Vec3::Zero() || torque != Vec3::Zero() || set[b] != 0) {
          acted_from = std::min(acted_from, b);
          acted_to = b + 1;
        }
        // NaN != 0 too, so a NaN lands here.
        if (force != Vec3::Zero() || torque != Vec3::Zero()) {
          if (model->is_fixed(std::size_t(b)))
            throw Error("BatchWorld::step: " + where(w, b, scene) +
                        " is not dynamic, but its force or torque is not zero");
          for (int c = 0; c < 3; ++c) {
            if (!(std::abs(force[c]) <= kMostLoad))
              throw Error("BatchWorld::step: " + where(w, b, scene) + ": force[" +
                          std::to_string(c) + "] = " + number_text(force[c]) +
                          " N is not finite or beyond 1e15");
            if (!(std::abs(torque[c]) <= kMostLoad))
              throw Error("BatchWorld::step: " + where(w, b, scene) + ": torque[" +
                          std::to_string(c) + "] = " + number_text(torque[c]) +
                          " N m is not finite or beyond 1e15");
          }
        }
        if (set[b] == 0)
          continue;
        if (!model->is_kinematic(std::size_t(b)))
          throw Error("BatchWorld::step: " + where(w, b, scene) +
                      " has a kinematic target but is not kinematic");
        const Real* target = x + kTargetWidth * b;
        const Real* now = o + kObservationWidth * b;
        BodyState from;
        from.position = Vec3(now[0], now[1], now[2]);
        from.orientation = Quat(now[3], now[4], now[5], now[6]);
        const std::string problem =
            kinematic_target_problem(from, Vec3(target[0], target[1], target[2]),
                                     Quat(target[3], target[4], target[5], target[6]), dt);
        if (!problem.empty())
          throw Error("BatchWorld::step: " + where(w, b, scene) + ": " + problem);
      }
    }
  }

  void step_world(int w, int n, StepWorkspace& scratch) {
    Simulation& sim = worlds[std::size_t(w)].simulation();
    const Real* f = row(forces, w, 3);
    const Real* t = row(torques, w, 3);
    const Real* x = row(targets, w, kTargetWidth);
    std::uint8_t* set = target_set.data() + std::size_t(w) * std::size_t(bodies);
    const int acted_from = acted_begin[std::size_t(w)];
    const int acted_to = acted_end[std::size_t(w)];
    for (int k = 0; k < n; ++k) {
      for (int b = acted_from; b < acted_to; ++b) {
        const Vec3 force(f[3 * b], f[3 * b + 1], f[3 * b + 2]);
        const Vec3 torque(t[3 * b], t[3 * b + 1], t[3 * b + 2]);
        if (force != Vec3::Zero())
          sim.add_force(b, force);
        if (torque != Vec3::Zero())
          sim.add_torque(b, torque);
        if (set[b] != 0) {
          const Real* target = x + kTargetWidth * b;
          sim.set_kinematic_target(b, Vec3(target[0], target[1], target[2]),
                                   Quat(target[3], target[4], target[5], target[6]));
          set[b] = 0;
        }
      }
      sim.step(scratch);
    }
    observe(w);
    sim.contact_forces(std::span(row(contact_forces, w, 3), std::size_t(bodies) * 3),
                       std::span(contact_counts.data() + std::size_t(w) * std::size_t(bodies),
                                 std::size_t(bodies)));
  }

  // The world of the scene's draw for `seed` (randomizing), or of the model itself, on one thread.
  World make_world(int w, std::uint64_t seed) {
    World world = randomizing
                      ? World(draw_storage[std::size_t(w)].draw(model->described_pointer(), seed))
                      : World(model);
    world.set_threads(1);
    return world;
  }

  // World w reset to its draw of `seed` (the drawn scene compiled, the world's buffers kept; a
  // new world where its bodies were changed since), or to the model's initial state. A draw that
  // fails its checks throws before the world, its seed or its draw count change.
  void renew(int w, std::uint64_t seed, std::uint64_t draw) {
    World& world = worlds[std::size_t(w)];
    if (randomizing) {
      std::shared_ptr<const Model> drawn =
          draw_storage[std::size_t(w)].draw(model->described_pointer(), seed);
      if (world.simulation().can_reset_to(*drawn))
        world.reset(std::move(drawn));
      else
        world = make_world(w, seed);
    } else {
      world.reset();
    }
    seeds[std::size_t(w)] = seed;
    draws[std::size_t(w)] = draw;
  }

  // Steps worlds [begin, end) in order on one thread. A large batch's worlds do not stay in the
  // cache between their steps, so before a world steps, the next one's arrays are recorded
  // (Simulation::prefetch_step_arrays) and its step asks for them a slice at a time, and the
  // object that holds the addresses of the one after that is asked for at once
  // (Simulation::prefetch_self). Only worlds of this thread's range: another thread may be
  // stepping the others, resizing their arrays. The range borrows one workspace for all its
  // worlds: borrowed per world, the pool's lock bounced between two threads' caches at every step.
  void step_range(int begin, int end, int n) {
    struct Borrowed {
      Impl& batch;
      StepWorkspace& scratch;
      // Also when a step throws; the requests of this range go with it.
      ~Borrowed() {
        scratch.next_world.clear();
        batch.give_scratch(scratch);
      }
    } borrowed{*this, take_scratch()};
    CachePrefetch& next_world = borrowed.scratch.next_world;
    for (int w = begin; w < end; ++w) {
      next_world.clear();
      if (ask_ahead && w + 2 < end)
        worlds[std::size_t(w) + 2].simulation().prefetch_self();
      if (ask_ahead && w + 1 < end)
        worlds[std::size_t(w) + 1].simulation().prefetch_step_arrays(next_world);
      step_world(w, n, borrowed.scratch);
    }
  }

  // Asking for the next world pays only where the worlds do not stay in the cache between their
  // steps; where they do, the requests are only work: boxes20 asking ahead at every size was 2%
  // to 6% slower for 16 and 64 worlds on one thread (docs/rl.md, "The requests in slices").
  // Estimated from the first world's arrays, whose capacities only grow; once a batch asks ahead
  // it goes on asking (ask_ahead), so that a world rebuilt by a reset does not switch it off.
  bool worlds_leave_the_cache() const {
    const WorldMemory m = worlds.front().simulation().memory();
    const std::size_t per_thread =
        (worlds.size() + std::size_t(threads) - 1) / std::size_t(threads);
    return (m.body_bytes + m.contact_bytes) * per_thread >
           CachePrefetch::kWorldBytesCachedPerThread;
  }

  // Calls work(begin, end) on ranges of worlds that cover the batch, on the batch's threads:
  // ranges of up to kWorldsPerRange worlds, and at least four per thread where there are enough
  // worlds (worlds of unequal cost, a resting one beside a falling one, still share out evenly).
  template <class Work>
  void for_world_ranges(const Work& work) {
    constexpr int kWorldsPerRange = 16;
    const int n = static_cast<int>(worlds.size());
    if (threads <= 1 || n == 1) {
      work(0, n);
      return;
    }
    const int grain = std::clamp(n / (4 * threads), 1, kWorldsPerRange);
    runner->run([&] {
      runner->for_chunks(n, grain, [&](std::int32_t begin, std::int32_t end) {
        work(static_cast<int>(begin), static_cast<int>(end));
      });
    });
  }
};

BatchWorld::BatchWorld(std::shared_ptr<const Scene> scene, int num_worlds, int threads,
                       std::uint64_t seed, int first_world)
    : BatchWorld(compile(std::move(scene)), num_worlds, threads, seed, first_world) {}

BatchWorld::BatchWorld(std::shared_ptr<const Model> model, int num_worlds, int threads,
                       std::uint64_t seed, int first_world)
    : impl_(std::make_unique<Impl>()) {
  if (!model)
    throw Error("BatchWorld: the model is null");
  if (num_worlds < 1 || num_worlds > kMostWorlds)
    throw Error("BatchWorld: " + std::to_string(num_worlds) + " worlds; expected 1 to 1000000");
  if (first_world < 0 || first_world > std::numeric_limits<int>::max() - num_worlds)
    throw Error("BatchWorld: first_world " + std::to_string(first_world) +
                " must be at least 0, with first_world + num_worlds within an int");
  Impl& m = *impl_;
  m.first_world = first_world;
  m.model = std::move(model);
  m.bodies = static_cast<int>(m.model->body_count());
  m.randomizing = m.model->described_scene().randomize.any();
  m.base_seed = seed;
  m.seeds.assign(std::size_t(num_worlds), 0);
  m.draws.assign(std::size_t(num_worlds), 0);
  m.worlds.reserve(std::size_t(num_worlds));
  if (m.randomizing)
    m.draw_storage.resize(std::size_t(num_worlds));
  for (int w = 0; w < num_worlds; ++w) {
    m.seeds[std::size_t(w)] = draw_seed(seed, first_world + w, 0);
    m.worlds.push_back(m.make_world(w, m.seeds[std::size_t(w)]));
  }
  const std::size_t rows = std::size_t(num_worlds) * std::size_t(m.bodies);
  m.observations.assign(rows * kObservationWidth, 0);
  m.forces.assign(rows * 3, 0);
  m.torques.assign(rows * 3, 0);
  m.targets.assign(rows * kTargetWidth, 0);
  m.target_set.assign(rows, 0);
  m.acted_begin.assign(std::size_t(num_worlds), 0);
  m.acted_end.assign(std::size_t(num_worlds), 0);
  m.contact_forces.assign(rows * 3, 0);
  m.contact_counts.assign(rows, 0);
  set_threads(threads);
  for (int w = 0; w < num_worlds; ++w)
    m.observe(w);
}

BatchWorld::~BatchWorld() = default;
BatchWorld::BatchWorld(BatchWorld&&) noexcept = default;
BatchWorld& BatchWorld::operator=(BatchWorld&&) noexcept = default;

int BatchWorld::size() const {
  return static_cast<int>(impl_->worlds.size());
}

int BatchWorld::body_count() const {
  return impl_->bodies;
}

std::size_t BatchWorld::scratch_bytes() const {
  const std::lock_guard<std::mutex> lock(impl_->scratch_mutex);
  std::size_t bytes = 0;
  for (const std::unique_ptr<StepWorkspace>& s : impl_->scratch)
    bytes += s->bytes_reserved();
  return bytes;
}

int BatchWorld::threads() const {
  return impl_->threads;
}

void BatchWorld::set_threads(int threads) {
  if (threads > 1024)
    throw Error("BatchWorld::set_threads: " + std::to_string(threads) + " threads; at most 1024");
  impl_->threads = thread_count(threads);
  impl_->runner = std::make_unique<ParallelRunner>(impl_->threads);
  impl_->free_scratch.reserve(std::size_t(impl_->threads));
}

std::span<const Real> BatchWorld::observations() const {
  return impl_->observations;
}

std::span<Real> BatchWorld::forces() {
  return impl_->forces;
}

std::span<Real> BatchWorld::torques() {
  return impl_->torques;
}

std::span<Real> BatchWorld::kinematic_targets() {
  return impl_->targets;
}

std::span<std::uint8_t> BatchWorld::kinematic_target_set() {
  return impl_->target_set;
}

void BatchWorld::step(int n) {
  if (n < 0)
    throw Error("BatchWorld::step: the step count " + std::to_string(n) + " is negative");
  if (n == 0)
    return;
  impl_->check_actions();
  impl_->ask_ahead = impl_->ask_ahead || impl_->worlds_leave_the_cache();
  impl_->for_world_ranges([&](int begin, int end) { impl_->step_range(begin, end, n); });
}

void BatchWorld::reset(std::span<const int> worlds) {
  reset_worlds(worlds, {});
}

void BatchWorld::reset(std::span<const int> worlds, std::span<const std::uint64_t> seeds) {
  if (seeds.size() != worlds.size())
    throw Error("BatchWorld::reset: " + std::to_string(seeds.size()) + " seeds for " +
                std::to_string(worlds.size()) + " worlds; give one seed per world");
  reset_worlds(worlds, seeds);
}

void BatchWorld::reset_worlds(std::span<const int> worlds, std::span<const std::uint64_t> seeds) {
  for (const int w : worlds) {
    if (w < 0 || w >= size())
      throw Error("BatchWorld::reset: world " + std::to_string(w) + " of " +
                  std::to_string(size()));
  }
  Impl& m = *impl_;
  const auto renew = [&](std::size_t i) {
    const int w = worlds[i];
    const std::uint64_t draw = m.draws[std::size_t(w)] + 1;
    m.renew(w, seeds.empty() ? draw_seed(m.base_seed, m.first_world + w, draw) : seeds[i], draw);
    m.observe(w);
    const std::size_t first = std::size_t(w) * std::size_t(m.bodies);
    std::fill_n(m.contact_forces.begin() + std::ptrdiff_t(3 * first), 3 * m.bodies, Real(0));
    std::fill_n(m.contact_counts.begin() + std::ptrdiff_t(first), m.bodies, 0);
    std::fill_n(m.target_set.begin() + std::ptrdiff_t(first), m.bodies, 0);
  };
  // A world listed twice is reset twice, in order (its second draw is the one that stays).
  // Otherwise each world's reset is its own, and they run on the batch's threads (if one throws,
  // each world is either reset with its new draw or left as it was).
  bool repeated = false;
  if (m.threads > 1 && worlds.size() > 1) {
    m.listed.resize(m.worlds.size(), 0);
    for (const int w : worlds)
      repeated = repeated || m.listed[std::size_t(w)]++ != 0;
    for (const int w : worlds)
      m.listed[std::size_t(w)] = 0;
  }
  if (repeated || m.threads <= 1 || worlds.size() < 2) {
    for (std::size_t i = 0; i < worlds.size(); ++i)
      renew(i);
    return;
  }
  m.runner->run([&] {
    m.runner->for_chunks(static_cast<std::int32_t>(worlds.size()), 1,
                         [&](std::int32_t begin, std::int32_t end) {
                           for (std::int32_t i = begin; i < end; ++i)
                             renew(std::size_t(i));
                         });
  });
}

void BatchWorld::reset() {
  std::vector<int> all(static_cast<std::size_t>(size()));
  for (int w = 0; w < size(); ++w)
    all[std::size_t(w)] = w;
  reset(all);
}

std::span<const Real> BatchWorld::contact_forces() const {
  return impl_->contact_forces;
}

std::span<const std::int32_t> BatchWorld::contact_counts() const {
  return impl_->contact_counts;
}

std::uint64_t BatchWorld::seed(int index) const {
  world(index);  // checks the index
  return impl_->seeds[std::size_t(index)];
}

std::uint64_t BatchWorld::draw_seed(std::uint64_t seed, int world, std::uint64_t draw) {
  return RandomStream(seed, std::uint64_t(world), draw).next();
}

std::uint64_t BatchWorld::state_hash(int index) const {
  return world(index).state_hash();
}

World& BatchWorld::world(int index) {
  if (index < 0 || index >= size())
    throw Error("BatchWorld::world: world " + std::to_string(index) + " of " +
                std::to_string(size()));
  return impl_->worlds[std::size_t(index)];
}

const World& BatchWorld::world(int index) const {
  return const_cast<BatchWorld*>(this)->world(index);
}

}  // namespace tumble
