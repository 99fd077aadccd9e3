#include "collision/broad_phase/spatial_hash_broad_phase.hpp"
#include "collision/broad_phase/pair_keys.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <utility>

namespace tumble {
namespace {

// Teschner et al. 2003, section 4.
constexpr std::uint32_t kP1 = 73856093u;
constexpr std::uint32_t kP2 = 19349663u;
constexpr std::uint32_t kP3 = 83492791u;
// Cell coordinates are clamped to +-2^30: monotone in x, so the lower-corner rule still holds,
// and a box reaching the clamp spans so many cells that it is oversized anyway.
constexpr Real kCellLimit = Real(1 << 30);
// An entry's tag: the slot in the low 28 bits; bit 28 + k set when the entry's cell is the first
// cell of the box on axis k; bit 31 set for a static proxy.
constexpr std::uint32_t kStaticBit = 1u << 31;
constexpr int kLowShift = 28;
constexpr std::uint32_t kSlotMask = (1u << kLowShift) - 1;
constexpr std::uint32_t kAllLow = 7u << kLowShift;

using detail::pair_key;

std::size_t next_pow2(std::size_t n) {
  std::size_t m = 16;
  while (m < n)
    m <<= 1;
  return m;
}

// Interleaves the low 21 bits of x, y, z (Morton 1966): nearby cells get nearby codes.
std::uint64_t morton(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  auto spread = [](std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  return spread(x) | spread(y) << 1 | spread(z) << 2;
}

inline bool same_cell(const std::int32_t* a, const std::int32_t* b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

}  // namespace

SpatialHashBroadPhase::SpatialHashBroadPhase(const SpatialHashSettings& settings)
    : settings_(settings) {}

std::uint32_t SpatialHashBroadPhase::allocate_slot() {
  if (!free_slots_.empty()) {
    const std::uint32_t s = free_slots_.back();
    free_slots_.pop_back();
    return s;
  }
  proxies_.emplace_back();
  boxes_.emplace_back();
  assert(proxies_.size() <= kSlotMask);
  return static_cast<std::uint32_t>(proxies_.size() - 1);
}

void SpatialHashBroadPhase::mark_dirty(std::uint32_t slot) {
  Proxy& p = proxies_[slot];
  if (!p.dirty) {
    p.dirty = true;
    dirty_.push_back(slot);
  }
}

void SpatialHashBroadPhase::insert(std::int32_t id, const Aabb& box, bool is_static) {
  assert(id >= 0);
  if (static_cast<std::size_t>(id) >= id_to_slot_.size())
    id_to_slot_.resize(static_cast<std::size_t>(id) + 1, -1);
  assert(id_to_slot_[id] < 0 && "id inserted twice");
  const std::uint32_t slot = allocate_slot();
  Proxy& p = proxies_[slot];
  const bool listed = p.dirty;  // a reused slot may still be in dirty_
  p = Proxy{};
  p.dirty = listed;
  p.id = id;
  p.is_static = is_static;
  p.state = State::live;
  boxes_[slot] = box;
  id_to_slot_[id] = static_cast<std::int32_t>(slot);
  mark_dirty(slot);  // the table's entries for this slot, if any, are someone else's
  ++live_;
}

void SpatialHashBroadPhase::remove(std::int32_t id) {
  const std::int32_t slot = id_to_slot_[id];
  assert(slot >= 0 && "removing an id that is not there");
  id_to_slot_[id] = -1;
  proxies_[slot].state = State::free;  // its table entries are skipped until the next build
  free_slots_.push_back(static_cast<std::uint32_t>(slot));
  --live_;
}

void SpatialHashBroadPhase::update(std::int32_t id, const Aabb& box) {
  const auto slot = static_cast<std::uint32_t>(id_to_slot_[id]);
  boxes_[slot] = box;
  mark_dirty(slot);
}

std::int32_t SpatialHashBroadPhase::cell_of(Real x) const {
  const Real c = std::floor(x * inv_cell_size_);
  if (!(c > -kCellLimit))
    return -(1 << 30);
  if (c > kCellLimit)
    return 1 << 30;
  return static_cast<std::int32_t>(c);
}

std::uint32_t SpatialHashBroadPhase::bucket_of(std::int32_t x, std::int32_t y,
                                               std::int32_t z) const {
  return ((static_cast<std::uint32_t>(x) * kP1) ^ (static_cast<std::uint32_t>(y) * kP2) ^
          (static_cast<std::uint32_t>(z) * kP3)) &
         bucket_mask_;
}

void SpatialHashBroadPhase::choose_cell_size() {
  if (settings_.cell_size > 0) {
    cell_size_ = settings_.cell_size;
  } else {
    // r: the radius of each box's bounding sphere, half its diagonal, averaged.
    Real sum = 0;
    std::size_t n = 0;
    for (std::size_t s = 0; s < proxies_.size(); ++s) {
      if (proxies_[s].state != State::live)
        continue;
      const Real r = Real(0.5) * (boxes_[s].max - boxes_[s].min).norm();
      if (std::isfinite(r)) {
        sum += r;
        ++n;
      }
    }
    const Real mean = n > 0 ? sum / Real(n) : Real(0);
    if (cell_size_ == 0 || mean > 2 * mean_at_choice_ || mean < Real(0.5) * mean_at_choice_) {
      mean_at_choice_ = mean;
      cell_size_ = 2 * mean;
      if (!(cell_size_ > 0) || !std::isfinite(cell_size_))
        cell_size_ = 1;  // all boxes are points (or none): any h works
    }
  }
  inv_cell_size_ = 1 / cell_size_;
}

// Renumbers the live proxies' slots in Morton order of their first cells and drops the free
// slots. Only between builds' start and fill, when nothing else holds a slot: dirty_ is empty,
// and oversized_, order_ and the table are about to be rebuilt.
void SpatialHashBroadPhase::renumber_slots() {
  morton_.clear();
  for (std::size_t s = 0; s < proxies_.size(); ++s) {
    if (proxies_[s].state != State::live)
      continue;
    const Aabb& b = boxes_[s];
    const auto c = [&](int k) { return static_cast<std::uint32_t>(cell_of(b.min[k])); };
    morton_.emplace_back(morton(c(0), c(1), c(2)), static_cast<std::uint32_t>(s));
  }
  std::sort(morton_.begin(), morton_.end());
  renumbered_proxies_.resize(morton_.size());
  renumbered_boxes_.resize(morton_.size());
  for (std::size_t i = 0; i < morton_.size(); ++i) {
    const std::uint32_t s = morton_[i].second;
    renumbered_proxies_[i] = proxies_[s];
    renumbered_boxes_[i] = boxes_[s];
    id_to_slot_[proxies_[s].id] = static_cast<std::int32_t>(i);
  }
  proxies_.swap(renumbered_proxies_);
  boxes_.swap(renumbered_boxes_);
  free_slots_.clear();
  builds_since_renumber_ = 0;
}

void SpatialHashBroadPhase::build() {
  choose_cell_size();
  for (std::uint32_t s : dirty_)
    proxies_[s].dirty = false;
  dirty_.clear();
  if (!built_ || ++builds_since_renumber_ >= 32)
    renumber_slots();

  // Cell ranges; oversized boxes aside. Dynamic proxies first, so that in every bucket their
  // entries precede the static ones.
  order_.clear();
  oversized_.clear();
  ranges_.resize(proxies_.size());
  std::size_t entries = 0;
  const Real max_cells = static_cast<Real>(settings_.max_cells_per_box);
  for (int pass = 0; pass < 2; ++pass) {
    const bool want_static = pass == 1;
    if (want_static)
      dynamic_in_order_ = order_.size();
    for (std::size_t s = 0; s < proxies_.size(); ++s) {
      Proxy& p = proxies_[s];
      if (p.state != State::live || p.is_static != want_static)
        continue;
      const Aabb& b = boxes_[s];
      CellRange& r = ranges_[s];
      Real cells = 1;
      for (int k = 0; k < 3; ++k) {
        r.lo[k] = cell_of(b.min[k]);
        r.hi[k] = cell_of(b.max[k]);
        cells *= Real(r.hi[k]) - Real(r.lo[k]) + 1;
      }
      p.oversized = !(cells <= max_cells) || !std::isfinite(b.min.sum() + b.max.sum());
      if (p.oversized) {
        oversized_.push_back(static_cast<std::uint32_t>(s));
      } else {
        order_.push_back(static_cast<std::uint32_t>(s));
        entries += static_cast<std::size_t>(cells);
      }
    }
  }

  // M: a power of two at least twice the occupied cells, estimated from the last build's ratio
  // of cells to entries; checked after the fill, which is redone with a larger M if short.
  std::size_t estimate = entries;
  if (built_ && entries_at_last_build_ > 0) {
    estimate =
        static_cast<std::size_t>(Real(occupied_) * Real(entries) / Real(entries_at_last_build_)) +
        1;
  }
  std::size_t buckets = next_pow2(2 * estimate + estimate / 4);
  for (;;) {
    bucket_mask_ = static_cast<std::uint32_t>(buckets - 1);
    // Counting sort by bucket: count, prefix sum, scatter. Afterwards bucket_start_[b] is the end
    // of bucket b and the start of bucket b + 1.
    bucket_start_.assign(buckets, 0);
    entry_bucket_.resize(entries);
    std::size_t n = 0;
    for (std::uint32_t s : order_) {
      const CellRange& r = ranges_[s];
      for (std::int32_t z = r.lo[2]; z <= r.hi[2]; ++z) {
        for (std::int32_t y = r.lo[1]; y <= r.hi[1]; ++y) {
          for (std::int32_t x = r.lo[0]; x <= r.hi[0]; ++x) {
            const std::uint32_t b = bucket_of(x, y, z);
            entry_bucket_[n++] = b;
            ++bucket_start_[b];
          }
        }
      }
    }
    std::uint32_t sum = 0;
    for (std::uint32_t& c : bucket_start_) {
      const std::uint32_t t = c;
      c = sum;
      sum += t;
    }
    entries_.resize(entries);
    n = 0;
    for (std::size_t o = 0; o < order_.size(); ++o) {
      const std::uint32_t s = order_[o];
      const std::uint32_t tag = o < dynamic_in_order_ ? s : (s | kStaticBit);
      const CellRange& r = ranges_[s];
      for (std::int32_t z = r.lo[2]; z <= r.hi[2]; ++z) {
        const std::uint32_t tag_z = tag | (z == r.lo[2] ? 4u << kLowShift : 0u);
        for (std::int32_t y = r.lo[1]; y <= r.hi[1]; ++y) {
          const std::uint32_t tag_y = tag_z | (y == r.lo[1] ? 2u << kLowShift : 0u);
          for (std::int32_t x = r.lo[0]; x <= r.hi[0]; ++x) {
            const std::uint32_t tag_x = tag_y | (x == r.lo[0] ? 1u << kLowShift : 0u);
            entries_[bucket_start_[entry_bucket_[n++]]++] = {{x, y, z}, tag_x};
          }
        }
      }
    }
    // Occupied cells: the distinct cells of each bucket, compared against the few distinct
    // ones seen so far in the bucket (all earlier entries only past 8 of them).
    occupied_ = 0;
    std::uint32_t begin = 0;
    for (std::size_t b = 0; b < buckets; ++b) {
      const std::uint32_t end = bucket_start_[b];
      std::array<const std::int32_t*, 8> seen;
      std::size_t n_seen = 0;
      for (std::uint32_t i = begin; i < end; ++i) {
        const std::int32_t* cell = entries_[i].cell;
        bool first = true;
        for (std::size_t d = 0; d < n_seen && first; ++d)
          first = !same_cell(cell, seen[d]);
        if (first && n_seen == seen.size()) {
          for (std::uint32_t j = begin; j < i && first; ++j)
            first = !same_cell(cell, entries_[j].cell);
        }
        if (first) {
          ++occupied_;
          if (n_seen < seen.size())
            seen[n_seen++] = cell;
        }
      }
      begin = end;
    }
    if (2 * occupied_ <= buckets)
      break;
    buckets = next_pow2(2 * occupied_);
  }
  entries_at_last_build_ = entries;
  built_ = true;
}

void SpatialHashBroadPhase::find_pairs(std::vector<ProxyPair>& out) {
  build();
  keys_.clear();
  const Entry* en = entries_.data();
  std::uint32_t begin = 0;
  for (std::size_t b = 0; b <= bucket_mask_; ++b) {
    const std::uint32_t end = bucket_start_[b];
    for (std::uint32_t i = begin; i + 1 < end; ++i) {
      const Entry& ei = en[i];
      if (ei.tag & kStaticBit)
        break;  // the rest are static: static-static pairs are never looked at
      const std::uint32_t si = ei.tag & kSlotMask;
      const std::uint32_t low_i = ei.tag & kAllLow;
      for (std::uint32_t j = i + 1; j < end; ++j) {
        const Entry& ej = en[j];
        // Report from the cell of the intersection's lower corner only, so exactly once. Both
        // boxes span this cell, so on each axis that corner's cell, max of the two boxes' first
        // cells, is this one iff this is the first cell of one of them: no arithmetic needed.
        if (((ej.tag & kAllLow) | low_i) != kAllLow)
          continue;
        if (!same_cell(ei.cell, ej.cell))
          continue;  // another cell that hashed to the same bucket
        const std::uint32_t sj = ej.tag & kSlotMask;
        if (boxes_[si].overlaps(boxes_[sj]))
          keys_.push_back(pair_key(proxies_[si].id, proxies_[sj].id));
      }
    }
    begin = end;
  }
  // Oversized proxies against the table's (only the dynamic ones for a static oversized one)
  // and against each other.
  for (std::size_t oi = 0; oi < oversized_.size(); ++oi) {
    const std::uint32_t o = oversized_[oi];
    const Proxy& po = proxies_[o];
    const Aabb& bo = boxes_[o];
    const std::size_t candidates = po.is_static ? dynamic_in_order_ : order_.size();
    for (std::size_t c = 0; c < candidates; ++c) {
      const std::uint32_t s = order_[c];
      if (bo.overlaps(boxes_[s]))
        keys_.push_back(pair_key(po.id, proxies_[s].id));
    }
    for (std::size_t oj = oi + 1; oj < oversized_.size(); ++oj) {
      const std::uint32_t s = oversized_[oj];
      if (!(po.is_static && proxies_[s].is_static) && bo.overlaps(boxes_[s]))
        keys_.push_back(pair_key(po.id, proxies_[s].id));
    }
  }
  detail::radix_sort_pair_keys(keys_, sort_scratch_);
  assert(std::adjacent_find(keys_.begin(), keys_.end()) == keys_.end());
  out.resize(keys_.size());
  for (std::size_t n = 0; n < keys_.size(); ++n) {
    out[n].a = static_cast<std::int32_t>(keys_[n] >> 32);
    out[n].b = static_cast<std::int32_t>(keys_[n] & 0xffffffffu);
  }
}

template <class Visit>
void SpatialHashBroadPhase::visit_cells(const CellRange& r, Visit&& visit) const {
  const Entry* en = entries_.data();
  for (std::int32_t z = r.lo[2]; z <= r.hi[2]; ++z) {
    for (std::int32_t y = r.lo[1]; y <= r.hi[1]; ++y) {
      for (std::int32_t x = r.lo[0]; x <= r.hi[0]; ++x) {
        const std::uint32_t b = bucket_of(x, y, z);
        const std::uint32_t end = bucket_start_[b];
        for (std::uint32_t i = b == 0 ? 0 : bucket_start_[b - 1]; i < end; ++i) {
          const Entry& e = en[i];
          if (e.cell[0] != x || e.cell[1] != y || e.cell[2] != z)
            continue;
          const std::uint32_t s = e.tag & kSlotMask;
          const Proxy& q = proxies_[s];
          if (q.state == State::live && !q.dirty)  // dirty ones are tested from dirty_
            visit(s, e);
        }
      }
    }
  }
}

// Every live proxy tested on its own: before the first build, or when the cells to visit
// would outnumber the proxies.
void SpatialHashBroadPhase::brute_force(const Aabb* box, const Vec3* origin, const Vec3* direction,
                                        Real max_t, std::vector<std::int32_t>& out) const {
  out.clear();
  for (std::size_t s = 0; s < proxies_.size(); ++s) {
    if (proxies_[s].state != State::live)
      continue;
    const bool hit = box ? boxes_[s].overlaps(*box)
                         : segment_touches_aabb(*origin, *direction, max_t, boxes_[s]);
    if (hit)
      out.push_back(proxies_[s].id);
  }
  std::sort(out.begin(), out.end());
}

void SpatialHashBroadPhase::query(const Aabb& box, std::vector<std::int32_t>& out) const {
  if (!built_) {
    brute_force(&box, nullptr, nullptr, 0, out);
    return;
  }
  CellRange r;
  Real cells = 1;
  for (int k = 0; k < 3; ++k) {
    r.lo[k] = cell_of(box.min[k]);
    r.hi[k] = cell_of(box.max[k]);
    cells *= Real(r.hi[k]) - Real(r.lo[k]) + 1;
  }
  if (!(cells <= Real(std::max<std::size_t>(live_, 64)))) {
    brute_force(&box, nullptr, nullptr, 0, out);
    return;
  }
  out.clear();
  visit_cells(r, [&](std::uint32_t s, const Entry& e) {
    // The lower-corner rule again, one cell reports each proxy: on each axis, the cell must be
    // the first of the proxy's or the first of the query box's.
    for (int k = 0; k < 3; ++k) {
      if (!(e.tag & (1u << (kLowShift + k))) && e.cell[k] != r.lo[k])
        return;
    }
    if (boxes_[s].overlaps(box))
      out.push_back(proxies_[s].id);
  });
  for (std::uint32_t s : oversized_) {
    const Proxy& q = proxies_[s];
    if (q.state == State::live && !q.dirty && boxes_[s].overlaps(box))
      out.push_back(q.id);
  }
  for (std::uint32_t s : dirty_) {
    if (proxies_[s].state == State::live && boxes_[s].overlaps(box))
      out.push_back(proxies_[s].id);
  }
  std::sort(out.begin(), out.end());
}

void SpatialHashBroadPhase::ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                                     std::vector<std::int32_t>& out) const {
  if (!built_) {
    brute_force(nullptr, &origin, &direction, max_t, out);
    return;
  }
  // Cut the segment into pieces at most one cell long on every axis; visit the cells of each
  // piece's box, inflated by a relative 1e-9 so that a box the slab test accepts (within a few
  // ulps of the segment) always overlaps some piece's box.
  Vec3 end;
  Vec3 margin;
  Real longest = 0;
  for (int k = 0; k < 3; ++k) {
    end[k] = direction[k] == 0 ? origin[k] : origin[k] + direction[k] * max_t;
    margin[k] = (std::abs(origin[k]) + std::abs(end[k])) * Real(1e-9);
    longest = std::max(longest, std::abs(end[k] - origin[k]));
  }
  const Real pieces_real = std::ceil(longest * inv_cell_size_);
  if (!(pieces_real <= Real(std::max<std::size_t>(live_ / 8, 16))) || !margin.allFinite()) {
    brute_force(nullptr, &origin, &direction, max_t, out);
    return;
  }
  const int pieces = std::max(1, static_cast<int>(pieces_real));
  out.clear();
  for (int p = 0; p < pieces; ++p) {
    const Real t0 = max_t * Real(p) / Real(pieces);
    const Real t1 = p + 1 == pieces ? max_t : max_t * Real(p + 1) / Real(pieces);
    CellRange r;
    for (int k = 0; k < 3; ++k) {
      const Real a = direction[k] == 0 ? origin[k] : origin[k] + direction[k] * t0;
      const Real b = direction[k] == 0 ? origin[k] : origin[k] + direction[k] * t1;
      r.lo[k] = cell_of(std::min(a, b) - margin[k]);
      r.hi[k] = cell_of(std::max(a, b) + margin[k]);
    }
    visit_cells(r, [&](std::uint32_t s, const Entry&) {
      if (segment_touches_aabb(origin, direction, max_t, boxes_[s]))
        out.push_back(proxies_[s].id);
    });
  }
  for (std::uint32_t s : oversized_) {
    const Proxy& q = proxies_[s];
    if (q.state == State::live && !q.dirty &&
        segment_touches_aabb(origin, direction, max_t, boxes_[s]))
      out.push_back(q.id);
  }
  for (std::uint32_t s : dirty_) {
    if (proxies_[s].state == State::live &&
        segment_touches_aabb(origin, direction, max_t, boxes_[s]))
      out.push_back(proxies_[s].id);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

}  // namespace tumble
