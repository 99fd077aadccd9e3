// Incremental sweep and prune on three axes.
//
// Sources: D. Baraff, "Dynamic simulation of non-penetrating rigid bodies", PhD thesis, Cornell
// University, 1992 (keep the bounding boxes' interval endpoints sorted on each axis and exploit
// coherence: insertion sort of an almost sorted list is O(n + swaps), and each swap is exactly
// one change of interval overlap on that axis); J. D. Cohen, M. C. Lin, D. Manocha,
// M. K. Ponamgi, "I-COLLIDE: an interactive and exact collision detection system for
// large-scale environments", ACM Symposium on Interactive 3D Graphics, 1995 ("sweep and prune":
// a pair is a candidate when its intervals overlap on all three axes, and that status changes
// only at swaps).
//
// Cost: one swap per endpoint crossed. With coherent motion that is few per proxy, but at a
// fixed density in 3D the endpoints per metre of one axis grow as n^(2/3), so the swaps per step
// grow as n^(5/3) x speed: sweep and prune suits up to some 10^4 bodies; grids and trees scale
// further.
//
// Data: per axis, the sorted endpoints of every proxy as two parallel arrays (values, and a
// 32-bit word `slot << 1 | is_max`), with a sentinel at each end so insertion sort needs no
// bounds checks; per proxy, the index of each of its six endpoints, so an update finds them in
// O(1) and an overlap test on an axis is two integer compares. Equal values sort min before
// max, so the positions encode the closed-interval overlap of Aabb::overlaps exactly.
//
// Pairs: the reported set is a pure function of the boxes, so it is not stored as a hash set
// with a flag per pair; instead each swap that can flip a pair's overlap (a min crossing a max
// while the other two axes overlap) records the pair as "touched". find_pairs re-tests the
// touched pairs with Aabb::overlaps and merges them into last step's sorted list: O(pairs +
// touched) a step, and nothing at all for pairs whose status did not change. Swaps between two
// static proxies record nothing: static pairs are never reported.
//
// Large moves (teleports): when a move would cross many endpoints (estimated from the axes'
// endpoint densities; the rule is at SweepAndPruneSettings), the proxy is removed and
// inserted again: its old pairs are touched, its endpoints stay in the arrays as dead entries,
// and the new box waits in a pending list. find_pairs merges all pending endpoints at once
// (sorted, then one merge pass per axis that also drops the dead ones: O(n + m log m) for m
// inserts, where inserting each by binary search and memmove would be O(n m)), then touches
// every pair of each new proxy found by a box query. Insert and remove use the same path, so a
// bulk load of n proxies is one sort and one merge.
//
// Box queries and ray casts: a proxy overlapping the box [lo, hi] on axis k has its min
// endpoint in [lo_k - w_k, hi_k] when its extent on k is at most w_k. So the search scans the
// endpoints in that value range (two binary searches) on the axis where it is shortest, and
// tests the few proxies wider than w on some axis (infinite ones included) from a separate list.
// w_k is re-chosen now and then from a histogram of extents, minimising (endpoint density x w)
// + 2 x (proxies wider than w). A ray cast searches its segment's box, inflated by a relative
// 1e-9 so rounding never hides a box that segment_touches_aabb accepts.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "collision/broad_phase/broad_phase.hpp"

namespace tumble {

struct SweepAndPruneSettings {
  // A move takes the remove-and-reinsert path instead of insertion sort when the endpoints it
  // would cross, estimated as the sum over the axes of |displacement| x (endpoints per metre on
  // that axis), exceed both `large_move_crossings` and `window_weight` x the endpoints a box
  // query for it would scan (its extent plus the query bound, times the density, on the best
  // axis): the reinsertion's cost is two such queries and a share of one merge pass, the
  // sort's cost is one swap per crossing. Both paths are exact; these only trade speed. Setting
  // both to 0 sends every move that changes a box through remove/reinsert, infinity none.
  Real large_move_crossings = 64;
  Real window_weight = 2;
};

class SweepAndPruneBroadPhase final : public BroadPhase {
 public:
  explicit SweepAndPruneBroadPhase(const SweepAndPruneSettings& settings = {});

  void insert(std::int32_t id, const Aabb& box, bool is_static) override;
  void remove(std::int32_t id) override;
  void update(std::int32_t id, const Aabb& box) override;
  void find_pairs(std::vector<ProxyPair>& out) override;
  void query(const Aabb& box, std::vector<std::int32_t>& out) const override;
  void ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                std::vector<std::int32_t>& out) const override;

  // What the structure did, for tests and profiling.
  struct Counters {
    std::int64_t small_moves = 0;  // updates done by insertion sort
    std::int64_t large_moves = 0;  // updates done by remove and reinsert
    std::int64_t swaps = 0;        // endpoint swaps made by insertion sort
  };
  const Counters& counters() const { return counters_; }
  // Proxies kept in the list of wide ones (wider than the query bound on some axis).
  std::size_t wide_count() const { return wide_.size(); }

 private:
  enum class State : std::uint8_t { free, pending, live, dead };

  // What insertion sort touches for every endpoint it passes: 32 bytes, half a cache line.
  struct Proxy {
    std::uint32_t ep[3][2] = {};   // index of the min [0] and max [1] endpoint on each axis
    std::int32_t list_index = -1;  // position in pending_ while pending, in wide_ while wide
    State state = State::free;
    bool is_static = false;
  };
  static_assert(sizeof(Proxy) == 32);

  std::uint32_t allocate_slot();
  void move_endpoint(int axis, std::uint32_t slot, int kind, Real value);
  void touch_overlaps(std::uint32_t slot);
  void flush();
  void maybe_recompute_bounds();
  void recompute_bounds();
  void classify(std::uint32_t slot);
  bool pair_is_live(std::uint64_t key) const;
  template <class Visit>
  void visit_overlaps(const Aabb& box, Visit&& visit) const;

  SweepAndPruneSettings settings_;
  std::vector<Proxy> proxies_;     // by slot
  std::vector<Aabb> boxes_;        // by slot
  std::vector<std::int32_t> ids_;  // by slot
  std::vector<std::int32_t> id_to_slot_;
  std::vector<std::uint32_t> free_slots_;
  std::vector<std::uint32_t> pending_;     // slots inserted since the last find_pairs
  std::vector<std::uint32_t> dead_;        // slots removed, whose endpoints are still in place
  std::vector<std::uint32_t> wide_;        // live slots wider than bound_ on some axis
  std::vector<Real> value_[3];             // endpoint values, sorted, sentinels at both ends
  std::vector<std::uint32_t> data_[3];     // slot << 1 | is_max, parallel to value_
  std::vector<std::uint64_t> touched_;     // pair keys whose status may have changed
  std::vector<std::uint64_t> pairs_;       // last reported pairs, keys a << 32 | b, sorted
  std::vector<std::uint64_t> next_pairs_;  // scratch
  std::vector<std::uint64_t> sort_scratch_;
  std::vector<Real> merge_value_;
  std::vector<std::uint32_t> merge_data_;
  std::vector<std::pair<Real, std::uint32_t>> new_endpoints_;
  std::vector<std::uint32_t> new_slots_;
  Real bound_[3] = {0, 0, 0};    // w_k: the widest extent kept out of wide_
  Real density_[3] = {0, 0, 0};  // endpoints per metre on each axis, at the last recompute
  std::size_t live_ = 0;
  std::size_t live_at_recompute_ = 0;
  std::size_t wide_at_recompute_ = 0;
  int steps_since_recompute_ = 0;
  bool bounds_valid_ = false;
  Counters counters_;
};

}  // namespace tumble
