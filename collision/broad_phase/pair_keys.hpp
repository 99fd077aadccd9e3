// Candidate pairs as 64-bit keys a << 32 | b with a < b: sorting the keys sorts the pairs by
// (a, b), the order every broad phase reports them in. Shared by the structures that collect
// pairs in whatever order their traversal finds them and sort once at the end.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace tumble::detail {

inline std::uint64_t pair_key(std::int32_t a, std::int32_t b) {
  if (a > b)
    std::swap(a, b);
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

// Sorts the keys ascending. `scratch` is reused between calls, so sorting allocates nothing
// once it has grown.
void radix_sort_pair_keys(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch);

}  // namespace tumble::detail
