#include "collision/broad_phase/sweep_and_prune_broad_phase.hpp"
#include "collision/broad_phase/pair_keys.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <utility>

namespace tumble {
namespace {

constexpr Real kInf = std::numeric_limits<Real>::infinity();

// Endpoint order: by value, and at equal values every min before every max, so that two
// intervals that share an end value come out overlapping, as closed intervals do.
inline bool key_less(Real va, std::uint32_t da, Real vb, std::uint32_t db) {
  return va < vb || (va == vb && (da & 1u) < (db & 1u));
}

using detail::pair_key;

// The lowest value the min endpoint of a proxy of extent <= w overlapping [lo, ...] can have,
// rounded down generously (1e-9 relative) so floating-point error never excludes one.
inline Real window_lower(Real lo, Real w) {
  if (!std::isfinite(lo))
    return lo;
  return lo - w - (w + std::abs(lo)) * Real(1e-9);
}

// Buckets of the extent histogram: one per power of two, 2^-64 .. 2^63 (clamped).
constexpr int kExtentBuckets = 128;

}  // namespace

SweepAndPruneBroadPhase::SweepAndPruneBroadPhase(const SweepAndPruneSettings& settings)
    : settings_(settings) {
  for (int k = 0; k < 3; ++k) {
    // Sentinels: nothing sorts below (-inf, min) or above (+inf, max), so insertion sort stops
    // on them without a bounds check. Their data is never read.
    value_[k] = {-kInf, kInf};
    data_[k] = {0u, 1u};
  }
}

std::uint32_t SweepAndPruneBroadPhase::allocate_slot() {
  if (!free_slots_.empty()) {
    const std::uint32_t s = free_slots_.back();
    free_slots_.pop_back();
    return s;
  }
  proxies_.emplace_back();
  boxes_.emplace_back();
  ids_.emplace_back();
  assert(proxies_.size() < (std::size_t(1) << 31));
  return static_cast<std::uint32_t>(proxies_.size() - 1);
}

void SweepAndPruneBroadPhase::insert(std::int32_t id, const Aabb& box, bool is_static) {
  assert(id >= 0);
  assert(box.min.x() <= box.max.x() && box.min.y() <= box.max.y() && box.min.z() <= box.max.z());
  if (static_cast<std::size_t>(id) >= id_to_slot_.size())
    id_to_slot_.resize(static_cast<std::size_t>(id) + 1, -1);
  assert(id_to_slot_[id] < 0 && "id inserted twice");
  const std::uint32_t slot = allocate_slot();
  Proxy& p = proxies_[slot];
  p = Proxy{};
  ids_[slot] = id;
  p.is_static = is_static;
  p.state = State::pending;
  p.list_index = static_cast<std::int32_t>(pending_.size());
  pending_.push_back(slot);
  boxes_[slot] = box;
  id_to_slot_[id] = static_cast<std::int32_t>(slot);
}

void SweepAndPruneBroadPhase::remove(std::int32_t id) {
  const std::int32_t signed_slot = id_to_slot_[id];
  assert(signed_slot >= 0 && "removing an id that is not there");
  const auto slot = static_cast<std::uint32_t>(signed_slot);
  id_to_slot_[id] = -1;
  Proxy& p = proxies_[slot];
  if (p.state == State::pending) {
    // Never reached the arrays, never reported: just forget it.
    const std::uint32_t last = pending_.back();
    pending_[p.list_index] = last;
    proxies_[last].list_index = p.list_index;
    pending_.pop_back();
    p.state = State::free;
    free_slots_.push_back(slot);
    return;
  }
  // Its pairs disappear; its endpoints stay in place (still sorted) until the next find_pairs
  // drops every dead one in a single pass.
  touch_overlaps(slot);
  if (p.list_index >= 0) {
    const std::uint32_t last = wide_.back();
    wide_[p.list_index] = last;
    proxies_[last].list_index = p.list_index;
    wide_.pop_back();
    p.list_index = -1;
  }
  p.state = State::dead;
  dead_.push_back(slot);
  --live_;
}

void SweepAndPruneBroadPhase::update(std::int32_t id, const Aabb& box) {
  assert(box.min.x() <= box.max.x() && box.min.y() <= box.max.y() && box.min.z() <= box.max.z());
  const auto slot = static_cast<std::uint32_t>(id_to_slot_[id]);
  Proxy& p = proxies_[slot];
  if (p.state == State::pending) {
    boxes_[slot] = box;  // merged with its final box at the next find_pairs
    return;
  }
  const Aabb old = boxes_[slot];
  // Large move (see SweepAndPruneSettings): estimated crossings against the estimated window
  // of the two box queries a reinsertion makes. A NaN displacement (an infinite end that stays
  // infinite) fails `d > 0`, which is right: that end does not move.
  Real crossings = 0;
  Real window = kInf;
  for (int k = 0; k < 3; ++k) {
    const Real d = std::max(std::abs(box.min[k] - old.min[k]), std::abs(box.max[k] - old.max[k]));
    if (d > 0)
      crossings += d * density_[k];
    window = std::min(window, density_[k] * (bound_[k] + (box.max[k] - box.min[k])));
  }
  const bool large =
      crossings > settings_.large_move_crossings && crossings > settings_.window_weight * window;
  if (large) {
    ++counters_.large_moves;
    const bool is_static = p.is_static;
    remove(id);
    insert(id, box, is_static);
    return;
  }
  ++counters_.small_moves;
  for (int k = 0; k < 3; ++k) {
    const Real lo = box.min[k];
    const Real hi = box.max[k];
    if (lo == old.min[k] && hi == old.max[k])
      continue;
    // Move the leading end first, so the interval never turns inside out and a proxy's own
    // endpoints never cross each other.
    if (lo < old.min[k]) {
      move_endpoint(k, slot, 0, lo);
      move_endpoint(k, slot, 1, hi);
    } else {
      move_endpoint(k, slot, 1, hi);
      move_endpoint(k, slot, 0, lo);
    }
  }
  boxes_[slot] = box;
  classify(slot);
}

// Insertion sort of one endpoint to its new value. Each swap with an endpoint of the other kind
// flips the two intervals' overlap on this axis (Baraff 1992; I-COLLIDE 1995); when they also
// overlap on the other two axes (compared by endpoint index), the pair's status flips, so it is
// touched. Swaps with an endpoint of the same kind change nothing.
void SweepAndPruneBroadPhase::move_endpoint(int axis, std::uint32_t slot, int kind, Real value) {
  Real* val = value_[axis].data();
  std::uint32_t* dat = data_[axis].data();
  Proxy* proxies = proxies_.data();
  const int k1 = axis == 0 ? 1 : 0;
  const int k2 = axis == 2 ? 1 : 2;
  std::uint32_t i = proxies[slot].ep[axis][kind];
  const std::uint32_t d = dat[i];
  const std::uint32_t kind_bit = d & 1u;
  const Proxy& p = proxies[slot];
  auto crossed = [&](std::uint32_t other) __attribute__((always_inline)) {
    const Proxy& q = proxies[other];
    if (q.state != State::live || (p.is_static && q.is_static))
      return;
    if (p.ep[k1][0] < q.ep[k1][1] && q.ep[k1][0] < p.ep[k1][1] && p.ep[k2][0] < q.ep[k2][1] &&
        q.ep[k2][0] < p.ep[k2][1]) {
      touched_.push_back(pair_key(ids_[slot], ids_[other]));
    }
  };
  std::int64_t swaps = 0;
  if (key_less(value, d, val[i], d)) {
    // Down: the sentinel at 0 stops the loop.
    for (;;) {
      const Real pv = val[i - 1];
      const std::uint32_t pd = dat[i - 1];
      if (!key_less(value, d, pv, pd))
        break;
      const std::uint32_t other = pd >> 1;
      assert(other != slot);
      if ((pd & 1u) != kind_bit)
        crossed(other);
      val[i] = pv;
      dat[i] = pd;
      proxies[other].ep[axis][pd & 1u] = i;
      --i;
      ++swaps;
    }
  } else {
    // Up: the sentinel at the end stops the loop.
    for (;;) {
      const Real nv = val[i + 1];
      const std::uint32_t nd = dat[i + 1];
      if (!key_less(nv, nd, value, d))
        break;
      const std::uint32_t other = nd >> 1;
      assert(other != slot);
      if ((nd & 1u) != kind_bit)
        crossed(other);
      val[i] = nv;
      dat[i] = nd;
      proxies[other].ep[axis][nd & 1u] = i;
      ++i;
      ++swaps;
    }
  }
  val[i] = value;
  dat[i] = d;
  proxies[slot].ep[axis][kind] = i;
  counters_.swaps += swaps;
}

template <class Visit>
void SweepAndPruneBroadPhase::visit_overlaps(const Aabb& box, Visit&& visit) const {
  // The axis whose window [box.min - w, box.max] holds the fewest endpoints.
  std::size_t best_lo = 0;
  std::size_t best_hi = 0;
  std::size_t best_count = std::numeric_limits<std::size_t>::max();
  int best = -1;
  for (int k = 0; k < 3; ++k) {
    const std::vector<Real>& v = value_[k];
    const auto first = v.begin() + 1;  // past the sentinels
    const auto last = v.end() - 1;
    const Real lower = window_lower(box.min[k], bound_[k]);
    const auto lo = std::lower_bound(first, last, lower);
    const auto hi = std::upper_bound(lo, last, box.max[k]);
    const auto count = static_cast<std::size_t>(hi - lo);
    if (count < best_count) {
      best_count = count;
      best = k;
      best_lo = static_cast<std::size_t>(lo - v.begin());
      best_hi = static_cast<std::size_t>(hi - v.begin());
    }
  }
  const std::uint32_t* dat = data_[best].data();
  for (std::size_t i = best_lo; i < best_hi; ++i) {
    const std::uint32_t d = dat[i];
    if (d & 1u)
      continue;
    const std::uint32_t s = d >> 1;
    const Proxy& q = proxies_[s];
    if (q.state != State::live || q.list_index >= 0)
      continue;  // dead, or visited from wide_ below
    if (boxes_[s].overlaps(box))
      visit(s);
  }
  for (std::uint32_t s : wide_) {
    if (boxes_[s].overlaps(box))
      visit(s);
  }
}

void SweepAndPruneBroadPhase::touch_overlaps(std::uint32_t slot) {
  const Proxy& p = proxies_[slot];
  visit_overlaps(boxes_[slot], [&](std::uint32_t s) {
    if (s == slot)
      return;
    const Proxy& q = proxies_[s];
    if (p.is_static && q.is_static)
      return;
    touched_.push_back(pair_key(ids_[slot], ids_[s]));
  });
}

void SweepAndPruneBroadPhase::classify(std::uint32_t slot) {
  const Aabb& b = boxes_[slot];
  bool wide = false;
  for (int k = 0; k < 3; ++k)
    wide |= !(b.max[k] - b.min[k] <= bound_[k]);  // infinite extents are wide
  Proxy& p = proxies_[slot];
  if (wide && p.list_index < 0) {
    p.list_index = static_cast<std::int32_t>(wide_.size());
    wide_.push_back(slot);
  } else if (!wide && p.list_index >= 0) {
    const std::uint32_t last = wide_.back();
    wide_[p.list_index] = last;
    proxies_[last].list_index = p.list_index;
    wide_.pop_back();
    p.list_index = -1;
  }
}

// Merges every pending proxy into the three arrays and drops every dead one, one pass per axis
// from the first position that changes.
void SweepAndPruneBroadPhase::flush() {
  if (pending_.empty() && dead_.empty())
    return;
  for (int k = 0; k < 3; ++k) {
    new_endpoints_.clear();
    for (std::uint32_t s : pending_) {
      new_endpoints_.emplace_back(boxes_[s].min[k], s << 1);
      new_endpoints_.emplace_back(boxes_[s].max[k], (s << 1) | 1u);
    }
    std::sort(new_endpoints_.begin(), new_endpoints_.end(), [](const auto& a, const auto& b) {
      if (key_less(a.first, a.second, b.first, b.second))
        return true;
      if (key_less(b.first, b.second, a.first, a.second))
        return false;
      return a.second < b.second;  // a total order, for determinism
    });
    std::vector<Real>& val = value_[k];
    std::vector<std::uint32_t>& dat = data_[k];
    std::size_t start = val.size() - 1;  // the upper sentinel
    if (!new_endpoints_.empty()) {
      // The first old endpoint that sorts after the first new one (old ones go first on ties).
      const Real v0 = new_endpoints_[0].first;
      const std::uint32_t d0 = new_endpoints_[0].second;
      std::size_t lo = 1;
      std::size_t hi = val.size() - 1;
      while (lo < hi) {
        const std::size_t mid = (lo + hi) / 2;
        if (key_less(v0, d0, val[mid], dat[mid]))
          hi = mid;
        else
          lo = mid + 1;
      }
      start = lo;
    }
    for (std::uint32_t s : dead_)
      start = std::min<std::size_t>(start, proxies_[s].ep[k][0]);

    merge_value_.assign(val.begin() + static_cast<std::ptrdiff_t>(start), val.end() - 1);
    merge_data_.assign(dat.begin() + static_cast<std::ptrdiff_t>(start), dat.end() - 1);
    val.resize(start);
    dat.resize(start);
    std::size_t i = 0;
    std::size_t j = 0;
    const std::size_t old_n = merge_value_.size();
    const std::size_t new_n = new_endpoints_.size();
    while (i < old_n || j < new_n) {
      const bool take_old =
          j == new_n || (i < old_n && !key_less(new_endpoints_[j].first, new_endpoints_[j].second,
                                                merge_value_[i], merge_data_[i]));
      Real v;
      std::uint32_t d;
      if (take_old) {
        v = merge_value_[i];
        d = merge_data_[i];
        ++i;
        if (proxies_[d >> 1].state == State::dead)
          continue;
      } else {
        v = new_endpoints_[j].first;
        d = new_endpoints_[j].second;
        ++j;
      }
      proxies_[d >> 1].ep[k][d & 1u] = static_cast<std::uint32_t>(val.size());
      val.push_back(v);
      dat.push_back(d);
    }
    val.push_back(kInf);
    dat.push_back(1u);
  }
  for (std::uint32_t s : dead_) {
    proxies_[s].state = State::free;
    free_slots_.push_back(s);
  }
  dead_.clear();
  new_slots_.swap(pending_);
  pending_.clear();
  for (std::uint32_t s : new_slots_) {
    proxies_[s].state = State::live;
    proxies_[s].list_index = -1;
    classify(s);
  }
  live_ += new_slots_.size();
}

void SweepAndPruneBroadPhase::maybe_recompute_bounds() {
  ++steps_since_recompute_;
  const bool due = !bounds_valid_ || steps_since_recompute_ >= 128 ||
                   live_ > 2 * live_at_recompute_ || 2 * live_ < live_at_recompute_ ||
                   wide_.size() > 2 * wide_at_recompute_ + 32;
  if (due)
    recompute_bounds();
}

// Chooses w_k, the query bound of each axis, and the endpoint density used by the large-move
// estimate, from the live boxes: O(n), every 128 steps or when the population changes a lot.
void SweepAndPruneBroadPhase::recompute_bounds() {
  for (int k = 0; k < 3; ++k) {
    std::array<std::uint32_t, kExtentBuckets> count{};
    std::array<Real, kExtentBuckets> widest{};
    std::size_t infinite = 0;
    std::size_t finite = 0;
    std::size_t positive = 0;
    Real lo = kInf;
    Real hi = -kInf;
    for (std::size_t s = 0; s < proxies_.size(); ++s) {
      if (proxies_[s].state != State::live)
        continue;
      const Aabb& b = boxes_[s];
      const Real e = b.max[k] - b.min[k];
      if (!std::isfinite(e)) {
        ++infinite;
        continue;
      }
      ++finite;
      lo = std::min(lo, b.min[k]);
      hi = std::max(hi, b.max[k]);
      if (e <= 0)
        continue;
      ++positive;
      const int bucket = std::clamp(std::ilogb(e) + 64, 0, kExtentBuckets - 1);
      ++count[bucket];
      widest[bucket] = std::max(widest[bucket], e);
    }
    const Real span = hi - lo;
    const Real density = finite > 0 && span > 0 ? Real(2 * finite) / span : Real(0);
    // Cost of a query ~ endpoints scanned (density x w) + 2 x wide proxies tested.
    Real best_w = 0;
    Real best_cost = 2 * Real(positive + infinite);
    std::size_t above = positive;
    Real w = 0;
    for (int b = 0; b < kExtentBuckets; ++b) {
      if (count[b] == 0)
        continue;
      above -= count[b];
      w = std::max(w, widest[b]);
      const Real cost = density * w + 2 * Real(above + infinite);
      if (cost < best_cost) {
        best_cost = cost;
        best_w = w;
      }
    }
    bound_[k] = best_w;
    density_[k] = density;
  }
  wide_.clear();
  for (std::size_t s = 0; s < proxies_.size(); ++s) {
    if (proxies_[s].state == State::live) {
      proxies_[s].list_index = -1;
      classify(static_cast<std::uint32_t>(s));
    }
  }
  live_at_recompute_ = live_;
  wide_at_recompute_ = wide_.size();
  steps_since_recompute_ = 0;
  bounds_valid_ = true;
}

bool SweepAndPruneBroadPhase::pair_is_live(std::uint64_t key) const {
  const auto a = static_cast<std::size_t>(key >> 32);
  const auto b = static_cast<std::size_t>(key & 0xffffffffu);
  if (a >= id_to_slot_.size() || b >= id_to_slot_.size())
    return false;
  const std::int32_t sa = id_to_slot_[a];
  const std::int32_t sb = id_to_slot_[b];
  if (sa < 0 || sb < 0)
    return false;
  const Proxy& pa = proxies_[sa];
  const Proxy& pb = proxies_[sb];
  if (pa.is_static && pb.is_static)
    return false;
  return boxes_[sa].overlaps(boxes_[sb]);
}

void SweepAndPruneBroadPhase::find_pairs(std::vector<ProxyPair>& out) {
  flush();
  maybe_recompute_bounds();
  // New proxies (inserted, or reinserted after a large move): every pair they are in is new.
  for (std::uint32_t s : new_slots_)
    touch_overlaps(s);
  new_slots_.clear();

  detail::radix_sort_pair_keys(touched_, sort_scratch_);
  touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());
  // Last step's pairs, with each touched pair re-tested on the real boxes.
  next_pairs_.clear();
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < pairs_.size() || j < touched_.size()) {
    if (j == touched_.size() || (i < pairs_.size() && pairs_[i] < touched_[j])) {
      next_pairs_.push_back(pairs_[i++]);
      continue;
    }
    if (i < pairs_.size() && pairs_[i] == touched_[j])
      ++i;
    const std::uint64_t key = touched_[j++];
    if (pair_is_live(key))
      next_pairs_.push_back(key);
  }
  pairs_.swap(next_pairs_);
  touched_.clear();
  out.resize(pairs_.size());
  for (std::size_t n = 0; n < pairs_.size(); ++n) {
    out[n].a = static_cast<std::int32_t>(pairs_[n] >> 32);
    out[n].b = static_cast<std::int32_t>(pairs_[n] & 0xffffffffu);
  }
}

void SweepAndPruneBroadPhase::query(const Aabb& box, std::vector<std::int32_t>& out) const {
  out.clear();
  visit_overlaps(box, [&](std::uint32_t s) { out.push_back(ids_[s]); });
  for (std::uint32_t s : pending_) {
    if (boxes_[s].overlaps(box))
      out.push_back(ids_[s]);
  }
  std::sort(out.begin(), out.end());
}

void SweepAndPruneBroadPhase::ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                                       std::vector<std::int32_t>& out) const {
  out.clear();
  // The segment's box, inflated by a relative 1e-9: a box the slab test accepts is within a
  // few ulps of the segment, far inside that margin.
  Aabb segment;
  for (int k = 0; k < 3; ++k) {
    const Real a = origin[k];
    const Real b = direction[k] == 0 ? a : a + direction[k] * max_t;
    const Real margin = (std::abs(a) + std::abs(b)) * Real(1e-9);
    segment.min[k] = std::min(a, b) - margin;
    segment.max[k] = std::max(a, b) + margin;
  }
  visit_overlaps(segment, [&](std::uint32_t s) {
    if (segment_touches_aabb(origin, direction, max_t, boxes_[s]))
      out.push_back(ids_[s]);
  });
  for (std::uint32_t s : pending_) {
    if (segment_touches_aabb(origin, direction, max_t, boxes_[s]))
      out.push_back(ids_[s]);
  }
  std::sort(out.begin(), out.end());
}

}  // namespace tumble
