// Asking the memory system for data before it is needed. A batch steps many small worlds one after
// another on each thread, and a large batch's worlds do not stay in the cache between their steps:
// each step then begins by waiting on its own arrays, one miss (and page walk) after another, most
// of them small arrays on pages of their own. Asking for the next world's arrays just before this
// one steps lets those misses overlap with its work (docs/rl.md, "Asking for the next world").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tumble {

// The requests for one world's data, up to a budget: the next world must fit in the second-level
// cache beside the one stepping, or the requests push out what this step still needs. Arrays
// asked for after the budget is spent are left to the step's own misses.
class CachePrefetch {
 public:
  static constexpr std::size_t kBytesPerWorld = 64 * 1024;
  static constexpr std::size_t kLineBytes = 64;

  // Every cache line that bytes [data, data + bytes) touch, as far as the budget goes.
  void ask(const void* data, std::size_t bytes) {
    if (bytes == 0 || left_ == 0)
      return;
    const std::uintptr_t begin = reinterpret_cast<std::uintptr_t>(data);
    const std::uintptr_t first_line = begin / kLineBytes * kLineBytes;
    const std::size_t span = begin + bytes - first_line;
    const std::size_t asked = span < left_ ? span : left_;
    left_ -= asked;
    // Addresses as integers: the first line may begin before the object.
    for (std::size_t offset = 0; offset < asked; offset += kLineBytes)
      __builtin_prefetch(reinterpret_cast<const void*>(first_line + offset), /*read*/ 0,
                         /*locality: the second-level hint*/ 2);
  }

  template <class T>
  void ask(const std::vector<T>& v) {
    ask(v.data(), v.size() * sizeof(T));
  }

  // Arrays in the order given, while the budget lasts.
  template <class... Arrays>
  void ask_each(const Arrays&... arrays) {
    (ask(arrays), ...);
  }

  template <class T>
  void ask_object(const T& object) {
    ask(&object, sizeof(T));
  }

 private:
  std::size_t left_ = kBytesPerWorld;
};

}  // namespace tumble
