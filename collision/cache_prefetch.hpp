// Asking the memory system for data before it is needed. A batch steps many small worlds one after
// another on each thread, and a large batch's worlds do not stay in the cache between their steps:
// each step then begins by waiting on its own arrays, one miss (and page walk) after another, most
// of them small arrays on pages of their own. Asking for the next world's arrays while this one
// steps lets those misses overlap with its work (docs/rl.md, "Asking for the next world").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tumble {

// The requests for one world's data, up to a budget: the next world must fit in the second-level
// cache beside the one stepping, or the requests push out what this step still needs. Arrays
// asked for after the budget is spent are left to the step's own misses.
//
// The lines are recorded (record), then asked for by issue(): all at once, or a slice at a time
// between the stages of another world's step. Several hundred requests in one burst wait for the
// core's few miss buffers, and the step that issued them waits with them (docs/rl.md, "How the rate
// falls with the batch's size").
class CachePrefetch {
 public:
  static constexpr std::size_t kBytesPerWorld = 64 * 1024;
  // The bytes of small worlds a thread's caches keep between their steps, about, counted as the
  // capacities of the worlds' arrays (Simulation::memory): a batch whose worlds hold more than
  // this per thread asks ahead; one whose worlds stay in the cache does not (the requests would
  // only be work). On the AMD EPYC machine of docs/rl.md a boxes20 world holds about 34 KB so
  // counted, so a thread of 256 such worlds or more asks ahead, one of 128 or fewer does not.
  static constexpr std::size_t kWorldBytesCachedPerThread = 8 << 20;
  static constexpr std::size_t kLineBytes = 64;
  // More arrays than a world's step reads; the ones past it are left to the step's own misses.
  static constexpr int kMaxRanges = 32;

  // Asks at once for every cache line of `object`.
  template <class T>
  static void issue_now(const T& object) {
    const std::uintptr_t begin = reinterpret_cast<std::uintptr_t>(&object);
    for (std::uintptr_t line = line_of(begin); line < begin + sizeof(T); line += kLineBytes)
      issue_line(line);
  }

  // Records every cache line that bytes [data, data + bytes) touch, as far as the budget goes.
  void record(const void* data, std::size_t bytes) {
    if (bytes == 0 || left_ == 0 || ranges_ == kMaxRanges)
      return;
    const std::uintptr_t begin = reinterpret_cast<std::uintptr_t>(data);
    const std::uintptr_t first_line = line_of(begin);
    const std::size_t span = begin + bytes - first_line;
    const std::size_t asked = span < left_ ? span : left_;
    left_ -= asked;
    next_line_[ranges_] = first_line;
    end_[ranges_] = first_line + asked;
    ++ranges_;
  }

  template <class T>
  void record(const std::vector<T>& v) {
    record(v.data(), v.size() * sizeof(T));
  }

  // Arrays in the order given, while the budget lasts.
  template <class... Arrays>
  void record_each(const Arrays&... arrays) {
    (record(arrays), ...);
  }

  // Asks the memory system for up to `lines` of the recorded lines not yet asked for, in the
  // order they were recorded.
  void issue(std::size_t lines) {
    for (; lines > 0 && issued_ < ranges_; ++issued_) {
      std::uintptr_t& line = next_line_[issued_];
      for (; lines > 0 && line < end_[issued_]; line += kLineBytes, --lines)
        issue_line(line);
      if (line < end_[issued_])
        return;
    }
  }
  void issue_all() { issue(~std::size_t(0)); }

  // Lines recorded and not yet asked for.
  std::size_t pending_lines() const {
    std::size_t lines = 0;
    for (int r = issued_; r < ranges_; ++r)
      lines += (end_[r] - next_line_[r] + kLineBytes - 1) / kLineBytes;
    return lines;
  }

  // Forgets every request, asked for or not, and restores the budget.
  void clear() {
    left_ = kBytesPerWorld;
    ranges_ = 0;
    issued_ = 0;
  }

 private:
  // Addresses as integers: a line may begin before the object it is asked for.
  static std::uintptr_t line_of(std::uintptr_t address) {
    return address / kLineBytes * kLineBytes;
  }
  static void issue_line(std::uintptr_t line) {
    __builtin_prefetch(reinterpret_cast<const void*>(line), /*read*/ 0,
                       /*locality: the second-level hint*/ 2);
  }

  std::size_t left_ = kBytesPerWorld;
  int ranges_ = 0;
  int issued_ = 0;  // ranges before this one are all asked for
  std::uintptr_t next_line_[kMaxRanges]{};
  std::uintptr_t end_[kMaxRanges]{};
};

}  // namespace tumble
