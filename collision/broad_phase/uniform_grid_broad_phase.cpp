// Uniform grid broad phase; the algorithm and its sources are described in the header.
#include "collision/broad_phase/uniform_grid_broad_phase.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <limits>

namespace tumble {

namespace grid_detail {

void ProxyStore::insert(std::int32_t id, const Aabb& box, bool is_static) {
  assert(id >= 0);
  const auto uid = static_cast<std::uint32_t>(id);
  if (uid >= loc_.size())
    loc_.resize(static_cast<std::size_t>(uid) + 1, kNone);
  if (loc_[uid] != kNone)
    remove(id);
  std::vector<GridProxy>& pool = is_static ? fixed : moving;
  loc_[uid] = static_cast<std::uint32_t>(pool.size()) | (is_static ? kStaticBit : 0u);
  pool.push_back({box, id, {}});
  id_bits_ = std::max(id_bits_, static_cast<int>(std::bit_width(uid)));
}

bool ProxyStore::remove(std::int32_t id) {
  const std::uint32_t loc = loc_[static_cast<std::uint32_t>(id)];
  assert(loc != kNone);
  const bool is_static = (loc & kStaticBit) != 0;
  std::vector<GridProxy>& pool = is_static ? fixed : moving;
  const std::uint32_t slot = loc & ~kStaticBit;
  if (slot + 1 != pool.size()) {
    pool[slot] = pool.back();
    loc_[static_cast<std::uint32_t>(pool[slot].id)] = slot | (loc & kStaticBit);
  }
  pool.pop_back();
  loc_[static_cast<std::uint32_t>(id)] = kNone;
  return is_static;
}

bool ProxyStore::update(std::int32_t id, const Aabb& box) {
  const std::uint32_t loc = loc_[static_cast<std::uint32_t>(id)];
  assert(loc != kNone);
  const bool is_static = (loc & kStaticBit) != 0;
  (is_static ? fixed : moving)[loc & ~kStaticBit].box = box;
  return is_static;
}

void ProxyStore::overlapping(const Aabb& box, std::vector<std::int32_t>& out) const {
  out.clear();
  for (const auto* pool : {&moving, &fixed}) {
    for (const GridProxy& p : *pool) {
      if (p.box.overlaps(box))
        out.push_back(p.id);
    }
  }
  std::sort(out.begin(), out.end());
}

void ProxyStore::touched_by_segment(const Vec3& origin, const Vec3& direction, Real max_t,
                                    std::vector<std::int32_t>& out) const {
  out.clear();
  for (const auto* pool : {&moving, &fixed}) {
    for (const GridProxy& p : *pool) {
      if (segment_touches_aabb(origin, direction, max_t, p.box))
        out.push_back(p.id);
    }
  }
  std::sort(out.begin(), out.end());
}

void ProxyStore::permute_moving(const std::vector<std::uint32_t>& order) {
  scratch_.resize(moving.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    scratch_[i] = moving[order[i]];
  moving.swap(scratch_);
  for (std::size_t i = 0; i < moving.size(); ++i)
    loc_[static_cast<std::uint32_t>(moving[i].id)] = static_cast<std::uint32_t>(i);
}

std::uint64_t* radix_sort(std::uint64_t* keys, std::uint64_t* scratch, std::size_t n, int lo_bit,
                          int hi_bit, std::vector<std::uint32_t>& histogram) {
  const int bits = std::max(1, hi_bit - lo_bit);
  const int passes = (bits + 10) / 11;
  const int digit = (bits + passes - 1) / passes;
  const std::size_t radix = std::size_t{1} << digit;
  const std::uint64_t mask = radix - 1;
  histogram.assign(static_cast<std::size_t>(passes) * radix, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (int p = 0; p < passes; ++p)
      ++histogram[p * radix + ((keys[i] >> (lo_bit + p * digit)) & mask)];
  }
  std::uint64_t* src = keys;
  std::uint64_t* dst = scratch;
  for (int p = 0; p < passes && n > 0; ++p) {
    const int shift = lo_bit + p * digit;
    std::uint32_t* h = &histogram[p * radix];
    if (h[(src[0] >> shift) & mask] == n)
      continue;
    std::uint32_t run = 0;
    for (std::size_t b = 0; b < radix; ++b) {
      const std::uint32_t c = h[b];
      h[b] = run;
      run += c;
    }
    for (std::size_t i = 0; i < n; ++i)
      dst[h[(src[i] >> shift) & mask]++] = src[i];
    std::swap(src, dst);
  }
  return src;
}

namespace {

// Spreads the low 10 bits of v two bits apart (Morton code of one axis).
std::uint64_t spread10(std::uint64_t v) {
  v = (v | v << 16) & 0x030000FFu;
  v = (v | v << 8) & 0x0300F00Fu;
  v = (v | v << 4) & 0x030C30C3u;
  v = (v | v << 2) & 0x09249249u;
  return v;
}

}  // namespace

void SpatialOrder::apply(ProxyStore& store) {
  const std::vector<GridProxy>& pool = store.moving;
  const std::size_t n = pool.size();
  Aabb centres;
  for (const GridProxy& p : pool) {
    if (is_regular(p.box))
      centres.grow(Real(0.5) * (p.box.min + p.box.max));
  }
  if (n < 2 || !is_regular(centres))
    return;
  const Vec3 scale =
      Real(1023) * (centres.max - centres.min).cwiseMax(Vec3::Constant(1e-300)).cwiseInverse();
  keys_.resize(n);
  for (std::size_t s = 0; s < n; ++s) {
    const Aabb& b = pool[s].box;
    std::uint64_t key = std::uint64_t{1} << 30;  // after every Morton code
    if (is_regular(b)) {
      const Vec3 q = ((Real(0.5) * (b.min + b.max) - centres.min).cwiseProduct(scale))
                         .cwiseMax(Vec3::Zero())
                         .cwiseMin(Vec3::Constant(1023));
      key = spread10(static_cast<std::uint64_t>(q.x())) |
            spread10(static_cast<std::uint64_t>(q.y())) << 1 |
            spread10(static_cast<std::uint64_t>(q.z())) << 2;
    }
    keys_[s] = key << 32 | s;
  }
  scratch_.resize(n);
  const std::uint64_t* sorted = radix_sort(keys_.data(), scratch_.data(), n, 32, 63, histogram_);
  order_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    order_[i] = static_cast<std::uint32_t>(sorted[i]);
  store.permute_moving(order_);
}

void PairSorter::begin(int id_bits) {
  shift_ = id_bits;
  row_words_ = ((std::size_t{1} << shift_) + 63) / 64;
  const std::size_t words = row_words_ << shift_;
  dense_ = last_count_ >= 256 && words <= 2 * last_count_;
  if (dense_ && bitmap_.size() != words)
    bitmap_.assign(words, 0);
  count_ = 0;
}

void PairSorter::grow() {
  keys_.resize(std::max<std::size_t>(1024, 2 * keys_.size()));
}

void PairSorter::finish(std::vector<ProxyPair>& out) {
  const std::size_t n = count_;
  last_count_ = n;
  if (dense_) {
    out.resize(n);
    std::size_t i = 0;
    for (std::size_t w = 0; w < bitmap_.size(); ++w) {
      std::uint64_t bits = bitmap_[w];
      if (bits == 0)
        continue;
      bitmap_[w] = 0;
      const auto a = static_cast<std::int32_t>(w / row_words_);
      const auto base = static_cast<std::int32_t>((w % row_words_) * 64);
      for (; bits != 0; bits &= bits - 1)
        out[i++] = {a, base + std::countr_zero(bits)};
    }
    out.resize(i);  // fewer only if a pair was emitted twice
    return;
  }
  std::uint64_t* sorted = keys_.data();
  if (n < 256) {
    std::sort(keys_.begin(), keys_.begin() + static_cast<std::ptrdiff_t>(n));
  } else {
    scratch_.resize(std::max(scratch_.size(), n));
    sorted = radix_sort(keys_.data(), scratch_.data(), n, 0, 2 * shift_, histogram_);
  }
  out.resize(n);
  const std::uint64_t low = (std::uint64_t{1} << shift_) - 1;
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = {static_cast<std::int32_t>(sorted[i] >> shift_),
              static_cast<std::int32_t>(sorted[i] & low)};
  }
}

void sort_unique(std::vector<std::int32_t>& ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
}

}  // namespace grid_detail

using grid_detail::GridProxy;
using grid_detail::is_regular;
using grid_detail::largest_extent;

UniformGridBroadPhase::UniformGridBroadPhase(Real cell_size) {
  settings_.cell_size = cell_size;
}

UniformGridBroadPhase::UniformGridBroadPhase(const UniformGridSettings& settings)
    : settings_(settings) {}

void UniformGridBroadPhase::insert(std::int32_t id, const Aabb& box, bool is_static) {
  store_.insert(id, box, is_static);
  fixed_dirty_ = fixed_dirty_ || is_static;
  built_ = false;
}

void UniformGridBroadPhase::remove(std::int32_t id) {
  fixed_dirty_ = store_.remove(id) || fixed_dirty_;
  built_ = false;
}

void UniformGridBroadPhase::update(std::int32_t id, const Aabb& box) {
  fixed_dirty_ = store_.update(id, box) || fixed_dirty_;
  built_ = false;
}

// The cell range of a proxy's box, written to p.lo and hi, if the box belongs in the grid.
UniformGridBroadPhase::Fit UniformGridBroadPhase::classify(GridProxy& p,
                                                           std::array<std::int32_t, 3>& hi) const {
  if (!is_regular(p.box))
    return Fit::irregular;
  // Size first: a big box that also sticks out of the region is oversized, not "outside", so
  // that big boxes never count towards re-deriving the layout.
  std::array<Real, 3> f0{};
  std::array<Real, 3> f1{};
  Real cells = 1;
  bool inside = true;
  for (int k = 0; k < 3; ++k) {
    f0[k] = (p.box.min[k] - layout_.origin[k]) * layout_.inv;
    f1[k] = (p.box.max[k] - layout_.origin[k]) * layout_.inv;
    cells *= std::floor(f1[k]) - std::floor(f0[k]) + 1;
    inside = inside && f0[k] >= 0 && f1[k] < static_cast<Real>(layout_.dims[k]);
  }
  if (cells > static_cast<Real>(settings_.max_cells_per_box))
    return Fit::oversized;
  if (!inside)
    return Fit::outside;
  // Both are non-negative here, so truncation is floor.
  std::array<std::int32_t, 3> lo{};
  for (int k = 0; k < 3; ++k) {
    lo[k] = static_cast<std::int32_t>(f0[k]);
    hi[k] = static_cast<std::int32_t>(f1[k]);
  }
  p.lo = lo;
  return Fit::grid;
}

// Same function as classify's, clamped to the grid: monotone, so cell(max(a, b)) is
// max(cell(a), cell(b)) here too.
std::int32_t UniformGridBroadPhase::clamped_cell(int axis, Real x) const {
  const Real f = std::floor((x - layout_.origin[axis]) * layout_.inv);
  const Real top = static_cast<Real>(layout_.dims[axis] - 1);
  if (!(f > 0))
    return 0;  // also NaN
  return static_cast<std::int32_t>(std::min(f, top));
}

void UniformGridBroadPhase::derive_layout() {
  // The cell size: given, or factor x the median largest extent of the finite boxes.
  extents_scratch_.clear();
  Real sum = 0;
  Aabb all;
  for (const auto* pool : {&store_.moving, &store_.fixed}) {
    for (const GridProxy& p : *pool) {
      if (!is_regular(p.box))
        continue;
      const Real e = largest_extent(p.box);
      extents_scratch_.push_back(e);
      sum += e;
      all.grow(p.box);
    }
  }
  const auto n = static_cast<std::int64_t>(extents_scratch_.size());
  layout_.mean_extent = n > 0 ? sum / static_cast<Real>(n) : 0;
  Real cell = settings_.cell_size;
  if (!(cell > 0) && n > 0) {
    auto mid = extents_scratch_.begin() + n / 2;
    std::nth_element(extents_scratch_.begin(), mid, extents_scratch_.end());
    cell = settings_.cell_size_factor * *mid;
    if (!(cell > 0)) {
      // Mostly points: as many cells as boxes over their bounds.
      cell = (all.max - all.min).maxCoeff() / std::cbrt(static_cast<Real>(n));
    }
  }
  if (!(cell > 0) || !std::isfinite(cell))
    cell = 1;

  // The region: the bounds of the boxes that will be in the grid, with slack for motion. The
  // memory cap grows the cell when the region would need too many cells.
  const std::int64_t cap =
      std::min(settings_.max_cells, std::max(settings_.min_cells, settings_.cells_per_box_cap * n));
  Vec3 origin = Vec3::Zero();
  std::array<Real, 3> dims{1, 1, 1};
  for (int attempt = 0;; ++attempt) {
    Aabb bounds;
    for (const auto* pool : {&store_.moving, &store_.fixed}) {
      for (const GridProxy& p : *pool) {
        if (!is_regular(p.box))
          continue;
        const Vec3 covered = (p.box.max - p.box.min) / cell + Vec3::Ones();
        if (covered.prod() <= static_cast<Real>(settings_.max_cells_per_box))
          bounds.grow(p.box);
      }
    }
    if (n > 0 && !is_regular(bounds))
      bounds = all;  // no box fits: the grid stays empty, any region will do
    if (!is_regular(bounds))
      bounds = Aabb{Vec3::Zero(), Vec3::Zero()};
    const Vec3 pad = Real(0.125) * (bounds.max - bounds.min) + Vec3::Constant(cell);
    origin = bounds.min - pad;
    Real padded_cells = 1;
    for (int k = 0; k < 3; ++k) {
      dims[k] = std::max(Real(1), std::ceil((bounds.max[k] + pad[k] - origin[k]) / cell));
      const Real brick = dims[k] >= 4 ? 4 : dims[k] >= 2 ? 2 : 1;
      padded_cells *= std::ceil(dims[k] / brick) * brick;
    }
    if (padded_cells <= static_cast<Real>(cap))
      break;
    cell *= std::max(std::cbrt(padded_cells / static_cast<Real>(cap)), Real(1.02));
  }

  layout_.origin = origin;
  layout_.cell = cell;
  layout_.inv = 1 / cell;
  // Cell numbers: bricks of up to 4 cells per axis (fewer on an axis with fewer cells), the
  // brick's bits interleaved in Z-order, bricks in row-major order after them.
  std::array<int, 3> brick_bits{};
  std::array<std::int64_t, 3> bricks{};
  for (int k = 0; k < 3; ++k) {
    layout_.dims[k] = static_cast<std::int32_t>(dims[k]);
    brick_bits[k] = std::min(
        2, static_cast<int>(std::bit_width(static_cast<std::uint32_t>(layout_.dims[k] - 1))));
    bricks[k] = (layout_.dims[k] + (1 << brick_bits[k]) - 1) >> brick_bits[k];
  }
  std::array<std::array<int, 2>, 3> position{};
  int inner_bits = 0;
  for (int round = 0; round < 2; ++round) {
    for (int k = 0; k < 3; ++k) {
      if (round < brick_bits[k])
        position[k][round] = inner_bits++;
    }
  }
  const std::array<std::int64_t, 3> stride{1, bricks[0], bricks[0] * bricks[1]};
  for (int k = 0; k < 3; ++k) {
    std::vector<std::uint32_t>& part = layout_.part[k];
    part.resize(static_cast<std::size_t>(layout_.dims[k]));
    for (std::int32_t i = 0; i < layout_.dims[k]; ++i) {
      std::int64_t code = ((i >> brick_bits[k]) * stride[k]) << inner_bits;
      for (int r = 0; r < brick_bits[k]; ++r)
        code |= static_cast<std::int64_t>((i >> r) & 1) << position[k][r];
      part[i] = static_cast<std::uint32_t>(code);
    }
  }
  layout_.cells = (bricks[0] * bricks[1] * bricks[2]) << inner_bits;
  layout_.valid = true;
  moving_range_.assign(static_cast<std::size_t>(layout_.cells), Range{});
  occupied_.clear();
  fixed_dirty_ = true;
  ++derivations_;
}

// Re-derive when many boxes left the region, when the boxes' mean size moved by more than 2x
// (auto cell size only), or when the bounds of the boxes need less than 1/64 of the region's
// cells (they shrank a lot).
bool UniformGridBroadPhase::layout_is_stale(std::int64_t outside, std::int64_t regular,
                                            Real extent_sum, const Aabb& bounds) const {
  if (!layout_.valid)
    return true;
  if (outside > std::max<std::int64_t>(16, regular / 16))
    return true;
  if (!(settings_.cell_size > 0) && regular > 0) {
    const Real mean = extent_sum / static_cast<Real>(regular);
    if (mean > 2 * layout_.mean_extent || mean < Real(0.5) * layout_.mean_extent)
      return true;
  }
  if (regular > 0) {
    Real needed = 1;
    Real have = 1;
    for (int k = 0; k < 3; ++k) {
      needed *= (bounds.max[k] - bounds.min[k]) * layout_.inv + 1;
      have *= static_cast<Real>(layout_.dims[k]);
    }
    if (have > 64 * needed)
      return true;
  }
  return false;
}

void UniformGridBroadPhase::build_static() {
  const std::vector<GridProxy>& pool = store_.fixed;
  const std::size_t cells = static_cast<std::size_t>(layout_.cells);
  fixed_start_.assign(cells + 1, 0);
  fixed_big_.clear();
  fixed_outside_ = 0;
  fixed_regular_ = 0;
  fixed_extent_sum_ = 0;
  fixed_bounds_ = Aabb{};
  // The hi corners are only needed during the build; moving_hi_ is free at this point.
  moving_hi_.resize(std::max(moving_hi_.size(), pool.size()));
  for (std::size_t s = 0; s < pool.size(); ++s) {
    GridProxy& p = store_.fixed[s];
    const Fit fit = classify(p, moving_hi_[s]);
    if (fit != Fit::irregular) {
      ++fixed_regular_;
      fixed_extent_sum_ += largest_extent(p.box);
      fixed_bounds_.grow(p.box);
    }
    if (fit == Fit::outside)
      ++fixed_outside_;
    if (fit != Fit::grid) {
      fixed_big_.push_back(static_cast<std::uint32_t>(s));
      moving_hi_[s][0] = -1;  // marks "not in the grid" for the passes below
      continue;
    }
    const auto& hi = moving_hi_[s];
    for (std::int32_t z = p.lo[2]; z <= hi[2]; ++z) {
      for (std::int32_t y = p.lo[1]; y <= hi[1]; ++y) {
        for (std::int32_t x = p.lo[0]; x <= hi[0]; ++x)
          ++fixed_start_[code(x, y, z)];
      }
    }
  }
  std::uint32_t run = 0;
  for (std::size_t c = 0; c < cells; ++c) {
    run += fixed_start_[c];
    fixed_start_[c] = run;
  }
  fixed_start_[cells] = run;
  fixed_entries_.resize(run);
  for (std::size_t s = pool.size(); s-- > 0;) {
    const auto& hi = moving_hi_[s];
    if (hi[0] < 0)
      continue;
    const GridProxy& p = pool[s];
    for (std::int32_t z = p.lo[2]; z <= hi[2]; ++z) {
      for (std::int32_t y = p.lo[1]; y <= hi[1]; ++y) {
        for (std::int32_t x = p.lo[0]; x <= hi[0]; ++x)
          fixed_entries_[--fixed_start_[code(x, y, z)]] = entry(s, p.lo, x, y, z);
      }
    }
  }
  fixed_dirty_ = false;
}

void UniformGridBroadPhase::build_moving() {
  if (++steps_since_sort_ >= 16 || !layout_.valid) {
    spatial_order_.apply(store_);
    steps_since_sort_ = 0;
  }
  std::vector<GridProxy>& pool = store_.moving;
  const std::size_t n = pool.size();
  for (int attempt = 0;; ++attempt) {
    if (!layout_.valid)
      derive_layout();
    if (fixed_dirty_)
      build_static();
    moving_hi_.resize(n);
    moving_in_grid_.resize(n);
    moving_big_.clear();
    std::int64_t outside = 0;
    std::int64_t regular = 0;
    Real extent_sum = 0;
    Aabb bounds = fixed_bounds_;
    for (std::size_t s = 0; s < n; ++s) {
      const Fit fit = classify(pool[s], moving_hi_[s]);
      moving_in_grid_[s] = fit == Fit::grid;
      if (fit != Fit::grid)
        moving_big_.push_back(static_cast<std::uint32_t>(s));
      if (fit == Fit::outside)
        ++outside;
      if (fit != Fit::irregular) {
        ++regular;
        extent_sum += largest_extent(pool[s].box);
        bounds.grow(pool[s].box);
      }
    }
    moving_outside_ = outside;
    if (attempt == 0 && layout_is_stale(outside + fixed_outside_, regular + fixed_regular_,
                                        extent_sum + fixed_extent_sum_, bounds)) {
      layout_.valid = false;
      continue;
    }
    break;
  }

  // Counting sort over the cells in use only: zero last step's cells, count (listing each cell
  // as it is first met), give each listed cell its offset, scatter.
  for (const std::uint32_t c : occupied_)
    moving_range_[c] = Range{};
  occupied_.clear();
  Range* range = moving_range_.data();
  for (std::size_t s = 0; s < n; ++s) {
    if (!moving_in_grid_[s])
      continue;
    const GridProxy& p = pool[s];
    const auto& hi = moving_hi_[s];
    for (std::int32_t z = p.lo[2]; z <= hi[2]; ++z) {
      for (std::int32_t y = p.lo[1]; y <= hi[1]; ++y) {
        for (std::int32_t x = p.lo[0]; x <= hi[0]; ++x) {
          const std::uint32_t c = code(x, y, z);
          if (range[c].end++ == 0)
            occupied_.push_back(c);
        }
      }
    }
  }
  std::uint32_t run = 0;
  for (const std::uint32_t c : occupied_) {
    const std::uint32_t count = range[c].end;
    range[c] = {run, run};
    run += count;
  }
  moving_entries_.resize(run);
  for (std::size_t s = 0; s < n; ++s) {
    if (!moving_in_grid_[s])
      continue;
    const GridProxy& p = pool[s];
    const auto& hi = moving_hi_[s];
    for (std::int32_t z = p.lo[2]; z <= hi[2]; ++z) {
      for (std::int32_t y = p.lo[1]; y <= hi[1]; ++y) {
        for (std::int32_t x = p.lo[0]; x <= hi[0]; ++x)
          moving_entries_[range[code(x, y, z)].end++] = entry(s, p.lo, x, y, z);
      }
    }
  }
}

// Every pair of grid proxies sharing a cell, reported in the cell of their intersection's lower
// corner only: on each axis one of the two boxes starts in this cell, so the OR of the two
// entries' masks is 7. Pairs failing that are skipped before their boxes are loaded.
void UniformGridBroadPhase::pairs_in_cells() {
  const GridProxy* moving = store_.moving.data();
  const GridProxy* fixed = store_.fixed.data();
  const std::uint32_t* entries = moving_entries_.data();
  const std::uint32_t* fixed_entries = fixed_entries_.data();
  const bool any_fixed = !fixed_entries_.empty();
  for (const std::uint32_t c : occupied_) {
    const std::uint32_t begin = moving_range_[c].begin;
    const std::uint32_t end = moving_range_[c].end;
    const std::uint32_t fixed_begin = any_fixed ? fixed_start_[c] : 0;
    const std::uint32_t fixed_end = any_fixed ? fixed_start_[c + 1] : 0;
    grid_detail::pairs_in_cell(entries, begin, end, fixed_entries, fixed_begin, fixed_end, moving,
                               fixed, sorter_);
  }
}

void UniformGridBroadPhase::pairs_with_oversized() {
  grid_detail::pairs_with_oversized(
      store_.moving, store_.fixed, moving_big_, fixed_big_,
      [this](std::size_t s) { return moving_in_grid_[s] != 0; }, sorter_);
}

void UniformGridBroadPhase::find_pairs(std::vector<ProxyPair>& out) {
  sorter_.begin(store_.id_bits());
  build_moving();
  pairs_in_cells();
  pairs_with_oversized();
  sorter_.finish(out);
  built_ = true;
}

void UniformGridBroadPhase::query(const Aabb& box, std::vector<std::int32_t>& out) const {
  if (!built_ || !is_regular(box)) {
    store_.overlapping(box, out);
    return;
  }
  out.clear();
  const std::vector<GridProxy>& moving = store_.moving;
  const std::vector<GridProxy>& fixed = store_.fixed;
  std::array<std::int32_t, 3> lo{};
  std::array<std::int32_t, 3> hi{};
  std::int64_t cells = 1;
  bool misses_region = false;
  for (int k = 0; k < 3; ++k) {
    const Real upper = layout_.origin[k] + layout_.cell * static_cast<Real>(layout_.dims[k]);
    misses_region = misses_region || box.max[k] < layout_.origin[k] || box.min[k] > upper;
    lo[k] = clamped_cell(k, box.min[k]);
    hi[k] = clamped_cell(k, box.max[k]);
    cells *= hi[k] - lo[k] + 1;
  }
  const auto in_grid = static_cast<std::int64_t>(moving.size() - moving_big_.size() + fixed.size() -
                                                 fixed_big_.size());
  if (misses_region) {
    // No grid proxy lies outside the region.
  } else if (cells > in_grid) {
    for (std::size_t s = 0; s < moving.size(); ++s) {
      if (moving_in_grid_[s] && moving[s].box.overlaps(box))
        out.push_back(moving[s].id);
    }
    for (const GridProxy& p : fixed) {
      if (p.box.overlaps(box))
        out.push_back(p.id);  // the oversized static ones too; skipped below
    }
  } else {
    // Each proxy is reported in the cell of max(its min corner, the box's min corner) only.
    for (std::int32_t z = lo[2]; z <= hi[2]; ++z) {
      for (std::int32_t y = lo[1]; y <= hi[1]; ++y) {
        for (std::int32_t x = lo[0]; x <= hi[0]; ++x) {
          const std::uint32_t c = code(x, y, z);
          auto visit = [&](const GridProxy& p) {
            if (p.box.overlaps(box) && code(std::max(p.lo[0], lo[0]), std::max(p.lo[1], lo[1]),
                                            std::max(p.lo[2], lo[2])) == c)
              out.push_back(p.id);
          };
          for (std::uint32_t i = moving_range_[c].begin; i < moving_range_[c].end; ++i)
            visit(moving[moving_entries_[i] >> kHomeBits]);
          if (!fixed_entries_.empty()) {
            for (std::uint32_t i = fixed_start_[c]; i < fixed_start_[c + 1]; ++i)
              visit(fixed[fixed_entries_[i] >> kHomeBits]);
          }
        }
      }
    }
  }
  const bool fixed_scanned = !misses_region && cells > in_grid;
  for (const std::uint32_t s : moving_big_) {
    if (moving[s].box.overlaps(box))
      out.push_back(moving[s].id);
  }
  if (!fixed_scanned) {
    for (const std::uint32_t s : fixed_big_) {
      if (fixed[s].box.overlaps(box))
        out.push_back(fixed[s].id);
    }
  }
  std::sort(out.begin(), out.end());
}

void UniformGridBroadPhase::ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                                     std::vector<std::int32_t>& out) const {
  out.clear();
  auto test = [&](const GridProxy& p) {
    if (segment_touches_aabb(origin, direction, max_t, p.box))
      out.push_back(p.id);
  };
  const bool regular_ray =
      origin.allFinite() && direction.allFinite() && std::isfinite(max_t) && !direction.isZero(0);
  if (!built_ || !regular_ray) {
    store_.touched_by_segment(origin, direction, max_t, out);
    return;
  }
  const std::vector<GridProxy>& moving = store_.moving;
  const std::vector<GridProxy>& fixed = store_.fixed;
  // Clip the segment to the region (inflated by the rounding allowance), then walk its cells.
  const Real eps = grid_detail::march_eps(origin, direction, max_t, layout_.cell);
  Real t0 = 0;
  Real t1 = max_t;
  for (int k = 0; k < 3 && t0 <= t1; ++k) {
    const Real lower = layout_.origin[k] - eps;
    const Real upper = layout_.origin[k] + layout_.cell * static_cast<Real>(layout_.dims[k]) + eps;
    if (direction[k] == 0) {
      if (origin[k] < lower || origin[k] > upper)
        t1 = -1;
      continue;
    }
    Real ta = (lower - origin[k]) / direction[k];
    Real tb = (upper - origin[k]) / direction[k];
    if (ta > tb)
      std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  const bool any_in_grid = moving_big_.size() < moving.size() || fixed_big_.size() < fixed.size();
  if (t0 <= t1 && any_in_grid) {
    grid_detail::march_segment(
        origin, direction, t0, t1, eps, [this](int axis, Real x) { return clamped_cell(axis, x); },
        [this](int axis, std::int32_t i) {
          return layout_.origin[axis] + layout_.cell * static_cast<Real>(i);
        },
        [&](std::int32_t x, std::int32_t y, std::int32_t z) {
          const std::uint32_t c = code(x, y, z);
          for (std::uint32_t i = moving_range_[c].begin; i < moving_range_[c].end; ++i)
            test(moving[moving_entries_[i] >> kHomeBits]);
          if (!fixed_entries_.empty()) {
            for (std::uint32_t i = fixed_start_[c]; i < fixed_start_[c + 1]; ++i)
              test(fixed[fixed_entries_[i] >> kHomeBits]);
          }
        });
  }
  for (const std::uint32_t s : moving_big_)
    test(moving[s]);
  for (const std::uint32_t s : fixed_big_)
    test(fixed[s]);
  grid_detail::sort_unique(out);
}

}  // namespace tumble
