// ParallelRunner on plain std::threads, for the ThreadSanitizer build (TUMBLE_TSAN) only: Debian's
// oneTBB library is not instrumented, so ThreadSanitizer cannot see the hand-over of a task from
// one thread to another inside it and reports the loops' every read as a race. Here every
// hand-over is a mutex, a condition variable or an atomic it sees, so what it reports is a race in
// tumble's own loops. The chunks are the ones oneTBB's simple partitioner makes (a range halved,
// [begin, middle) and [middle, end), until no piece is longer than `grain`), taken by the threads
// in any order. One difference: a loop split from inside a chunk runs there in one piece.
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "dynamics/parallel_runner.hpp"

namespace tumble {

namespace {

// Set while a thread runs a chunk: a loop split from inside a chunk runs there in one piece
// (the pool's workers are busy with the outer loop).
thread_local bool in_chunk = false;

}  // namespace

struct ParallelRunner::Arena {
  explicit Arena(int workers) {
    try {
      for (int i = 0; i < workers; ++i)
        threads.emplace_back([this] { serve(); });
    } catch (...) {
      stop_workers();  // those started already
      throw;
    }
  }
  ~Arena() { stop_workers(); }

  void stop_workers() {
    {
      const std::lock_guard lock(mutex);
      stop = true;
    }
    wake.notify_all();
    for (std::thread& t : threads)
      t.join();
    threads.clear();
  }

  // The simple partitioner's pieces of [begin, end), in order.
  void add_chunks(std::int32_t begin, std::int32_t end, std::int32_t grain) {
    if (end - begin > grain) {
      const std::int32_t middle = begin + (end - begin) / 2;
      add_chunks(begin, middle, grain);
      add_chunks(middle, end, grain);
    } else {
      chunks.emplace_back(begin, end);
    }
  }

  // A chunk that throws stops the loop's other chunks from starting; the first exception is
  // thrown again on the calling thread, as oneTBB does.
  void run_chunks() {
    in_chunk = true;
    const auto count = static_cast<std::int32_t>(chunks.size());
    for (;;) {
      const std::int32_t k = next.fetch_add(1);
      if (k >= count)
        break;
      try {
        body(context, chunks[std::size_t(k)].first, chunks[std::size_t(k)].second);
      } catch (...) {
        next.store(count);
        const std::lock_guard lock(mutex);
        if (!error)
          error = std::current_exception();
      }
    }
    in_chunk = false;
  }

  void serve() {
    std::uint64_t seen = 0;
    std::unique_lock lock(mutex);
    for (;;) {
      wake.wait(lock, [&] { return stop || generation != seen; });
      if (stop)
        return;
      seen = generation;
      lock.unlock();
      run_chunks();
      lock.lock();
      if (--working == 0)
        finished.notify_one();
    }
  }

  void split(std::int32_t n, std::int32_t chunk, void (*work)(void*, std::int32_t, std::int32_t),
             void* work_context) {
    {
      const std::lock_guard lock(mutex);
      body = work;
      context = work_context;
      chunks.clear();
      add_chunks(0, n, std::max<std::int32_t>(1, chunk));
      next.store(0);
      error = nullptr;
      working = static_cast<int>(threads.size());
      ++generation;
    }
    wake.notify_all();
    run_chunks();
    // Every worker passes through each loop once, so the next loop finds them all waiting.
    std::unique_lock lock(mutex);
    finished.wait(lock, [&] { return working == 0; });
    if (error) {
      std::exception_ptr thrown = std::exchange(error, nullptr);
      lock.unlock();
      std::rethrow_exception(thrown);
    }
  }

  std::mutex mutex;
  std::condition_variable wake, finished;
  std::vector<std::thread> threads;
  std::uint64_t generation = 0;
  int working = 0;
  bool stop = false;
  void (*body)(void*, std::int32_t, std::int32_t) = nullptr;
  void* context = nullptr;
  std::vector<std::pair<std::int32_t, std::int32_t>> chunks;  // this loop's, [begin, end)
  std::atomic<std::int32_t> next{0};                          // the next chunk to take
  std::exception_ptr error;  // the first a chunk threw, for the calling thread
};

ParallelRunner::ParallelRunner(int threads) {
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  threads_ = threads > 0 ? threads : cores;
  if (threads_ > 1)
    arena_ = std::make_unique<Arena>(std::min(threads_, cores) - 1);
}

ParallelRunner::~ParallelRunner() = default;

void ParallelRunner::enter(void (*work)(void*), void* context) const {
  work(context);
}

void ParallelRunner::split(std::int32_t count, std::int32_t grain,
                           void (*body)(void*, std::int32_t, std::int32_t), void* context) const {
  ++split_loops_;
  if (in_chunk || arena_->threads.empty()) {
    body(context, 0, count);
    return;
  }
  arena_->split(count, grain, body, context);
}

}  // namespace tumble
