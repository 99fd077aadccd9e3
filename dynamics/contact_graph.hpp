// The order in which the contact solver visits a step's touching pairs, and which of them it may
// solve side by side: each pair gets a colour such that no two pairs of one colour share a body
// that moves, so the pairs of a colour can be solved side by side (one per vector lane, or on
// several threads) and give the same bits in any order. Static bodies do not count: nothing
// writes their velocity.
//
// Source: Catto, "SIMD Matters" (2024) and Box2D v3's constraint graph (src/constraint_graph.c):
// greedy colouring with a bit set of colours per body, and an overflow set for the pairs that
// find no free colour, solved one at a time. (Ordering the pairs by layers from the ground first,
// as shock propagation does, was tried: it held no scene better and split towers into one pair
// per group; docs/architecture.md.)
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace tumble {

class ContactGraph {
 public:
  // Colours; a body with more moving partners sends its extra pairs to the overflow.
  static constexpr int kColors = 64;

  // A run of pairs (in order()) that the solver visits together: either independent pairs of
  // one colour, or the overflow, to be solved one pair at a time.
  struct Group {
    std::int32_t begin = 0;
    std::int32_t end = 0;
    bool sequential = false;
  };

  // Orders pairs: pair i joins bodies slot_a[i] and slot_b[i] of [0, slot_count); slot 0 is the
  // shared slot of every static body. First fit in pair order, so the result depends on the
  // pairs alone; colour by colour, then the overflow.
  void build(std::span<const std::int32_t> slot_a, std::span<const std::int32_t> slot_b,
             std::int32_t slot_count);

  std::span<const std::int32_t> order() const { return order_; }
  std::span<const Group> groups() const { return groups_; }
  int color_count() const { return color_count_; }
  int overflow_pairs() const { return overflow_pairs_; }

 private:
  std::vector<std::int32_t> order_;
  std::vector<Group> groups_;
  int color_count_ = 0;
  int overflow_pairs_ = 0;
  // Scratch kept across steps.
  std::vector<std::uint64_t> used_;  // per slot, the colours its pairs took
  std::vector<std::uint8_t> color_;  // per pair
  std::vector<std::int32_t> color_start_;
};

}  // namespace tumble
