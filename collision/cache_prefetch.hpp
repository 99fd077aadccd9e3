// Asking the memory system for data before it is needed. A batch steps many small worlds one after
// another on each thread, and a large batch's worlds do not stay in the cache between their steps:
// each step then begins by waiting on its own arrays, one miss (and page walk) after another, most
// of them small arrays on pages of their own. Asking for the next world's arrays while this one
// steps lets those misses overlap with work (docs/rl.md, "Memory").
#pragma once

#include <cstddef>
#include <vector>

namespace tumble {

// What one world asks for at most: the next world must fit in the second-level cache beside the
// one stepping, or the fetch pushes out what this step still needs. A larger world gets its first
// bytes of each array only (the headers, and the bodies' start).
inline constexpr std::size_t kPrefetchBytesPerArray = 16 * 1024;

inline void prefetch_bytes(const void* data, std::size_t bytes) {
  const char* p = static_cast<const char*>(data);
  const std::size_t n = bytes < kPrefetchBytesPerArray ? bytes : kPrefetchBytesPerArray;
  for (std::size_t offset = 0; offset < n; offset += 64)
    __builtin_prefetch(p + offset, /*read*/ 0, /*into every level but the first*/ 2);
}

template <class T>
void prefetch_array(const std::vector<T>& v) {
  prefetch_bytes(v.data(), v.size() * sizeof(T));
}

template <class T>
void prefetch_object(const T& object) {
  prefetch_bytes(&object, sizeof(T));
}

}  // namespace tumble
