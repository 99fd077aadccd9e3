#include "collision/broad_phase/pair_keys.hpp"

#include <algorithm>
#include <array>
#include <bit>

namespace tumble::detail {

// Ids are small, so the keys are first packed to a << w | b with w
// the bit width of the largest b, then sorted by LSD radix in as few passes of at most 12 bits
// as that width allows (2 passes for 2k ids, 3 for 100k); std::sort for short lists.
void radix_sort_pair_keys(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch) {
  const std::size_t n = keys.size();
  if (n < 256) {
    std::sort(keys.begin(), keys.end());
    return;
  }
  std::uint64_t all = 0;
  for (std::uint64_t k : keys)
    all |= k;
  const int lo_bits = std::bit_width(static_cast<std::uint32_t>(all));
  const int total = lo_bits + std::bit_width(static_cast<std::uint32_t>(all >> 32));
  const std::uint64_t lo_mask = (std::uint64_t(1) << lo_bits) - 1;
  const int passes = std::max(1, (total + 11) / 12);
  const int digit = (total + passes - 1) / passes;
  const std::uint64_t digit_mask = (std::uint64_t(1) << digit) - 1;
  static constexpr int kMaxPasses = 6;  // 64 bits at 12 a pass, rounded up
  std::array<std::array<std::uint32_t, 4096>, kMaxPasses> counts;
  for (int p = 0; p < passes; ++p)
    std::fill_n(counts[p].begin(), std::size_t(1) << digit, 0u);
  for (std::uint64_t& k : keys) {
    k = ((k >> 32) << lo_bits) | (k & lo_mask);
    for (int p = 0; p < passes; ++p)
      ++counts[p][(k >> (p * digit)) & digit_mask];
  }
  scratch.resize(n);
  std::uint64_t* src = keys.data();
  std::uint64_t* dst = scratch.data();
  for (int p = 0; p < passes; ++p) {
    std::uint32_t sum = 0;
    for (std::size_t d = 0; d <= digit_mask; ++d) {
      const std::uint32_t t = counts[p][d];
      counts[p][d] = sum;
      sum += t;
    }
    for (std::size_t i = 0; i < n; ++i)
      dst[counts[p][(src[i] >> (p * digit)) & digit_mask]++] = src[i];
    std::swap(src, dst);
  }
  for (std::size_t i = 0; i < n; ++i)
    keys[i] = ((src[i] >> lo_bits) << 32) | (src[i] & lo_mask);
}

}  // namespace tumble::detail
