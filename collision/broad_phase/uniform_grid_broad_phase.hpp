// Uniform grid broad phase: a dense grid over the bounds of the finite boxes,
// rebuilt every find_pairs by a counting sort into two flat arrays (cell start offsets and the
// proxy indices of each cell, no per-cell containers), with the cells numbered along a Z-order
// (Morton) curve so that neighbouring cells sit near each other in memory. The layout is the
// GPU one of Green, "Particle Simulation using CUDA" (NVIDIA, 2010); the grid itself is
// Ericson, Real-Time Collision Detection (2005), 7.1 (uniform grids), run on the CPU.
//
// - Cells are numbered in 4 x 4 x 4 bricks, Z-order inside a brick and bricks in row-major order:
//   the locality of a Morton curve with at most 3 cells of padding per axis (a pure Morton code
//   pads each axis to a power of two, up to 8x the cells).
// - Per step only the cells in use are touched: the counting pass lists the cells it finds
//   non-empty, offsets are assigned over that list, and the list zeroes them again next step, so
//   a step costs O(entries), not O(cells). The static grid, rebuilt rarely, is a plain prefix.
// - Every 16 steps the dynamic proxies are sorted along a Morton curve of their centres, so that
//   the proxies of neighbouring cells are neighbours in memory (what GPU particle codes do every
//   step).
//
// - A box goes into every cell it overlaps. A pair is tested in every cell both share, but
//   reported only in the one cell that holds the lower corner of the two boxes' intersection,
//   max(a.min, b.min): that cell is (max(lo_a.x, lo_b.x), ...) in integer cell coordinates, since
//   the cell function is monotone; equivalently, on every axis one of the two boxes has its
//   lowest cell there. Each cell entry carries those three "lowest here" bits (after the home
//   cells of Le Grand, "Broad-Phase Collision Detection with CUDA", GPU Gems 3, ch. 32, 2007),
//   so the check is one OR of two entries, made before any box is loaded (Ericson 7.1 discusses
//   the alternatives: time stamps, pair hashes). An entry is slot << 3 | bits: at most 2^29
//   proxies.
// - Infinite, inverted or NaN boxes, boxes that would cover more than `max_cells_per_box`
//   cells and boxes that lie outside the grid's region go to an "oversized" list whose members
//   are tested against every proxy; so planes cost O(n) and never touch the grid.
// - Static proxies live in their own arrays and their own grid, rebuilt only when a static
//   proxy changes: per step they cost only the lookups of the dynamic cells they share.
// - The region (origin, cell counts) covers the grid-sized boxes with 1/8 of slack plus a cell
//   on each side. It is re-derived, with the cell size, when more than max(16, n / 16) boxes
//   have left it, when the boxes' mean largest extent moved by more than 2x (derived cell size
//   only), or when the boxes' bounds need fewer than 1/64 of its cells; until then a box that
//   leaves it is simply tested as oversized, so results never depend on when it is re-derived.
//
// The cell size, its default and the memory cap are described with `UniformGridSettings`.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "collision/broad_phase/broad_phase.hpp"

namespace tumble {

// Tunables of the uniform grid. Lengths in metres.
struct UniformGridSettings {
  // Edge of a cell. 0 derives it: `cell_size_factor` times the median, over the finite boxes, of
  // each box's largest extent (max over axes of max - min). The median ignores a few huge or tiny
  // boxes that a mean would follow; the factor trades cells per box (small cells: a box lands in
  // up to 8 and more cells) against boxes per cell (large cells: more pair tests per cell).
  // Re-derived when the mean of those extents moves by more than 2x from the value it had at
  // the last derivation. Too small: every box spans many cells and ends in the oversized list
  // (O(n^2)); too large: everything shares a cell (O(n^2) too). Factor 2 measured fastest on
  // 10k-100k moving boxes of similar size: 1 put each box in about 8 cells and ran 1.1-1.4x
  // slower, 3 was within 5% of 2.
  Real cell_size = 0;
  Real cell_size_factor = 2;
  // A box covering more cells than this is kept in the oversized list instead (tested against
  // every proxy). Too small: big boxes cost O(n) each; too large: one box fills many cells.
  std::int32_t max_cells_per_box = 64;
  // Memory cap. The grid never has more than max(min_cells, cells_per_box_cap * boxes) cells
  // (with the brick padding), and never more than max_cells (2^23 cells: 64 MiB of dynamic cell
  // ranges, 32 MiB of static offsets). When the region over the cell size needs more, the cell
  // size grows until it fits. Memory per step is O(cells in use) whatever the cap.
  std::int64_t cells_per_box_cap = 32;
  std::int64_t min_cells = 4096;
  std::int64_t max_cells = std::int64_t{1} << 23;
};

// Helpers shared by the uniform and the hierarchical grid: not part of the public interface.
namespace grid_detail {

// One proxy as the grids read it in their inner loops: the box, the caller's id and the lowest
// cell the box overlaps (recomputed at every build), in one 64-byte cache line.
struct GridProxy {
  Aabb box;
  std::int32_t id = 0;
  std::array<std::int32_t, 3> lo{};
};
static_assert(sizeof(GridProxy) == 64, "a proxy fills one cache line");

// True for boxes with finite coordinates and min <= max on every axis; the grids place only
// these in cells. Others (planes, NaN, inverted) are tested against everything with
// Aabb::overlaps, which is then exactly what brute force does with them.
inline bool is_regular(const Aabb& b) {
  return std::isfinite(b.min.x()) && std::isfinite(b.min.y()) && std::isfinite(b.min.z()) &&
         std::isfinite(b.max.x()) && std::isfinite(b.max.y()) && std::isfinite(b.max.z()) &&
         b.min.x() <= b.max.x() && b.min.y() <= b.max.y() && b.min.z() <= b.max.z();
}

inline Real largest_extent(const Aabb& b) {
  return std::max(b.max.x() - b.min.x(), std::max(b.max.y() - b.min.y(), b.max.z() - b.min.z()));
}

// Proxies in dense arrays, dynamic and static apart, so that a step's passes over the dynamic
// ones never touch the static ones. Ids map to (kind, slot); removal swaps the last proxy into
// the hole, so slots move and a structure must not keep slots across a removal.
class ProxyStore {
 public:
  void insert(std::int32_t id, const Aabb& box, bool is_static);
  // Both return whether the proxy is static (its grid then needs a rebuild).
  bool remove(std::int32_t id);
  bool update(std::int32_t id, const Aabb& box);

  // The slot of a proxy and whether it is static; slot -1 if the id is not in the store.
  std::int64_t slot_of(std::int32_t id, bool& is_static) const {
    const auto uid = static_cast<std::uint32_t>(id);
    if (id < 0 || uid >= loc_.size() || loc_[uid] == kNone)
      return -1;
    is_static = (loc_[uid] & kStaticBit) != 0;
    return loc_[uid] & ~kStaticBit;
  }

  // The ids of every proxy whose box overlaps `box`, sorted: the brute-force query the grids
  // fall back to before their first build and for boxes they cannot bin (infinite, NaN).
  void overlapping(const Aabb& box, std::vector<std::int32_t>& out) const;
  // The same for the segment origin + t direction, t in [0, max_t] (rays they cannot march).
  void touched_by_segment(const Vec3& origin, const Vec3& direction, Real max_t,
                          std::vector<std::int32_t>& out) const;

  // Puts the dynamic proxies in the order of `order` (a permutation of their slots).
  void permute_moving(const std::vector<std::uint32_t>& order);

  // Bits of the largest id inserted so far: pair keys are (a << id_bits) | b.
  int id_bits() const { return id_bits_; }

  std::vector<GridProxy> moving;  // dynamic proxies
  std::vector<GridProxy> fixed;   // static proxies

 private:
  static constexpr std::uint32_t kNone = 0xffffffffu;
  static constexpr std::uint32_t kStaticBit = 0x80000000u;
  std::vector<std::uint32_t> loc_;  // id -> slot | kStaticBit, or kNone
  std::vector<GridProxy> scratch_;
  int id_bits_ = 1;
};

// LSD radix sort of n 64-bit keys on their bits [lo_bit, hi_bit), digits of at most 11 bits;
// passes where every key has the same digit are skipped. Returns keys or scratch, whichever
// holds the result.
std::uint64_t* radix_sort(std::uint64_t* keys, std::uint64_t* scratch, std::size_t n, int lo_bit,
                          int hi_bit, std::vector<std::uint32_t>& histogram);

// Sorts the dynamic proxies along a Morton curve (10 bits per axis) of their box centres over
// the centres' bounds, non-finite boxes last, so that proxies near in space are near in memory.
class SpatialOrder {
 public:
  void apply(ProxyStore& store);

 private:
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint64_t> scratch_;
  std::vector<std::uint32_t> histogram_;
  std::vector<std::uint32_t> order_;
};

// Collects pairs and hands them out sorted by (a, b). Two ways, chosen at begin() from the
// previous call's count (either gives the same output):
// - sparse: 64-bit keys (a << id_bits) | b, sorted with an LSD radix sort over the bits the ids
//   use (two ids of 17 bits: 34 bits, four passes of at most 11 bits);
// - dense (a cluster where every box touches every other): an ids x ids bit matrix, used when it
//   has at most two 64-bit words per pair; emit sets a bit, finish reads the matrix in order and
//   clears it on the way.
// No allocation once the buffers have grown.
class PairSorter {
 public:
  void begin(int id_bits);
  void emit(std::int32_t a, std::int32_t b) {
    auto lo = static_cast<std::uint64_t>(a);
    auto hi = static_cast<std::uint64_t>(b);
    if (lo > hi)
      std::swap(lo, hi);
    if (dense_) {
      bitmap_[lo * row_words_ + (hi >> 6)] |= std::uint64_t{1} << (hi & 63);
      ++count_;
      return;
    }
    if (count_ == keys_.size())
      grow();
    keys_[count_++] = (lo << shift_) | hi;
  }
  void finish(std::vector<ProxyPair>& out);

 private:
  void grow();

  std::vector<std::uint64_t> keys_;  // the first count_ are in use
  std::vector<std::uint64_t> scratch_;
  std::vector<std::uint32_t> histogram_;
  std::vector<std::uint64_t> bitmap_;  // all zero between calls
  std::size_t count_ = 0;
  std::size_t last_count_ = 0;
  std::size_t row_words_ = 1;
  int shift_ = 1;
  bool dense_ = false;
};

// A cell's list entry: the proxy's slot above kHomeBits bits telling on which axes this cell is
// the proxy's lowest (after Le Grand's home and phantom cells, GPU Gems 3, ch. 32, 2007).
inline constexpr int kHomeBits = 3;
inline constexpr std::uint32_t kHomeMask = 7;

// The pairs of the oversized lists (slots of proxies too big for any cell): each dynamic member
// against every other proxy, each static member against every dynamic proxy in the grid
// (static-static pairs are never reported). `in_grid(s)` says whether dynamic slot s is in the
// grid rather than on the list.
template <class InGrid>
void pairs_with_oversized(const std::vector<GridProxy>& moving, const std::vector<GridProxy>& fixed,
                          const std::vector<std::uint32_t>& moving_big,
                          const std::vector<std::uint32_t>& fixed_big, InGrid in_grid,
                          PairSorter& sorter) {
  for (std::size_t k = 0; k < moving_big.size(); ++k) {
    const GridProxy& a = moving[moving_big[k]];
    for (std::size_t s = 0; s < moving.size(); ++s) {
      if (in_grid(s) && a.box.overlaps(moving[s].box))
        sorter.emit(a.id, moving[s].id);
    }
    for (std::size_t j = k + 1; j < moving_big.size(); ++j) {
      const GridProxy& b = moving[moving_big[j]];
      if (a.box.overlaps(b.box))
        sorter.emit(a.id, b.id);
    }
    for (const GridProxy& b : fixed) {
      if (a.box.overlaps(b.box))
        sorter.emit(a.id, b.id);
    }
  }
  for (const std::uint32_t f : fixed_big) {
    const GridProxy& a = fixed[f];
    for (std::size_t s = 0; s < moving.size(); ++s) {
      if (in_grid(s) && a.box.overlaps(moving[s].box))
        sorter.emit(a.id, moving[s].id);
    }
  }
}

// The pairs of one cell: each dynamic entry of [begin, end) with the later dynamic entries and
// with the static entries [fixed_begin, fixed_end). A pair is reported only in the one cell
// where, on every axis, at least one of the two boxes starts, so a pair that shares several
// cells is found once.
inline void pairs_in_cell(const std::uint32_t* entries, std::uint32_t begin, std::uint32_t end,
                          const std::uint32_t* fixed_entries, std::uint32_t fixed_begin,
                          std::uint32_t fixed_end, const GridProxy* moving, const GridProxy* fixed,
                          PairSorter& sorter) {
  for (std::uint32_t i = begin; i < end; ++i) {
    const std::uint32_t ea = entries[i];
    const std::uint32_t need = ~ea & kHomeMask;  // axes where a does not start here
    const GridProxy& a = moving[ea >> kHomeBits];
    for (std::uint32_t j = i + 1; j < end; ++j) {
      const std::uint32_t eb = entries[j];
      if ((eb & need) != need)
        continue;
      const GridProxy& b = moving[eb >> kHomeBits];
      if (a.box.overlaps(b.box))
        sorter.emit(a.id, b.id);
    }
    for (std::uint32_t j = fixed_begin; j < fixed_end; ++j) {
      const std::uint32_t eb = fixed_entries[j];
      if ((eb & need) != need)
        continue;
      const GridProxy& b = fixed[eb >> kHomeBits];
      if (a.box.overlaps(b.box))
        sorter.emit(a.id, b.id);
    }
  }
}

// Sorts ids ascending and drops duplicates (ray casts find a proxy once per cell).
void sort_unique(std::vector<std::int32_t>& ids);

// Visits every cell that the segment origin + t * direction, t in [t0, t1], may touch, slab by
// slab along the axis where the direction is largest: in each slab of cells along that axis the
// segment's piece is bounded, inflated by `eps` (metres) for rounding, and every cell of that
// bound is visited. Conservative (a few extra cells), never misses one, and visits each cell
// once. cell_of(axis, x) maps a coordinate to its cell index (monotone, clamped as the grid
// wants), lower(axis, i) gives the coordinate of the lower face of cell i, and visit(i, j, k)
// receives cell coordinates. `direction` must have a non-zero component.
template <class CellOf, class Lower, class Visit>
void march_segment(const Vec3& origin, const Vec3& direction, Real t0, Real t1, Real eps,
                   const CellOf& cell_of, const Lower& lower, const Visit& visit) {
  int a = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(direction[k]) > std::abs(direction[a]))
      a = k;
  }
  const int b = (a + 1) % 3;
  const int c = (a + 2) % 3;
  const Real pa0 = origin[a] + t0 * direction[a];
  const Real pa1 = origin[a] + t1 * direction[a];
  const std::int32_t ia0 = cell_of(a, std::min(pa0, pa1) - eps);
  const std::int32_t ia1 = cell_of(a, std::max(pa0, pa1) + eps);
  const Real dt = eps / std::abs(direction[a]);
  std::array<std::int32_t, 3> cell{};
  for (std::int32_t ia = ia0; ia <= ia1; ++ia) {
    Real ta = (lower(a, ia) - origin[a]) / direction[a];
    Real tb = (lower(a, ia + 1) - origin[a]) / direction[a];
    if (ta > tb)
      std::swap(ta, tb);
    ta = std::max(ta - dt, t0);
    tb = std::min(tb + dt, t1);
    if (ta > tb)
      continue;
    const Real b0 = origin[b] + ta * direction[b];
    const Real b1 = origin[b] + tb * direction[b];
    const Real c0 = origin[c] + ta * direction[c];
    const Real c1 = origin[c] + tb * direction[c];
    const std::int32_t jb0 = cell_of(b, std::min(b0, b1) - eps);
    const std::int32_t jb1 = cell_of(b, std::max(b0, b1) + eps);
    const std::int32_t jc0 = cell_of(c, std::min(c0, c1) - eps);
    const std::int32_t jc1 = cell_of(c, std::max(c0, c1) + eps);
    cell[a] = ia;
    for (std::int32_t jb = jb0; jb <= jb1; ++jb) {
      cell[b] = jb;
      for (std::int32_t jc = jc0; jc <= jc1; ++jc) {
        cell[c] = jc;
        visit(cell[0], cell[1], cell[2]);
      }
    }
  }
}

// Rounding allowance for march_segment: far above the error of o + t d and of the slab test in
// segment_touches_aabb, far below a cell.
inline Real march_eps(const Vec3& origin, const Vec3& direction, Real max_t, Real cell) {
  const Real reach = origin.cwiseAbs().maxCoeff() + direction.cwiseAbs().maxCoeff() * max_t;
  return Real(1e-6) * cell + Real(1e-12) * reach;
}

}  // namespace grid_detail

class UniformGridBroadPhase final : public BroadPhase {
 public:
  // cell_size in metres; 0 derives it from the boxes (see UniformGridSettings).
  explicit UniformGridBroadPhase(Real cell_size = 0);
  explicit UniformGridBroadPhase(const UniformGridSettings& settings);

  void insert(std::int32_t id, const Aabb& box, bool is_static) override;
  void remove(std::int32_t id) override;
  void update(std::int32_t id, const Aabb& box) override;
  void find_pairs(std::vector<ProxyPair>& out) override;
  // Both use the grid as it was at the last find_pairs; after an insert, remove or update they
  // scan every proxy instead (exact, O(n)) until the next find_pairs.
  void query(const Aabb& box, std::vector<std::int32_t>& out) const override;
  void ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                std::vector<std::int32_t>& out) const override;

  // Introspection for tests and tuning, as of the last find_pairs.
  Real cell_size() const { return layout_.cell; }
  std::array<std::int32_t, 3> grid_dims() const { return layout_.dims; }
  std::int64_t cell_count() const { return layout_.cells; }  // with the brick padding
  std::int32_t oversized_count() const {
    return static_cast<std::int32_t>(moving_big_.size() + fixed_big_.size());
  }
  int layout_derivations() const { return derivations_; }

 private:
  struct Layout {
    bool valid = false;
    Vec3 origin = Vec3::Zero();
    Real cell = 1;
    Real inv = 1;
    std::array<std::int32_t, 3> dims{1, 1, 1};
    // Per axis: coordinate -> its part of the cell number (brick offset + bits inside the brick);
    // a cell's number is the sum of the three parts.
    std::array<std::vector<std::uint32_t>, 3> part;
    std::int64_t cells = 1;
    Real mean_extent = 0;  // at derivation, to detect change
  };
  // Cell range of one proxy, and why it is not in the grid.
  enum class Fit : std::uint8_t { grid, irregular, outside, oversized };

  Fit classify(grid_detail::GridProxy& p, std::array<std::int32_t, 3>& hi) const;
  void derive_layout();
  bool layout_is_stale(std::int64_t outside, std::int64_t regular, Real extent_sum,
                       const Aabb& bounds) const;
  void build_static();
  void build_moving();
  void pairs_in_cells();
  void pairs_with_oversized();
  // A cell entry (grid_detail::kHomeBits).
  static constexpr int kHomeBits = grid_detail::kHomeBits;
  static std::uint32_t entry(std::size_t slot, const std::array<std::int32_t, 3>& lo,
                             std::int32_t x, std::int32_t y, std::int32_t z) {
    return static_cast<std::uint32_t>(slot) << kHomeBits | static_cast<std::uint32_t>(x == lo[0]) |
           static_cast<std::uint32_t>(y == lo[1]) << 1 |
           static_cast<std::uint32_t>(z == lo[2]) << 2;
  }
  std::uint32_t code(std::int32_t x, std::int32_t y, std::int32_t z) const {
    return layout_.part[0][x] + layout_.part[1][y] + layout_.part[2][z];
  }
  std::int32_t clamped_cell(int axis, Real x) const;

  UniformGridSettings settings_;
  grid_detail::ProxyStore store_;
  Layout layout_;
  bool built_ = false;       // grid matches the proxies (query and ray_cast may use it)
  bool fixed_dirty_ = true;  // the static grid needs a rebuild
  int derivations_ = 0;

  // Dynamic grid, rebuilt every find_pairs. Only the occupied cells' ranges are non-zero.
  struct Range {
    std::uint32_t begin = 0;
    std::uint32_t end = 0;
  };
  std::vector<Range> moving_range_;  // per cell
  std::vector<std::uint32_t> moving_entries_;
  std::vector<std::uint32_t> occupied_;  // non-empty dynamic cells, in the order first met
  grid_detail::SpatialOrder spatial_order_;
  int steps_since_sort_ = 0;
  std::vector<std::array<std::int32_t, 3>> moving_hi_;
  std::vector<std::uint8_t> moving_in_grid_;
  std::vector<std::uint32_t> moving_big_;
  std::int64_t moving_outside_ = 0;

  // Static grid, rebuilt when a static proxy changes or the layout is re-derived.
  std::vector<std::uint32_t> fixed_start_;  // cells + 1 offsets
  std::vector<std::uint32_t> fixed_entries_;
  std::vector<std::uint32_t> fixed_big_;
  std::int64_t fixed_outside_ = 0;
  std::int64_t fixed_regular_ = 0;
  Real fixed_extent_sum_ = 0;
  Aabb fixed_bounds_;  // of the regular static boxes

  std::vector<Real> extents_scratch_;
  grid_detail::PairSorter sorter_;
};

}  // namespace tumble
