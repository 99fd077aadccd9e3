// A rigid solid given by a signed distance field (collision/sdf/sdf_tree.hpp), with what the
// engine needs besides the field: mass properties, a bounding box and radius, and points spread
// over its surface for the narrow phase (collision/narrow_phase/pairs/sdf_pairs.cpp).
//
// Mass properties are integrated over phi < 0 on a grid of cells (the resolution: kMassCells
// along the longest side of the bounds unless the caller picks another); cells the surface may
// cross (|phi| below the cell's half diagonal) are split into kSubcells^3 sub-cells, each counted
// by the fraction 1/2 - phi / s of its size s that lies inside (exact for a plane across an
// axis-aligned cell). The volume error of a torus (1.0, 0.25) is below 0.05% and its inertia's
// below 0.1% (tests/collision/sdf_shape_test.cpp; docs/sdf.md). The local frame is the tree's,
// moved so that the centre of mass is the origin, as for every shape.
//
// Surface points: the centre of every grid cell the surface crosses, projected onto phi = 0 by
// Newton steps along the gradient, with the outward normal there; about one point per cell side
// of surface (kMassCells = 48: a torus (1, 0.25) gets 6,240; 8 cells give it 200). They are
// bucketed in a coarse grid so that the points inside a box are found without a scan.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/aabb.hpp"
#include "collision/math.hpp"
#include "collision/sdf/sdf_tree.hpp"
#include "tumble/shape.hpp"

namespace tumble {

class SdfShape {
 public:
  static constexpr int kMassCells = 48;
  static constexpr int kSubcells = 4;
  // The resolutions a shape may have. Cost and surface points grow as cells^2 (the cells the
  // surface crosses) plus cells^3 / 64 (the whole grid, one sample a cell): 96 takes about four
  // times as long as 48 to build and has four times the points (a cube's six faces about 55,000);
  // 8 is coarse enough for a placeholder, fine enough to see a solid as thick as an eighth of its
  // length.
  static constexpr int kMinCells = 8;
  static constexpr int kMaxCells = 96;
  // The narrow phase numbers a field's points in 16 bits of a contact's feature id (which the
  // solver's warm start matches from step to step): a solid with more is refused, naming a
  // resolution to lower.
  static constexpr int kMaxSurfacePoints = 65536;

  // Throws tumble::Error when the field has no bounded solid (a half-space alone, or a solid
  // smaller than the grid can see: no cell centre inside), or when `cells` (the grid's cells
  // along the longest side of the bounds) is outside [kMinCells, kMaxCells].
  explicit SdfShape(const SdfNode& root, int cells = kMassCells);

  // The field in the local frame (centre of mass at the origin), at `time` (seconds; Shape's
  // field_time, which the world keeps at its clock) for a field that changes with time.
  sdf::Sample sample(const Vec3& p, Real time = 0) const {
    return tree_.sample(p + tree_origin_, time);
  }
  Real distance(const Vec3& p, Real time = 0) const {
    return tree_.distance(p + tree_origin_, time);
  }
  // A field that changes with time (a morph, collision/sdf/sdf_tree.hpp): only static and
  // kinematic bodies may have one (its mass properties are those it starts with). Its surface
  // points are those of where it starts and where it ends, and queries project them onto the
  // surface of their time; surface_motion() bounds how far that surface is from them.
  bool changes_with_time() const { return tree_.changes_with_time(); }
  Real surface_motion() const { return surface_motion_; }
  Real changes_from() const { return tree_.changes_from(); }
  Real changes_until() const { return tree_.changes_until(); }

  // Where the tree's origin is in the local frame: tree point = local point + centre_in_tree().
  const Vec3& centre_in_tree() const { return tree_origin_; }
  const Aabb& local_bounds() const { return local_bounds_; }
  Real volume() const { return volume_; }
  const Mat3& unit_inertia() const { return unit_inertia_; }
  Real bounding_radius() const { return bounding_radius_; }
  // The radius of the largest ball inside the solid (from the grid): half the thinnest part.
  Real inner_radius() const { return inner_radius_; }
  // The grid's cell size: the spacing of the surface points, and the scale of their error.
  Real cell_size() const { return cell_; }
  bool is_exact() const { return tree_.is_exact(); }
  // SdfTree::is_one_lipschitz, kept at construction.
  bool is_one_lipschitz() const { return one_lipschitz_; }
  // How far from the surface the field's values can be trusted (SdfTree::reach).
  Real reach() const { return tree_.reach(); }

  int surface_point_count() const { return static_cast<int>(points_.size()); }
  const Vec3& surface_point(int i) const { return points_[std::size_t(i)]; }
  const Vec3& surface_normal(int i) const { return normals_[std::size_t(i)]; }
  const std::vector<Vec3>& surface_points() const { return points_; }

  // Calls f(index) for every surface point in `box` (local frame), in index order within each
  // bucket and buckets in x-fastest order: deterministic. `near(centre, radius)` is asked first
  // for each bucket holding points (the ball around it that holds them); a bucket it refuses is
  // skipped whole, which is how a caller culls by a partner's distance (a 1-Lipschitz field
  // farther than radius + margin from the centre has none of its points within the margin).
  template <class Near, class F>
  void for_each_surface_point_in(const Aabb& box, Near&& near, F&& f) const {
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      const Real a = (box.min[k] - local_bounds_.min[k]) / bucket_;
      const Real b = (box.max[k] - local_bounds_.min[k]) / bucket_;
      if (!(b >= 0) || !(a < Real(buckets_[k])))
        return;
      lo[k] = a < 0 ? 0 : int(a);
      hi[k] = b >= Real(buckets_[k] - 1) ? buckets_[k] - 1 : int(b);
    }
    const Real radius = bucket_ * Real(0.8660254037844386);
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) {
          const std::size_t cell =
              std::size_t(x) + std::size_t(buckets_[0]) *
                                   (std::size_t(y) + std::size_t(buckets_[1]) * std::size_t(z));
          if (bucket_start_[cell] == bucket_start_[cell + 1])
            continue;
          const Vec3 centre =
              local_bounds_.min +
              bucket_ * Vec3(Real(x) + Real(0.5), Real(y) + Real(0.5), Real(z) + Real(0.5));
          if (!near(centre, radius))
            continue;
          for (std::uint32_t i = bucket_start_[cell]; i < bucket_start_[cell + 1]; ++i) {
            const Vec3& p = points_[bucket_points_[i]];
            if (box.contains(p))
              f(int(bucket_points_[i]));
          }
        }
  }
  template <class F>
  void for_each_surface_point_in(const Aabb& box, F&& f) const {
    for_each_surface_point_in(
        box, [](const Vec3&, Real) { return true; }, f);
  }

 private:
  SdfTree tree_;
  Vec3 tree_origin_ = Vec3::Zero();
  Aabb local_bounds_;
  Real volume_ = 0;
  Mat3 unit_inertia_ = Mat3::Zero();
  Real bounding_radius_ = 0;
  Real inner_radius_ = 0;
  Real cell_ = 0;
  Real surface_motion_ = 0;
  bool one_lipschitz_ = false;
  std::vector<Vec3> points_;
  std::vector<Vec3> normals_;
  Real bucket_ = 1;
  int buckets_[3] = {1, 1, 1};
  std::vector<std::uint32_t> bucket_start_;
  std::vector<std::uint32_t> bucket_points_;
};

// The shape of `root` at a resolution of `cells` (SdfShape); `centre_of_mass` (if given)
// receives the centre of mass in the tree's frame, where a body must be placed for the solid to
// sit where the tree says. Throws as SdfShape does and as SdfTree does for a malformed tree.
Shape sdf_shape(const SdfNode& root, Vec3* centre_of_mass = nullptr,
                int cells = SdfShape::kMassCells);

}  // namespace tumble
