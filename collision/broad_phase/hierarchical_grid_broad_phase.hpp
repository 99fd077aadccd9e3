// Hierarchical grid broad phase: levels of cells of edge s_l = s_0 * 2^l, each box on the one
// level whose cells are as large as the box, each level a hashed grid. After Mirtich,
// "Efficient Algorithms for Two-Phase Collision Detection" (MERL TR-97-23, 1997), the
// hierarchical hash grid, and Ericson, Real-Time Collision Detection (2005), 7.2 (hierarchical
// grids). Cells are hashed with the primes of Teschner et al., "Optimized Spatial Hashing for
// Collision Detection of Deformable Objects" (VMV 2003) into a power-of-two open-addressing
// table per level (linear probing).
//
// Definitions.
// - r, a box's size: its largest extent, max over axes of (max - min).
// - s_0: the base cell edge. Given to the constructor, or derived as the smallest power of two
//   >= the smallest positive r among the finite boxes (powers of two make x / s_l an exact
//   scaling). Re-derived when the smallest r falls below s_0 / 4 or rises above s_0 * 2^16.
// - level l = ceil(log2(r / s_0)), and 0 for r <= s_0 (level_for_size), so s_l >= r: the box spans
//   at most 2 cells of its level per axis, 2 x 2 x 2 in all. r = max - min can round below the
//   true extent (the box [-1e-17, 1] has r = 1 and touches 3 unit cells); such a box moves one
//   level up, so the bound is exact.
// - Boxes that are not finite, or would need a level >= kMaxLevels, go to an oversized list
//   tested against every proxy (planes, NaN).
//
// Each box is inserted in every cell of its level it overlaps (at most 8), and each pair is found
// exactly once:
// - same level: in the cells the two share, reported only in the cell holding the lower corner of
//   their intersection (on each axis one of the two boxes has its lowest cell there; each cell
//   entry carries those three bits, as in the uniform grid);
// - different levels: only from the finer box A, which looks up the cells of each coarser level
//   it overlaps (at most 8 per level, since A is at most half a cell of any coarser level), with
//   the same lower-corner rule in that level's cells. The coarser box never looks down.
// Static proxies have their own level grids, rebuilt only when a static proxy changes; static
// pairs are never formed. A dynamic box is the one that looks in the static grids, in all their
// levels: coarser and same levels as above, and finer levels too (the symmetric case, where the
// dynamic box is the coarser one): there it visits the cells it overlaps at that finer level, or
// when those are more than the static boxes of that level, tests those boxes directly.
//
// Cache: every 16 steps the dynamic proxies are sorted along a Morton curve of their centres
// (as in the uniform grid), and the lookups of coarser cells remember the last cell per level,
// which the next box in that order mostly asks for again.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "collision/broad_phase/broad_phase.hpp"
#include "collision/broad_phase/uniform_grid_broad_phase.hpp"

namespace tumble {

class HierarchicalGridBroadPhase final : public BroadPhase {
 public:
  // Levels 0 .. kMaxLevels - 1: sizes up to s_0 * 2^47 (enough for 1e-3 m .. 1e11 m).
  static constexpr int kMaxLevels = 48;

  // base_cell is s_0 in metres; 0 derives it from the boxes.
  explicit HierarchicalGridBroadPhase(Real base_cell = 0);

  void insert(std::int32_t id, const Aabb& box, bool is_static) override;
  void remove(std::int32_t id) override;
  void update(std::int32_t id, const Aabb& box) override;
  void find_pairs(std::vector<ProxyPair>& out) override;
  // Both use the grids as they were at the last find_pairs; after an insert, remove or update
  // they scan every proxy instead (exact, O(n)) until the next find_pairs.
  void query(const Aabb& box, std::vector<std::int32_t>& out) const override;
  void ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                std::vector<std::int32_t>& out) const override;

  // The level rule: 0 if r <= s0, else ceil(log2(r / s0)), evaluated exactly (s0 * 2^l >= r and
  // l = 0 or s0 * 2^(l-1) < r). May exceed kMaxLevels (INT_MAX when r / s0 overflows).
  static int level_for_size(Real r, Real s0);

  // Introspection for tests and tuning, as of the last find_pairs.
  Real base_cell() const { return s0_; }
  // The level of a proxy, -1 if it is in the oversized list or unknown.
  int level_of(std::int32_t id) const;
  int oversized_count() const { return static_cast<int>(moving_big_.size() + fixed_big_.size()); }
  int base_derivations() const { return derivations_; }

 private:
  using Cells3 = std::array<std::int32_t, 3>;

  // The hashed grids of one kind of proxy (dynamic or static), all levels, rebuilt as a whole:
  // a counting sort of the (proxy, cell) entries into one flat array, with the cells found
  // through one open-addressing table per level.
  class LevelGrids {
   public:
    struct Cell {
      Cells3 at;  // cell coordinates on its level
      std::uint32_t begin = 0;
      std::uint32_t end = 0;
    };
    static constexpr std::uint32_t kNoCell = 0xffffffffu;

    // level[s] is the level of pool[s], -1 for none; pool[s].lo and hi[s] its cell range there.
    void build(const std::vector<grid_detail::GridProxy>& pool,
               const std::vector<std::int8_t>& level, const std::vector<Cells3>& hi);
    std::uint32_t find(int level, const Cells3& at) const;

    const std::vector<int>& levels() const { return nonempty_; }  // ascending
    std::uint32_t objects(int level) const { return level_begin_[level + 1] - level_begin_[level]; }
    const std::uint32_t* level_slots(int level) const { return &by_level_[level_begin_[level]]; }
    std::uint32_t cells_begin(int level) const { return cell_begin_[level]; }
    std::uint32_t cells_end(int level) const { return cell_begin_[level + 1]; }
    const Cell& cell(std::uint32_t c) const { return cells_[c]; }
    const std::uint32_t* entries() const { return entries_.data(); }
    bool empty() const { return nonempty_.empty(); }

   private:
    struct Slot {
      Cells3 at;
      std::uint32_t cell;
    };
    struct Table {
      std::uint32_t offset = 0;
      std::uint32_t mask = 0;
      int bits = 0;  // log2 of the size, at least 4; 0 for an empty level
    };
    std::uint32_t find_or_add(int level, const Cells3& at);

    std::array<Table, kMaxLevels> tables_{};
    std::vector<Slot> slots_;
    std::vector<Cell> cells_;
    std::array<std::uint32_t, kMaxLevels + 1> cell_begin_{};   // cells of a level are contiguous
    std::array<std::uint32_t, kMaxLevels + 1> level_begin_{};  // into by_level_
    std::vector<std::uint32_t> by_level_;                      // slots, grouped by level
    std::vector<std::uint32_t> entry_cell_;                    // build scratch
    std::vector<std::uint32_t> entries_;  // slot << 3 | lowest-cell bits, per cell
    std::vector<int> nonempty_;
  };

  // The level of a box and its cell range there (into p.lo and hi), or -1 for the oversized list.
  int classify(grid_detail::GridProxy& p, Cells3& hi) const;
  void derive_base(Real smallest);
  void build_static();
  void classify_moving(Real& smallest);
  void pairs_same_level();
  void pairs_across_levels();
  void pairs_with_oversized();
  Real level_inv(int level) const { return std::ldexp(inv_s0_, -level); }
  Real level_cell(int level) const { return std::ldexp(s0_, level); }
  static std::int32_t cell_of(Real x, Real inv);

  Real fixed_s0_ = 0;  // the constructor's s_0, 0 for derived
  Real s0_ = 1;
  Real inv_s0_ = 1;
  bool s0_valid_ = false;
  int derivations_ = 0;
  grid_detail::ProxyStore store_;
  bool built_ = false;
  bool fixed_dirty_ = true;

  std::vector<std::int8_t> moving_level_;
  std::vector<Cells3> moving_hi_;
  std::vector<std::uint32_t> moving_big_;
  LevelGrids moving_grid_;

  std::vector<std::int8_t> fixed_level_;
  std::vector<Cells3> fixed_hi_;
  std::vector<std::uint32_t> fixed_big_;
  LevelGrids fixed_grid_;
  Real fixed_smallest_ = 0;  // smallest positive r among the static boxes, 0 if none

  grid_detail::SpatialOrder spatial_order_;
  int steps_since_sort_ = 0;
  grid_detail::PairSorter sorter_;
};

}  // namespace tumble
