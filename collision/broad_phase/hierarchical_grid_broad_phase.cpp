// Hierarchical hash grid broad phase; the algorithm, its sources and the rules that make each
// pair found once are described in the header.
#include "collision/broad_phase/hierarchical_grid_broad_phase.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace tumble {

using grid_detail::GridProxy;
using grid_detail::is_regular;
using grid_detail::largest_extent;

namespace {

using grid_detail::kHomeBits;
using grid_detail::kHomeMask;

// Cell coordinates are clamped to +-2^30 so that they and their neighbours fit an int32 (their
// differences need 64 bits or a Real). The clamp is monotone, so the lower-corner rule still
// holds: the two outermost cells of each axis just extend to infinity.
constexpr std::int32_t kCellLimit = std::int32_t{1} << 30;

// Where a cell goes in its level's table of 2^bits slots: Teschner et al. (2003),
// x p1 xor y p2 xor z p3 with three large primes. A power-of-two table keeps only low bits,
// which depend only on the low bits of the coordinates; a Fibonacci multiply (Knuth, TAOCP 3,
// 6.4) moves every bit into the top bits that index the table. (Hashing 4 x 4 x 4 bricks to
// blocks of 64 slots, for locality, was tried and was slower: dense bricks make long linear-
// probing runs, which misses for empty cells must walk.)
std::uint32_t cell_slot(const std::array<std::int32_t, 3>& at, int bits) {
  const std::uint32_t h = (static_cast<std::uint32_t>(at[0]) * 73856093u) ^
                          (static_cast<std::uint32_t>(at[1]) * 19349663u) ^
                          (static_cast<std::uint32_t>(at[2]) * 83492791u);
  return (h * 0x9E3779B1u) >> (32 - bits);
}

bool same_cell(const std::array<std::int32_t, 3>& a, const std::array<std::int32_t, 3>& b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

// The bits telling on which axes `at` is the lowest cell of the range starting at `lo`.
std::uint32_t home_bits(const std::array<std::int32_t, 3>& lo, std::int32_t x, std::int32_t y,
                        std::int32_t z) {
  return static_cast<std::uint32_t>(x == lo[0]) | static_cast<std::uint32_t>(y == lo[1]) << 1 |
         static_cast<std::uint32_t>(z == lo[2]) << 2;
}

}  // namespace

// ---- LevelGrids ------------------------------------------------------------------------------

void HierarchicalGridBroadPhase::LevelGrids::build(const std::vector<GridProxy>& pool,
                                                   const std::vector<std::int8_t>& level,
                                                   const std::vector<Cells3>& hi) {
  std::array<std::uint32_t, kMaxLevels> inserts{};
  level_begin_.fill(0);
  for (std::size_t s = 0; s < pool.size(); ++s) {
    const int l = level[s];
    if (l < 0)
      continue;
    ++level_begin_[l + 1];
    const Cells3& lo = pool[s].lo;
    inserts[l] += static_cast<std::uint32_t>((hi[s][0] - lo[0] + 1) * (hi[s][1] - lo[1] + 1) *
                                             (hi[s][2] - lo[2] + 1));
  }
  // Proxies grouped by level (a counting sort), and one table per non-empty level, sized to a
  // power of two at least twice its cell insertions (load factor <= 1/2).
  nonempty_.clear();
  std::uint32_t table_size = 0;
  for (int l = 0; l < kMaxLevels; ++l) {
    const std::uint32_t count = level_begin_[l + 1];
    level_begin_[l + 1] += level_begin_[l];
    tables_[l] = Table{};
    if (count == 0)
      continue;
    nonempty_.push_back(l);
    const std::uint32_t size = std::bit_ceil(std::max(16u, 2 * inserts[l]));
    tables_[l] = {table_size, size - 1, std::countr_zero(size)};
    table_size += size;
  }
  by_level_.resize(level_begin_[kMaxLevels]);
  std::array<std::uint32_t, kMaxLevels + 1> cursor = level_begin_;
  for (std::size_t s = 0; s < pool.size(); ++s) {
    if (level[s] >= 0)
      by_level_[cursor[level[s]]++] = static_cast<std::uint32_t>(s);
  }
  slots_.assign(table_size, Slot{{0, 0, 0}, kNoCell});

  // Counting sort of the (proxy, cell) entries: count per cell (cells numbered as first met,
  // level by level), prefix, scatter.
  cells_.clear();
  entry_cell_.clear();
  for (int l = 0; l < kMaxLevels; ++l) {
    cell_begin_[l] = static_cast<std::uint32_t>(cells_.size());
    for (std::uint32_t k = level_begin_[l]; k < level_begin_[l + 1]; ++k) {
      const std::uint32_t s = by_level_[k];
      const Cells3& lo = pool[s].lo;
      for (std::int32_t z = lo[2]; z <= hi[s][2]; ++z) {
        for (std::int32_t y = lo[1]; y <= hi[s][1]; ++y) {
          for (std::int32_t x = lo[0]; x <= hi[s][0]; ++x) {
            const std::uint32_t c = find_or_add(l, {x, y, z});
            ++cells_[c].end;
            entry_cell_.push_back(c);
          }
        }
      }
    }
  }
  cell_begin_[kMaxLevels] = static_cast<std::uint32_t>(cells_.size());
  std::uint32_t run = 0;
  for (Cell& c : cells_) {
    const std::uint32_t count = c.end;
    c.begin = run;
    c.end = run;
    run += count;
  }
  entries_.resize(run);
  std::size_t e = 0;
  for (std::uint32_t s : by_level_) {
    const Cells3& lo = pool[s].lo;
    for (std::int32_t z = lo[2]; z <= hi[s][2]; ++z) {
      for (std::int32_t y = lo[1]; y <= hi[s][1]; ++y) {
        for (std::int32_t x = lo[0]; x <= hi[s][0]; ++x)
          entries_[cells_[entry_cell_[e++]].end++] = s << kHomeBits | home_bits(lo, x, y, z);
      }
    }
  }
}

std::uint32_t HierarchicalGridBroadPhase::LevelGrids::find_or_add(int level, const Cells3& at) {
  const Table& t = tables_[level];
  std::uint32_t i = cell_slot(at, t.bits);
  for (;;) {
    Slot& slot = slots_[t.offset + i];
    if (slot.cell == kNoCell) {
      slot.at = at;
      slot.cell = static_cast<std::uint32_t>(cells_.size());
      cells_.push_back({at, 0, 0});
      return slot.cell;
    }
    if (same_cell(slot.at, at))
      return slot.cell;
    i = (i + 1) & t.mask;
  }
}

std::uint32_t HierarchicalGridBroadPhase::LevelGrids::find(int level, const Cells3& at) const {
  const Table& t = tables_[level];
  if (t.bits == 0)
    return kNoCell;  // empty level: no table
  std::uint32_t i = cell_slot(at, t.bits);
  for (;;) {
    const Slot& slot = slots_[t.offset + i];
    if (slot.cell == kNoCell || same_cell(slot.at, at))
      return slot.cell;
    i = (i + 1) & t.mask;
  }
}

// ---- HierarchicalGridBroadPhase --------------------------------------------------------------

HierarchicalGridBroadPhase::HierarchicalGridBroadPhase(Real base_cell) : fixed_s0_(base_cell) {
  if (fixed_s0_ > 0) {
    s0_ = fixed_s0_;
    inv_s0_ = 1 / fixed_s0_;
    s0_valid_ = true;
  }
}

void HierarchicalGridBroadPhase::insert(std::int32_t id, const Aabb& box, bool is_static) {
  store_.insert(id, box, is_static);
  fixed_dirty_ = fixed_dirty_ || is_static;
  built_ = false;
}

void HierarchicalGridBroadPhase::remove(std::int32_t id) {
  fixed_dirty_ = store_.remove(id) || fixed_dirty_;
  built_ = false;
}

void HierarchicalGridBroadPhase::update(std::int32_t id, const Aabb& box) {
  fixed_dirty_ = store_.update(id, box) || fixed_dirty_;
  built_ = false;
}

int HierarchicalGridBroadPhase::level_for_size(Real r, Real s0) {
  if (!(r > s0))
    return 0;
  const Real q = r / s0;
  if (!std::isfinite(q))
    return std::numeric_limits<int>::max();  // r / s0 overflows: far past the last level
  // q = m 2^e with m in [0.5, 1): ceil(log2 q) is e, or e - 1 when m is exactly 0.5. Rounding the
  // quotient cannot cross a power of two: for r > s0 2^k the nearest double above s0 2^k gives
  // q = 2^k (1 + 2^-52 / mantissa(s0)), more than half an ulp above 2^k, and for r <= s0 2^k
  // the rounded q is <= 2^k; so this is the exact rule.
  int e = 0;
  const Real m = std::frexp(q, &e);
  return m == Real(0.5) ? e - 1 : e;
}

int HierarchicalGridBroadPhase::level_of(std::int32_t id) const {
  bool is_static = false;
  const std::int64_t slot = store_.slot_of(id, is_static);
  if (slot < 0)
    return -1;
  const std::vector<std::int8_t>& levels = is_static ? fixed_level_ : moving_level_;
  return static_cast<std::size_t>(slot) < levels.size() ? levels[slot] : -1;
}

std::int32_t HierarchicalGridBroadPhase::cell_of(Real x, Real inv) {
  const Real f = std::floor(x * inv);
  if (!(f > -kCellLimit))
    return -kCellLimit;  // also NaN
  return static_cast<std::int32_t>(std::min(f, Real(kCellLimit)));
}

int HierarchicalGridBroadPhase::classify(GridProxy& p, Cells3& hi) const {
  if (!is_regular(p.box))
    return -1;
  for (int l = level_for_size(largest_extent(p.box), s0_); l < kMaxLevels; ++l) {
    const Real inv = level_inv(l);
    Cells3 lo{};
    bool fits = true;
    for (int k = 0; k < 3; ++k) {
      lo[k] = cell_of(p.box.min[k], inv);
      hi[k] = cell_of(p.box.max[k], inv);
      fits = fits && std::int64_t{hi[k]} - lo[k] <= 1;
    }
    if (fits) {
      p.lo = lo;
      return l;
    }
    // One ulp over s_l: the level above has room.
  }
  return -1;
}

// s_0 = the smallest power of two >= the smallest positive r (1 if every box is a point).
void HierarchicalGridBroadPhase::derive_base(Real smallest) {
  int e = 0;
  if (smallest > 0) {
    const Real m = std::frexp(smallest, &e);
    if (m == Real(0.5))
      --e;
    e = std::clamp(e, -400, 400);
  }
  s0_ = std::ldexp(Real(1), e);
  inv_s0_ = std::ldexp(Real(1), -e);
  s0_valid_ = true;
  fixed_dirty_ = true;
  ++derivations_;
}

void HierarchicalGridBroadPhase::build_static() {
  const std::size_t n = store_.fixed.size();
  fixed_level_.resize(n);
  fixed_hi_.resize(n);
  fixed_big_.clear();
  fixed_smallest_ = 0;
  for (std::size_t s = 0; s < n; ++s) {
    GridProxy& p = store_.fixed[s];
    const int l = classify(p, fixed_hi_[s]);
    fixed_level_[s] = static_cast<std::int8_t>(l);
    if (l < 0)
      fixed_big_.push_back(static_cast<std::uint32_t>(s));
    if (is_regular(p.box)) {
      const Real r = largest_extent(p.box);
      if (r > 0 && (fixed_smallest_ == 0 || r < fixed_smallest_))
        fixed_smallest_ = r;
    }
  }
  fixed_grid_.build(store_.fixed, fixed_level_, fixed_hi_);
  fixed_dirty_ = false;
}

void HierarchicalGridBroadPhase::classify_moving(Real& smallest) {
  const std::size_t n = store_.moving.size();
  moving_level_.resize(n);
  moving_hi_.resize(n);
  moving_big_.clear();
  smallest = 0;
  for (std::size_t s = 0; s < n; ++s) {
    GridProxy& p = store_.moving[s];
    const int l = classify(p, moving_hi_[s]);
    moving_level_[s] = static_cast<std::int8_t>(l);
    if (l < 0) {
      moving_big_.push_back(static_cast<std::uint32_t>(s));
      if (!is_regular(p.box))
        continue;
    }
    const Real r = largest_extent(p.box);
    if (r > 0 && (smallest == 0 || r < smallest))
      smallest = r;
  }
}

// Pairs on one level: dynamic-dynamic and dynamic-static in the cells they share, reported in
// the cell of the intersection's lower corner only (the OR of the two entries' bits is 7).
void HierarchicalGridBroadPhase::pairs_same_level() {
  const GridProxy* moving = store_.moving.data();
  const GridProxy* fixed = store_.fixed.data();
  const std::uint32_t* entries = moving_grid_.entries();
  const std::uint32_t* fixed_entries = fixed_grid_.entries();
  for (const int l : moving_grid_.levels()) {
    const bool fixed_here = fixed_grid_.objects(l) > 0;
    for (std::uint32_t c = moving_grid_.cells_begin(l); c < moving_grid_.cells_end(l); ++c) {
      const LevelGrids::Cell& cell = moving_grid_.cell(c);
      std::uint32_t fixed_begin = 0;
      std::uint32_t fixed_end = 0;
      if (fixed_here) {
        const std::uint32_t fc = fixed_grid_.find(l, cell.at);
        if (fc != LevelGrids::kNoCell) {
          fixed_begin = fixed_grid_.cell(fc).begin;
          fixed_end = fixed_grid_.cell(fc).end;
        }
      }
      grid_detail::pairs_in_cell(entries, cell.begin, cell.end, fixed_entries, fixed_begin,
                                 fixed_end, moving, fixed, sorter_);
    }
  }
}

// Pairs across levels, found from the dynamic box only: against coarser dynamic levels (the
// finer box looks up), and against every other static level (coarser: it looks up; finer: it
// looks down, since a static box never looks).
void HierarchicalGridBroadPhase::pairs_across_levels() {
  const std::vector<GridProxy>& moving = store_.moving;
  const std::vector<GridProxy>& fixed = store_.fixed;
  // The last cell looked up per level of each grid: the proxies are sorted in space, so the next
  // box mostly asks for the same coarse cell again, and is answered without touching the table.
  struct Memo {
    Cells3 at{};
    std::uint32_t cell = LevelGrids::kNoCell;
    bool valid = false;
  };
  std::array<std::array<Memo, kMaxLevels>, 2> memo{};
  // The boxes of `grid` (proxies `pool`) on `level` that a's box overlaps, each once: a looks
  // in the cells it overlaps there, and reports in the cell of the intersection's lower corner.
  auto look = [&](const GridProxy& a, const LevelGrids& grid, const std::vector<GridProxy>& pool,
                  int level, bool scan_if_cheaper) {
    Memo& last = memo[&grid == &fixed_grid_][level];
    const Real inv = level_inv(level);
    Cells3 lo{};
    Cells3 hi{};
    Real cells = 1;
    for (int k = 0; k < 3; ++k) {
      lo[k] = cell_of(a.box.min[k], inv);
      hi[k] = cell_of(a.box.max[k], inv);
      cells *= static_cast<Real>(hi[k]) - static_cast<Real>(lo[k]) + 1;
    }
    if (scan_if_cheaper && cells > static_cast<Real>(grid.objects(level))) {
      const std::uint32_t* slots = grid.level_slots(level);
      for (std::uint32_t k = 0; k < grid.objects(level); ++k) {
        const GridProxy& b = pool[slots[k]];
        if (a.box.overlaps(b.box))
          sorter_.emit(a.id, b.id);
      }
      return;
    }
    const std::uint32_t* entries = grid.entries();
    for (std::int32_t z = lo[2]; z <= hi[2]; ++z) {
      for (std::int32_t y = lo[1]; y <= hi[1]; ++y) {
        for (std::int32_t x = lo[0]; x <= hi[0]; ++x) {
          const Cells3 at{x, y, z};
          if (!last.valid || !same_cell(last.at, at))
            last = {at, grid.find(level, at), true};
          const std::uint32_t c = last.cell;
          if (c == LevelGrids::kNoCell)
            continue;
          const std::uint32_t need = ~home_bits(lo, x, y, z) & kHomeMask;
          const LevelGrids::Cell& cell = grid.cell(c);
          for (std::uint32_t j = cell.begin; j < cell.end; ++j) {
            const std::uint32_t eb = entries[j];
            if ((eb & need) != need)
              continue;
            const GridProxy& b = pool[eb >> kHomeBits];
            if (a.box.overlaps(b.box))
              sorter_.emit(a.id, b.id);
          }
        }
      }
    }
  };
  const std::vector<int>& moving_levels = moving_grid_.levels();
  const std::vector<int>& fixed_levels = fixed_grid_.levels();
  for (std::size_t li = 0; li < moving_levels.size(); ++li) {
    const int la = moving_levels[li];
    const std::uint32_t* slots = moving_grid_.level_slots(la);
    for (std::uint32_t k = 0; k < moving_grid_.objects(la); ++k) {
      const GridProxy& a = moving[slots[k]];
      for (std::size_t lj = li + 1; lj < moving_levels.size(); ++lj)
        look(a, moving_grid_, moving, moving_levels[lj], false);
      for (const int ls : fixed_levels) {
        if (ls != la)
          look(a, fixed_grid_, fixed, ls, ls < la);
      }
    }
  }
}

void HierarchicalGridBroadPhase::pairs_with_oversized() {
  grid_detail::pairs_with_oversized(
      store_.moving, store_.fixed, moving_big_, fixed_big_,
      [this](std::size_t s) { return moving_level_[s] >= 0; }, sorter_);
}

void HierarchicalGridBroadPhase::find_pairs(std::vector<ProxyPair>& out) {
  sorter_.begin(store_.id_bits());
  // Neighbours in space next to each other in memory: consecutive proxies then touch the same
  // cells, so the hash table stays in cache while the grids are built.
  if (++steps_since_sort_ >= 16 || !s0_valid_) {
    spatial_order_.apply(store_);
    steps_since_sort_ = 0;
  }
  for (int attempt = 0;; ++attempt) {
    if (!s0_valid_) {
      Real smallest = 0;
      for (const auto* pool : {&store_.moving, &store_.fixed}) {
        for (const GridProxy& p : *pool) {
          const Real r = is_regular(p.box) ? largest_extent(p.box) : 0;
          if (r > 0 && (smallest == 0 || r < smallest))
            smallest = r;
        }
      }
      derive_base(smallest);
    }
    if (fixed_dirty_)
      build_static();
    Real smallest = 0;
    classify_moving(smallest);
    if (attempt == 0 && !(fixed_s0_ > 0)) {
      if (fixed_smallest_ > 0 && (smallest == 0 || fixed_smallest_ < smallest))
        smallest = fixed_smallest_;
      if (smallest > 0 && (smallest < s0_ / 4 || smallest > s0_ * 65536)) {
        s0_valid_ = false;
        continue;
      }
    }
    break;
  }
  moving_grid_.build(store_.moving, moving_level_, moving_hi_);
  pairs_same_level();
  pairs_across_levels();
  pairs_with_oversized();
  sorter_.finish(out);
  built_ = true;
}

void HierarchicalGridBroadPhase::query(const Aabb& box, std::vector<std::int32_t>& out) const {
  if (!built_ || !is_regular(box)) {
    store_.overlapping(box, out);
    return;
  }
  out.clear();
  auto search = [&](const LevelGrids& grid, const std::vector<GridProxy>& pool) {
    for (const int l : grid.levels()) {
      const Real inv = level_inv(l);
      Cells3 lo{};
      Cells3 hi{};
      Real cells = 1;
      for (int k = 0; k < 3; ++k) {
        lo[k] = cell_of(box.min[k], inv);
        hi[k] = cell_of(box.max[k], inv);
        cells *= static_cast<Real>(hi[k]) - static_cast<Real>(lo[k]) + 1;
      }
      if (cells > static_cast<Real>(grid.objects(l))) {
        const std::uint32_t* slots = grid.level_slots(l);
        for (std::uint32_t k = 0; k < grid.objects(l); ++k) {
          if (pool[slots[k]].box.overlaps(box))
            out.push_back(pool[slots[k]].id);
        }
        continue;
      }
      for (std::int32_t z = lo[2]; z <= hi[2]; ++z) {
        for (std::int32_t y = lo[1]; y <= hi[1]; ++y) {
          for (std::int32_t x = lo[0]; x <= hi[0]; ++x) {
            const std::uint32_t c = grid.find(l, {x, y, z});
            if (c == LevelGrids::kNoCell)
              continue;
            const std::uint32_t need = ~home_bits(lo, x, y, z) & kHomeMask;
            for (std::uint32_t j = grid.cell(c).begin; j < grid.cell(c).end; ++j) {
              const std::uint32_t e = grid.entries()[j];
              if ((e & need) == need && pool[e >> kHomeBits].box.overlaps(box))
                out.push_back(pool[e >> kHomeBits].id);
            }
          }
        }
      }
    }
  };
  search(moving_grid_, store_.moving);
  search(fixed_grid_, store_.fixed);
  for (const std::uint32_t s : moving_big_) {
    if (store_.moving[s].box.overlaps(box))
      out.push_back(store_.moving[s].id);
  }
  for (const std::uint32_t s : fixed_big_) {
    if (store_.fixed[s].box.overlaps(box))
      out.push_back(store_.fixed[s].id);
  }
  std::sort(out.begin(), out.end());
}

void HierarchicalGridBroadPhase::ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
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
  int a = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(direction[k]) > std::abs(direction[a]))
      a = k;
  }
  auto search = [&](const LevelGrids& grid, const std::vector<GridProxy>& pool) {
    if (max_t < 0)
      return;  // the slab test rejects a non-zero direction with max_t < 0
    for (const int l : grid.levels()) {
      const Real inv = level_inv(l);
      const Real cell = level_cell(l);
      // Cells the march may visit: a slab of the main axis covers at most about 3 x 3 cells,
      // except the two clamped outermost ones, which are infinite and may cover n_b x n_c. When
      // that is more than the boxes on this level, testing them all is cheaper.
      std::array<Real, 3> n{};
      for (int k = 0; k < 3; ++k) {
        n[k] = std::abs(static_cast<Real>(cell_of(origin[k] + max_t * direction[k], inv)) -
                        static_cast<Real>(cell_of(origin[k], inv))) +
               1;
      }
      const int b = (a + 1) % 3;
      const int c = (a + 2) % 3;
      const Real visits = std::min(n[a] * n[b] * n[c], 9 * n[a] + 2 * n[b] * n[c]);
      if (visits > static_cast<Real>(grid.objects(l))) {
        const std::uint32_t* slots = grid.level_slots(l);
        for (std::uint32_t k = 0; k < grid.objects(l); ++k)
          test(pool[slots[k]]);
        continue;
      }
      grid_detail::march_segment(
          origin, direction, 0, max_t, grid_detail::march_eps(origin, direction, max_t, cell),
          [inv](int, Real x) { return cell_of(x, inv); },
          [cell](int, std::int32_t i) {
            // The clamped outermost cells reach to infinity.
            if (i <= -kCellLimit)
              return -std::numeric_limits<Real>::infinity();
            if (i > kCellLimit)
              return std::numeric_limits<Real>::infinity();
            return cell * static_cast<Real>(i);
          },
          [&](std::int32_t x, std::int32_t y, std::int32_t z) {
            const std::uint32_t c = grid.find(l, {x, y, z});
            if (c == LevelGrids::kNoCell)
              return;
            for (std::uint32_t j = grid.cell(c).begin; j < grid.cell(c).end; ++j)
              test(pool[grid.entries()[j] >> kHomeBits]);
          });
    }
  };
  search(moving_grid_, store_.moving);
  search(fixed_grid_, store_.fixed);
  for (const std::uint32_t s : moving_big_)
    test(store_.moving[s]);
  for (const std::uint32_t s : fixed_big_)
    test(store_.fixed[s]);
  grid_detail::sort_unique(out);
}

}  // namespace tumble
