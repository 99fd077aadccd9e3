#include "dynamics/contact_graph.hpp"

#include <bit>

namespace tumble {

void ContactGraph::build(std::span<const std::int32_t> slot_a, std::span<const std::int32_t> slot_b,
                         std::int32_t slot_count) {
  const std::size_t pairs = slot_a.size();
  constexpr std::uint8_t kOverflow = 0xff;
  used_.assign(std::size_t(slot_count), 0);
  color_.resize(pairs);
  color_start_.assign(kColors + 2, 0);
  for (std::size_t i = 0; i < pairs; ++i) {
    const std::int32_t a = slot_a[i];
    const std::int32_t b = slot_b[i];
    const std::uint64_t taken =
        (a > 0 ? used_[std::size_t(a)] : 0) | (b > 0 ? used_[std::size_t(b)] : 0);
    std::uint8_t c = kOverflow;
    if (taken != ~std::uint64_t(0)) {
      const int free = std::countr_one(taken);
      c = static_cast<std::uint8_t>(free);
      const std::uint64_t bit = std::uint64_t(1) << free;
      if (a > 0)
        used_[std::size_t(a)] |= bit;
      if (b > 0)
        used_[std::size_t(b)] |= bit;
    }
    color_[i] = c;
    ++color_start_[std::size_t(c == kOverflow ? kColors : c) + 1];
  }
  for (int c = 0; c <= kColors; ++c)
    color_start_[std::size_t(c) + 1] += color_start_[std::size_t(c)];
  groups_.clear();
  color_count_ = 0;
  overflow_pairs_ = color_start_[kColors + 1] - color_start_[kColors];
  for (int c = 0; c <= kColors; ++c) {
    const std::int32_t first = color_start_[std::size_t(c)];
    const std::int32_t last = color_start_[std::size_t(c) + 1];
    if (first == last)
      continue;
    groups_.push_back({first, last, c == kColors});
    if (c < kColors)
      ++color_count_;
  }
  order_.resize(pairs);
  for (std::size_t i = 0; i < pairs; ++i) {
    const std::size_t bucket = color_[i] == kOverflow ? kColors : color_[i];
    order_[std::size_t(color_start_[bucket]++)] = static_cast<std::int32_t>(i);
  }
}

}  // namespace tumble
