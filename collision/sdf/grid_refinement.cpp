// The refined band of a grid SDF (collision/sdf/grid_refinement.hpp).
#include "collision/sdf/grid_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "collision/closest_point_on_triangle.hpp"
#include "collision/sdf/mesh_distance_band.hpp"
#include "collision/sdf/sdf_grid.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

constexpr int kBlockNodes =
    GridRefinement::kBlock * GridRefinement::kBlock * GridRefinement::kBlock;

std::size_t within_block(int i, int j, int k) {
  constexpr int b = GridRefinement::kBlock;
  return std::size_t(i % b) +
         std::size_t(b) * (std::size_t(j % b) + std::size_t(b) * std::size_t(k % b));
}

}  // namespace

void GridRefinement::check_size(const std::array<int, 3>& coarse_nodes, int refine) {
  if (refine < 2 || refine > kMaxRefine)
    throw Error("SDF grid: refine must be from 2 to " + std::to_string(kMaxRefine) + ", got " +
                std::to_string(refine));
  std::int64_t table = 1;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t fine = std::int64_t(coarse_nodes[std::size_t(k)] - 1) * refine + 1;
    table *= (fine + kBlock - 1) / kBlock;
    if (table > kMaxBlocks)
      throw Error("SDF grid: the refined band's table of blocks passes " +
                  std::to_string(kMaxBlocks) + " entries; use larger cells or refine less");
  }
}

GridRefinement GridRefinement::build(std::span<const Vec3> vertices,
                                     std::span<const std::array<std::int32_t, 3>> triangles,
                                     const SdfGrid& coarse, int refine) {
  check_size(coarse.nodes(), refine);
  GridRefinement r;
  r.refine_ = refine;
  r.origin_ = coarse.origin();
  r.cell_ = coarse.cell() / Real(refine);
  std::int64_t table = 1;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t fine = std::int64_t(coarse.nodes()[std::size_t(k)] - 1) * refine + 1;
    r.nodes_[std::size_t(k)] = int(fine);
    r.blocks_[std::size_t(k)] = int((fine + kBlock - 1) / kBlock);
    table *= r.blocks_[std::size_t(k)];
  }
  r.block_slot_.assign(std::size_t(table), -1);
  const auto table_index = [&](int bx, int by, int bz) {
    return std::size_t(bx) + std::size_t(r.blocks_[0]) *
                                 (std::size_t(by) + std::size_t(r.blocks_[1]) * std::size_t(bz));
  };

  // The blocks within kBand + 2 fine cells of a triangle: the band, and the two nodes a tricubic
  // stencil reaches beyond it. A block of the triangle's grown box is taken when its centre is
  // within that reach plus the block's half diagonal of the triangle (a large tilted triangle's
  // box holds many blocks far from it).
  const Real reach = (SdfGrid::kBand + 2) * r.cell_;
  const Real block_size = kBlock * r.cell_;
  const Real take = reach + block_size * Real(0.8660254037844386);  // + half the diagonal
  for (const auto& t : triangles) {
    const Vec3& a = vertices[std::size_t(t[0])];
    const Vec3& b = vertices[std::size_t(t[1])];
    const Vec3& c = vertices[std::size_t(t[2])];
    int lo[3], hi[3];
    sdf::node_range_near(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c), reach, r.origin_,
                         r.cell_, r.nodes_, lo, hi);
    for (int k = 0; k < 3; ++k) {
      lo[k] /= kBlock;
      hi[k] /= kBlock;
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) {
          std::int32_t& slot = r.block_slot_[table_index(x, y, z)];
          if (slot == 0)
            continue;
          const Vec3 centre =
              r.origin_ + block_size * (Vec3(Real(x), Real(y), Real(z)) + Vec3::Constant(0.5));
          if ((centre - closest_point_on_triangle(centre, a, b, c)).norm() <= take)
            slot = 0;
        }
  }
  std::int64_t slots = 0;
  for (std::int32_t& slot : r.block_slot_)
    if (slot == 0) {
      if ((slots + 1) * kBlockNodes > SdfGrid::kMaxNodes)
        throw Error("SDF grid: the refined band passes " + std::to_string(SdfGrid::kMaxNodes) +
                    " nodes; use larger cells or refine less");
      slot = std::int32_t(slots++);
    }
  // The nodes within the band of a triangle first take their least distance to one (unsigned,
  // in place: the values are the only node-sized array), then, block by block, its sign by the
  // parity of their fine row's crossings; every other node of a block the coarse grid's value.
  r.values_.assign(std::size_t(slots) * kBlockNodes, std::numeric_limits<Real>::infinity());

  const auto node_index = [&](int i, int j, int k) -> std::int64_t {
    const std::int32_t slot = r.slot_of(i / kBlock, j / kBlock, k / kBlock);
    return slot < 0 ? -1 : std::int64_t(slot) * kBlockNodes + std::int64_t(within_block(i, j, k));
  };
  const Real band = SdfGrid::kBand * r.cell_;
  sdf::for_each_node_near_triangles(
      vertices, triangles, r.origin_, r.cell_, r.nodes_, band, [&](int x, int y, int z, Real d) {
        const std::int64_t at = node_index(x, y, z);
        if (at >= 0)
          r.values_[std::size_t(at)] = std::min(r.values_[std::size_t(at)], d);
      });
  const std::vector<sdf::RowCrossing> crossings =
      sdf::row_crossings(vertices, triangles, r.origin_, r.cell_, r.nodes_);
  const auto by_row = [](const sdf::RowCrossing& c, std::size_t row) { return c.row < row; };
  for (int bz = 0; bz < r.blocks_[2]; ++bz)
    for (int by = 0; by < r.blocks_[1]; ++by)
      for (int bx = 0; bx < r.blocks_[0]; ++bx) {
        const std::int32_t slot = r.slot_of(bx, by, bz);
        if (slot < 0)
          continue;
        for (int k = bz * kBlock; k < (bz + 1) * kBlock; ++k)
          for (int j = by * kBlock; j < (by + 1) * kBlock; ++j) {
            // A block past the lattice's last row holds nodes no sample reads: the coarse value.
            const bool row_in_lattice = j < r.nodes_[1] && k < r.nodes_[2];
            const std::size_t row = std::size_t(j) + std::size_t(r.nodes_[1]) * std::size_t(k);
            auto first = crossings.end(), last = crossings.end();
            if (row_in_lattice) {
              first = std::lower_bound(crossings.begin(), crossings.end(), row, by_row);
              last = first;
              while (last != crossings.end() && last->row == row)
                ++last;
            }
            for (int i = bx * kBlock; i < (bx + 1) * kBlock; ++i) {
              Real& value = r.values_[std::size_t(slot) * kBlockNodes + within_block(i, j, k)];
              const Vec3 node = r.origin_ + r.cell_ * Vec3(Real(i), Real(j), Real(k));
              if (row_in_lattice && i < r.nodes_[0] && value <= band) {
                const auto before =
                    std::lower_bound(first, last, node.x(),
                                     [](const sdf::RowCrossing& c, Real v) { return c.x < v; });
                if ((before - first) % 2 != 0)
                  value = -value;
                ++r.band_nodes_;
              } else {
                value = coarse.sample(node, GridInterpolation::tricubic).distance;
              }
            }
          }
      }
  return r;
}

Real GridRefinement::value(int i, int j, int k) const {
  const std::int32_t slot = slot_of(i / kBlock, j / kBlock, k / kBlock);
  return values_[std::size_t(slot) * kBlockNodes + within_block(i, j, k)];
}

bool GridRefinement::sample(const Vec3& p, GridInterpolation how, sdf::Sample& out) const {
  const int before = how == GridInterpolation::tricubic ? 1 : 0;
  const int after = how == GridInterpolation::tricubic ? 2 : 1;
  int cell_index[3];
  Real t[3];
  int block_low[3], block_high[3];
  for (int k = 0; k < 3; ++k) {
    const Real u = (p[k] - origin_[k]) / cell_;
    if (!(u >= 0 && u <= Real(nodes_[std::size_t(k)] - 1)))
      return false;  // outside the lattice (or not a number)
    const int i = std::min(int(u), nodes_[std::size_t(k)] - 2);
    if (i - before < 0 || i + after > nodes_[std::size_t(k)] - 1)
      return false;
    cell_index[k] = i;
    t[k] = std::clamp(u - Real(i), Real(0), Real(1));
    block_low[k] = (i - before) / kBlock;
    block_high[k] = (i + after) / kBlock;
  }
  for (int bz = block_low[2]; bz <= block_high[2]; ++bz)
    for (int by = block_low[1]; by <= block_high[1]; ++by)
      for (int bx = block_low[0]; bx <= block_high[0]; ++bx)
        if (slot_of(bx, by, bz) < 0)
          return false;
  out = sdf::interpolate(cell_index, t, cell_, how,
                         [&](int i, int j, int k) { return value(i, j, k); });
  return true;
}

}  // namespace tumble
