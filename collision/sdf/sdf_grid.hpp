// A signed distance field stored on a regular grid and interpolated: built from a closed triangle
// mesh (or from any field sampled at the nodes), sampled trilinearly or tricubically with the
// exact gradient of the interpolant.
//
// Building from a mesh, the way of Baerentzen's and Sethian's narrow-band methods:
//  - near the surface (within kBand cells of a triangle), the exact distance to the nearest
//    triangle (Ericson, Real-Time Collision Detection, 5.1.5), each triangle visiting the nodes of
//    its box grown by the band;
//  - beyond, the Eikonal equation |grad phi| = 1 solved by fast sweeping (Zhao, "A fast sweeping
//    method for Eikonal equations", Mathematics of Computation 74, 2005): Gauss-Seidel sweeps in
//    the 8 orderings of the axes with Godunov's upwind update, the band's values held fixed;
//  - the sign by ray parity: each row of nodes along x counts the triangles its line crosses (the
//    line moved off the nodes by an irrational hair, so it never passes through an edge or a
//    vertex), and a node with an odd count of crossings before it is inside. The mesh must be
//    closed and consistently oriented (every edge run once each way by two triangles), which the
//    build checks and refuses otherwise.
//
// Refinement (`refine` > 1): the band near the surface sampled that many times finer, in blocks
// of nodes that exist only near the surface (collision/sdf/grid_refinement.hpp); a point whose
// stencil lies in the refined band is sampled there, any other on the grid.
//
// Interpolation: trilinear (C0; its gradient is piecewise, exact for the interpolant) or tricubic
// (Catmull-Rom in each axis, C1: the gradient is continuous across cells, so contacts sliding
// over cell faces do not feel the grid). Outside the grid the value is the boundary's plus the
// distance to the grid's box (a lower bound of the distance to the surface, as for CSG bounds).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "collision/aabb.hpp"
#include "collision/math.hpp"
#include "collision/sdf/grid_interpolation.hpp"
#include "collision/sdf/grid_refinement.hpp"
#include "collision/sdf/sdf_primitives.hpp"

namespace tumble {

class SdfGrid {
 public:
  static constexpr int kBand = 3;                     // cells of exact distance around the surface
  static constexpr std::int64_t kMaxNodes = 1 << 27;  // 128 M nodes, 1 GB of doubles

  struct BuildReport {
    std::int64_t nodes = 0;
    std::int64_t band_nodes = 0;  // nodes given their exact distance
    int sweeps = 0;
    std::int64_t refined_nodes = 0;       // nodes of the refined band's blocks
    std::int64_t refined_band_nodes = 0;  // of those, given their exact distance
    double seconds = 0;
    std::size_t bytes = 0;
  };

  // From a closed mesh (vertices and counter-clockwise triangles seen from outside) with cells of
  // `cell` metres; the grid covers the mesh's box grown by `margin_cells` cells (at least the
  // band), its band near the surface `refine` times finer when refine > 1. Throws tumble::Error
  // for an empty or open mesh, a cell not positive, too many nodes, or refine outside 1 to
  // GridRefinement::kMaxRefine.
  static SdfGrid from_mesh(std::span<const Vec3> vertices,
                           std::span<const std::array<std::int32_t, 3>> triangles, Real cell,
                           int margin_cells = kBand + 1, BuildReport* report = nullptr,
                           int refine = 1);

  // From values at the nodes: node (i, j, k) at origin + cell (i, j, k), x fastest.
  SdfGrid(const Vec3& origin, Real cell, std::array<int, 3> nodes, std::vector<Real> values);

  sdf::Sample sample(const Vec3& p, GridInterpolation how = GridInterpolation::tricubic) const;
  Real value(int i, int j, int k) const {
    return values_[std::size_t(i) + std::size_t(nodes_[0]) *
                                        (std::size_t(j) + std::size_t(nodes_[1]) * std::size_t(k))];
  }

  const Vec3& origin() const { return origin_; }
  Real cell() const { return cell_; }
  const std::array<int, 3>& nodes() const { return nodes_; }
  // The grid's box; phi <= 0 only inside it.
  Aabb box() const;
  std::size_t bytes() const {
    return values_.size() * sizeof(Real) + (refinement_ ? refinement_->bytes() : 0);
  }
  // The refined band, or null.
  const GridRefinement* refinement() const { return refinement_.get(); }

 private:
  sdf::Sample inside_sample(const Vec3& p, GridInterpolation how) const;
  Vec3 origin_ = Vec3::Zero();
  Real cell_ = 1;
  std::array<int, 3> nodes_{1, 1, 1};
  std::vector<Real> values_;
  std::shared_ptr<const GridRefinement> refinement_;
};

}  // namespace tumble
