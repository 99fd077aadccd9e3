// Spatial hash broad phase.
//
// Source: M. Teschner, B. Heidelberger, M. Mueller, D. Pomeranets, M. Gross, "Optimized Spatial
// Hashing for Collision Detection of Deformable Objects", VMV 2003: space is cut into cubic
// cells of edge h, cell (i, j, k) goes to bucket (i p1 xor j p2 xor k p3) mod M with the primes
// p1 = 73856093, p2 = 19349663, p3 = 83492791, and only the cells that hold something cost
// memory. A rule of thumb for h is about twice the mean object radius; tumble takes
// a box's radius to be that of its bounding sphere.
//
// The table is rebuilt by every find_pairs with a counting sort of (cell, proxy) entries into
// one flat array ordered by bucket: no per-cell lists, no allocation once the buffers are warm.
// M is the power of two at least 2.25 x the occupied cells expected (last build's ratio of cells
// to entries); the fill counts the occupied cells and is redone with a larger M in the rare
// step where M < 2 x occupied.
// A box goes into every cell it spans. Within a bucket, entries of different cells that
// collided in the hash are told apart by the cell coordinates stored in each entry, and a pair
// is reported only from the cell that holds the lower corner of the two boxes' intersection,
// max(a.min, b.min): that point lies in both boxes, so that cell is in both cell ranges, and it
// is one cell, so each pair is reported exactly once with no dedupe. The final test is
// Aabb::overlaps, so a hash collision never yields a false pair. Dynamic proxies' entries come
// first in each bucket, so static-static pairs are never even looked at.
//
// Boxes spanning more than SpatialHashSettings::max_cells_per_box cells, and infinite ones, go
// to an "oversized" list tested against every proxy instead, so one huge box cannot flood the
// table.
//
// Every 32 builds the slots are renumbered in Morton order of the boxes' first cells, so that the
// boxes of one cell, and the buckets of neighbouring proxies' cells, are near each other in
// memory when the table is filled and scanned (the hash itself scatters cells on purpose).
//
// Queries between two find_pairs see boxes that changed since the table was built (inserted,
// updated) as "dirty": those are tested one by one, the table's entries for them are skipped.
// A box query visits the cells of its box with the same lower-corner rule; a ray cast visits
// the cells of pieces of its segment (each piece's box inflated by a relative 1e-9 so rounding
// never hides a box that segment_touches_aabb accepts), then sorts and dedupes.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/broad_phase/broad_phase.hpp"

namespace tumble {

struct SpatialHashSettings {
  // Cell edge h in metres. 0 (default) = automatic: h = 2 r, r the mean radius of the finite
  // boxes' bounding spheres (half of each box's diagonal), set at the first find_pairs that has
  // boxes and set again whenever that mean has changed by more than a factor 2 since h was set.
  // A cube of half-extent a then spans about 1.6 cells a side (h = 2 sqrt(3) a). Too small a
  // cell puts each box in many cells; too large, many boxes in one cell, tested pairwise.
  Real cell_size = 0;
  // A box spanning more cells than this (or infinite) is kept out of the table and tested
  // against every proxy: it would cost more entries than that test costs.
  std::int64_t max_cells_per_box = 256;
};

class SpatialHashBroadPhase final : public BroadPhase {
 public:
  explicit SpatialHashBroadPhase(const SpatialHashSettings& settings = {});

  void insert(std::int32_t id, const Aabb& box, bool is_static) override;
  void remove(std::int32_t id) override;
  void update(std::int32_t id, const Aabb& box) override;
  void find_pairs(std::vector<ProxyPair>& out) override;
  void query(const Aabb& box, std::vector<std::int32_t>& out) const override;
  void ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                std::vector<std::int32_t>& out) const override;

  // The state of the last build, for tests and profiling.
  Real cell_size() const { return cell_size_; }
  std::size_t oversized_count() const { return oversized_.size(); }
  std::size_t entry_count() const { return entries_.size(); }
  std::size_t bucket_count() const { return bucket_mask_ + 1; }
  std::size_t occupied_cells() const { return occupied_; }

 private:
  enum class State : std::uint8_t { free, live };
  struct Proxy {
    std::int32_t id = -1;
    State state = State::free;
    bool is_static = false;
    bool dirty = false;      // changed since the table was built
    bool oversized = false;  // in oversized_ at the last build
  };
  struct CellRange {
    std::int32_t lo[3];
    std::int32_t hi[3];
  };
  // One (cell, proxy) of the table. `tag`: the slot in the low 28 bits, bit 28 + k set when
  // `cell` is the box's first cell on axis k, bit 31 set for a static proxy.
  struct Entry {
    std::int32_t cell[3];
    std::uint32_t tag;
  };

  std::uint32_t allocate_slot();
  void mark_dirty(std::uint32_t slot);
  void choose_cell_size();
  void renumber_slots();
  void build();
  std::int32_t cell_of(Real x) const;
  std::uint32_t bucket_of(std::int32_t x, std::int32_t y, std::int32_t z) const;
  template <class Visit>
  void visit_cells(const CellRange& range, Visit&& visit) const;
  void brute_force(const Aabb* box, const Vec3* origin, const Vec3* direction, Real max_t,
                   std::vector<std::int32_t>& out) const;

  SpatialHashSettings settings_;
  std::vector<Proxy> proxies_;  // by slot
  std::vector<Aabb> boxes_;     // by slot
  std::vector<std::int32_t> id_to_slot_;
  std::vector<std::uint32_t> free_slots_;
  std::vector<std::uint32_t> dirty_;         // slots changed since the last build
  std::vector<std::uint32_t> oversized_;     // slots outside the table at the last build
  std::vector<std::uint32_t> order_;         // slots in the table: dynamic ones, then static ones
  std::vector<CellRange> ranges_;            // by slot, during a build
  std::vector<std::uint32_t> bucket_start_;  // size M + 1
  std::vector<std::uint32_t> entry_bucket_;  // bucket of each entry, in order_ order
  std::vector<Entry> entries_;               // sorted by bucket
  std::vector<std::uint64_t> keys_;          // pair keys a << 32 | b
  std::vector<std::uint64_t> sort_scratch_;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> morton_;  // scratch for renumber_slots
  std::vector<Proxy> renumbered_proxies_;
  std::vector<Aabb> renumbered_boxes_;
  Real cell_size_ = 0;
  Real inv_cell_size_ = 0;
  Real mean_at_choice_ = 0;  // the mean half-extent h was derived from (automatic mode)
  std::uint32_t bucket_mask_ = 0;
  std::size_t occupied_ = 0;          // distinct occupied cells at the last build
  std::size_t dynamic_in_order_ = 0;  // order_[0, this) are the dynamic proxies
  std::size_t live_ = 0;
  std::size_t entries_at_last_build_ = 0;
  int builds_since_renumber_ = 0;
  bool built_ = false;
};

}  // namespace tumble
