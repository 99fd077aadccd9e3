#include "dynamics/parallel_runner.hpp"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

namespace tumble {

struct ParallelRunner::Arena {
  explicit Arena(int threads) : arena(threads) {}
  tbb::task_arena arena;
};

ParallelRunner::ParallelRunner(int threads) {
  threads_ = threads > 0 ? threads : tbb::info::default_concurrency();
  if (threads_ < 1)
    threads_ = 1;
  // More threads than cores would only take turns on them (oneTBB starts no more workers than
  // the machine has cores and warns when asked to): the arena gets at most the cores. The work
  // is split the same way whatever the count, so the results do not change.
  if (threads_ > 1)
    arena_ = std::make_unique<Arena>(std::min(threads_, tbb::info::default_concurrency()));
}

ParallelRunner::~ParallelRunner() = default;

void ParallelRunner::enter(void (*work)(void*), void* context) const {
  arena_->arena.execute([&] { work(context); });
}

// A simple partitioner splits to chunks of at most `grain` whatever the thread count; which
// thread runs a chunk may vary, what it computes does not.
void ParallelRunner::split(std::int32_t count, std::int32_t grain,
                           void (*body)(void*, std::int32_t, std::int32_t), void* context) const {
  ++split_loops_;
  const auto chunk = [&](const tbb::blocked_range<std::int32_t>& r) {
    body(context, r.begin(), r.end());
  };
  tbb::parallel_for(tbb::blocked_range<std::int32_t>(0, count, grain), chunk,
                    tbb::simple_partitioner());
}

}  // namespace tumble
