// Runs independent pieces of a step's work on several threads (oneTBB), with results that do not
// depend on the thread count: a loop handed to for_chunks must write, for each index, only what
// that index owns (a body, a bundle of independent contacts, a candidate pair), so that running
// its chunks in any order or at once gives the same bits as running it in one piece. The order
// of anything that accumulates (a body's velocity over the colours of the contact graph) stays
// with the caller, which runs such loops one after another.
//
// One runner per world: its arena caps the threads the world's step uses at `threads()`, and
// run() enters it once per step, so the loops inside share its workers without entering it
// again.
#pragma once

#include <cstdint>
#include <memory>
#include <type_traits>

namespace tumble {

class ParallelRunner {
 public:
  // `threads` <= 0: the machine's cores. More than the cores split the work as that many would,
  // on as many threads as there are cores.
  explicit ParallelRunner(int threads = 1);
  ~ParallelRunner();
  ParallelRunner(const ParallelRunner&) = delete;
  ParallelRunner& operator=(const ParallelRunner&) = delete;

  int threads() const { return threads_; }
  // Loops for_chunks has split over threads since the runner was made (the step's thread calls
  // for_chunks, so a plain count).
  std::int64_t split_loops() const { return split_loops_; }

  // Calls work() inside the runner's arena (directly with one thread).
  template <class Work>
  void run(Work&& work) const {
    if (threads_ <= 1) {
      work();
      return;
    }
    enter(&call<Work>, &work);
  }

  // Calls body(begin, end) on chunks that cover [0, count), each at most `grain` long; with one
  // thread, or fewer than two chunks of work, as one call body(0, count).
  template <class Body>
  void for_chunks(std::int32_t count, std::int32_t grain, Body&& body) const {
    if (count <= 0)
      return;
    if (threads_ <= 1 || count < 2 * grain) {
      body(std::int32_t(0), count);
      return;
    }
    split(count, grain, &call_range<Body>, &body);
  }

 private:
  template <class Work>
  static void call(void* work) {
    (*static_cast<std::remove_reference_t<Work>*>(work))();
  }
  template <class Body>
  static void call_range(void* body, std::int32_t begin, std::int32_t end) {
    (*static_cast<std::remove_reference_t<Body>*>(body))(begin, end);
  }
  void enter(void (*work)(void*), void* context) const;
  void split(std::int32_t count, std::int32_t grain,
             void (*body)(void*, std::int32_t, std::int32_t), void* context) const;

  struct Arena;
  int threads_ = 1;
  mutable std::int64_t split_loops_ = 0;
  std::unique_ptr<Arena> arena_;
};

}  // namespace tumble
