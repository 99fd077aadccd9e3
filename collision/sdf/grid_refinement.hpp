// A grid's band near the surface sampled `refine` times finer than the grid itself: adaptive
// resolution where contacts happen, at a memory cost that grows with the surface's area rather
// than the grid's volume (the idea of narrow-band level sets: Adalsteinsson and Sethian, "A fast
// level set method for propagating interfaces", J. Comput. Phys. 118, 1995; stored the way of
// Museth's VDB, in fixed blocks of nodes found through a table, "VDB: High-resolution sparse
// volumes with dynamic topology", ACM TOG 32(3), 2013).
//
// The fine nodes lie on the grid's own lattice divided by `refine`, in blocks of 8^3 nodes. A
// block exists where its centre lies within kBand + 2 fine cells and half its diagonal of a
// triangle: every node within
// kBand fine cells of the surface holds its exact distance (signed by ray parity along its fine
// row), the others of an existing block the coarse grid's value there. A point whose
// interpolation stencil (2 nodes a side trilinear, 4 tricubic) lies in existing blocks is
// sampled at the fine level, any other at the coarse one.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "collision/math.hpp"
#include "collision/sdf/grid_interpolation.hpp"
#include "collision/sdf/sdf_primitives.hpp"

namespace tumble {

class SdfGrid;

class GridRefinement {
 public:
  static constexpr int kBlock = 8;
  static constexpr int kMaxRefine = 16;
  // The table of blocks spans the whole grid, 4 bytes a block: at most 64 MB of it.
  static constexpr std::int64_t kMaxBlocks = std::int64_t(1) << 24;

  // The refined band of `coarse`, a grid built from the same closed mesh. Throws tumble::Error for
  // a factor outside [2, kMaxRefine], more than kMaxBlocks blocks in the table, or more fine
  // nodes than SdfGrid::kMaxNodes.
  static GridRefinement build(std::span<const Vec3> vertices,
                              std::span<const std::array<std::int32_t, 3>> triangles,
                              const SdfGrid& coarse, int refine);

  // Throws tumble::Error when refining a grid of `coarse_nodes` by `refine` would pass the
  // limits above (before anything is built).
  static void check_size(const std::array<int, 3>& coarse_nodes, int refine);

  // The fine interpolant at p when its stencil lies in the refined band (true), else false.
  bool sample(const Vec3& p, GridInterpolation how, sdf::Sample& out) const;

  int refine() const { return refine_; }
  Real cell() const { return cell_; }
  std::int64_t nodes() const { return std::int64_t(values_.size()); }
  std::int64_t band_nodes() const { return band_nodes_; }
  std::size_t bytes() const {
    return values_.size() * sizeof(Real) + block_slot_.size() * sizeof(std::int32_t);
  }

 private:
  std::int32_t slot_of(int bx, int by, int bz) const {
    return block_slot_[std::size_t(bx) +
                       std::size_t(blocks_[0]) *
                           (std::size_t(by) + std::size_t(blocks_[1]) * std::size_t(bz))];
  }
  Real value(int i, int j, int k) const;

  int refine_ = 1;
  Vec3 origin_ = Vec3::Zero();
  Real cell_ = 1;
  std::array<int, 3> nodes_{};            // fine nodes along each axis
  std::array<int, 3> blocks_{};           // blocks along each axis
  std::vector<std::int32_t> block_slot_;  // per block: its index into values_ / kBlock^3, or -1
  std::vector<Real> values_;
  std::int64_t band_nodes_ = 0;
};

}  // namespace tumble
