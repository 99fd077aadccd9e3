// Mass properties and surface points of an SDF solid (collision/shapes/sdf_shape.hpp).
#include "collision/shapes/sdf_shape.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "tumble/error.hpp"

namespace tumble {
namespace {

// Moments of the solid about the tree's origin, summed cell by cell.
struct Moments {
  Real mass = 0;  // the volume (unit density)
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();  // sum of m x x^T, with each cell's own spread

  void add(const Vec3& centre, Real side, Real fraction) {
    if (fraction <= 0)
      return;
    const Real m = fraction * side * side * side;
    mass += m;
    first += m * centre;
    second += m * (centre * centre.transpose());
    // A full cube's own second moment is m s^2 / 12 on each axis; a part-filled one is treated
    // the same (its share is small: only surface cells are partly filled).
    second.diagonal().array() += m * side * side / 12;
  }
};

Real inside_fraction(Real phi, Real side) {
  return std::clamp(Real(0.5) - phi / side, Real(0), Real(1));
}

}  // namespace

SdfShape::SdfShape(const SdfNode& root, int cells_along_longest) : tree_(root) {
  if (cells_along_longest < kMinCells || cells_along_longest > kMaxCells)
    throw Error("an SDF shape's resolution must be " + std::to_string(kMinCells) + " to " +
                std::to_string(kMaxCells) + " cells along its longest side, got " +
                std::to_string(cells_along_longest));
  one_lipschitz_ = tree_.is_one_lipschitz();
  if (!tree_.is_bounded())
    throw Error(
        "an SDF shape must be a bounded solid: a half-space is unbounded (intersect it with a "
        "bounded solid, or use a plane shape)");
  const Aabb& tb = tree_.bounds();
  const Vec3 size = tb.max - tb.min;
  const Real longest = size.maxCoeff();
  cell_ = longest / Real(cells_along_longest);
  // A cell of margin on every side (the bounds of a bound field may touch the surface), and the
  // grid centred on the bounds, so that a symmetric solid is sampled symmetrically.
  int cells[3];
  Vec3 start;
  for (int k = 0; k < 3; ++k) {
    cells[k] = std::max(1, int(std::ceil(size[k] / cell_)) + 2);
    start[k] = (tb.min[k] + tb.max[k]) / 2 - cell_ * Real(cells[k]) / 2;
  }

  const Real half_diagonal = cell_ * Real(0.8660254037844386);
  const Real sub = cell_ / kSubcells;
  Moments moments;
  Real deepest = 0;
  std::vector<Vec3> tree_points;
  std::vector<Vec3> tree_normals;
  // The mass (of a static or kinematic body only, if the field changes) as the field starts.
  const Real time_of_mass = tree_.changes_with_time() ? tree_.changes_from() : Real(0);
  // Newton steps onto phi = 0 along the gradient, from a cell's centre.
  const auto add_surface_point = [&](const Vec3& centre, Real time) {
    Vec3 p = centre;
    sdf::Sample s = tree_.sample(p, time);
    for (int step = 0; step < 8 && std::abs(s.distance) > cell_ * Real(1e-6); ++step) {
      const Real g2 = s.gradient.squaredNorm();
      if (!(g2 > 0))
        break;
      p -= (s.distance / g2) * s.gradient;
      s = tree_.sample(p, time);
    }
    if (std::abs(s.distance) <= cell_ * Real(1e-6) && s.gradient.squaredNorm() > 0 &&
        (p - centre).norm() <= 2 * cell_) {
      tree_points.push_back(p);
      tree_normals.push_back(s.gradient.normalized());
    }
  };
  for (int z = 0; z < cells[2]; ++z)
    for (int y = 0; y < cells[1]; ++y)
      for (int x = 0; x < cells[0]; ++x) {
        const Vec3 centre =
            start + cell_ * Vec3(Real(x) + Real(0.5), Real(y) + Real(0.5), Real(z) + Real(0.5));
        const Real phi = tree_.distance(centre, time_of_mass);
        deepest = std::min(deepest, phi);
        if (phi <= -half_diagonal) {
          moments.add(centre, cell_, 1);
          continue;
        }
        if (phi >= half_diagonal)
          continue;
        // The surface may cross this cell: sub-cells for the mass, a surface point for contacts.
        for (int k = 0; k < kSubcells; ++k)
          for (int j = 0; j < kSubcells; ++j)
            for (int i = 0; i < kSubcells; ++i) {
              const Vec3 c = centre + sub * Vec3(Real(i) + Real(0.5) - Real(kSubcells) / 2,
                                                 Real(j) + Real(0.5) - Real(kSubcells) / 2,
                                                 Real(k) + Real(0.5) - Real(kSubcells) / 2);
              moments.add(c, sub, inside_fraction(tree_.distance(c, time_of_mass), sub));
            }
        add_surface_point(centre, time_of_mass);
      }
  // A field that changes with time has surface points of where it ends too; a query projects
  // them onto the surface of its time (SdfShape::changes_with_time).
  if (tree_.changes_with_time())
    for (int z = 0; z < cells[2]; ++z)
      for (int y = 0; y < cells[1]; ++y)
        for (int x = 0; x < cells[0]; ++x) {
          const Vec3 centre =
              start + cell_ * Vec3(Real(x) + Real(0.5), Real(y) + Real(0.5), Real(z) + Real(0.5));
          if (std::abs(tree_.distance(centre, tree_.changes_until())) < half_diagonal)
            add_surface_point(centre, tree_.changes_until());
        }
  if (!(moments.mass > 0) || tree_points.empty())
    throw Error("an SDF shape must enclose a solid at least a grid cell across (" +
                std::to_string(cell_) + " m here)");
  if (tree_points.size() > std::size_t(kMaxSurfacePoints))
    throw Error("an SDF shape may have at most " + std::to_string(kMaxSurfacePoints) +
                " surface points, and this one has " + std::to_string(tree_points.size()) + " at " +
                std::to_string(cells_along_longest) +
                " cells along its longest side: lower its resolution");
  volume_ = moments.mass;
  const Vec3 centre = moments.first / moments.mass;
  tree_origin_ = centre;
  const Mat3 spread = moments.second - moments.mass * (centre * centre.transpose());
  const Mat3 inertia = spread.trace() * Mat3::Identity() - spread;
  // Symmetric to the last bit (the sums above round the two triangles differently).
  unit_inertia_ = (inertia + inertia.transpose()) / (2 * moments.mass);
  inner_radius_ = -deepest;
  // How far the surface moves over the field's change: each end's points measured in the other
  // end's field.
  if (tree_.changes_with_time())
    for (const Vec3& p : tree_points)
      surface_motion_ =
          std::max(surface_motion_, std::max(std::abs(tree_.distance(p, tree_.changes_from())),
                                             std::abs(tree_.distance(p, tree_.changes_until()))));

  points_.reserve(tree_points.size());
  normals_ = std::move(tree_normals);
  for (const Vec3& p : tree_points) {
    points_.push_back(p - centre);
    local_bounds_.grow(points_.back());
    bounding_radius_ = std::max(bounding_radius_, points_.back().norm());
  }
  // Between two surface points the surface may bulge out by a fraction of a cell.
  local_bounds_ = local_bounds_.inflated(cell_ / 2);
  bounding_radius_ += cell_ / 2;

  // Buckets of two cells for the point queries.
  bucket_ = 2 * cell_;
  std::size_t bucket_count = 1;
  for (int k = 0; k < 3; ++k) {
    buckets_[k] =
        std::max(1, int(std::ceil((local_bounds_.max[k] - local_bounds_.min[k]) / bucket_)));
    bucket_count *= std::size_t(buckets_[k]);
  }
  const auto bucket_of = [&](const Vec3& p) {
    std::size_t index = 0;
    std::size_t stride = 1;
    for (int k = 0; k < 3; ++k) {
      const int c = std::clamp(int((p[k] - local_bounds_.min[k]) / bucket_), 0, buckets_[k] - 1);
      index += stride * std::size_t(c);
      stride *= std::size_t(buckets_[k]);
    }
    return index;
  };
  bucket_start_.assign(bucket_count + 1, 0);
  for (const Vec3& p : points_)
    ++bucket_start_[bucket_of(p) + 1];
  for (std::size_t b = 0; b < bucket_count; ++b)
    bucket_start_[b + 1] += bucket_start_[b];
  bucket_points_.resize(points_.size());
  std::vector<std::uint32_t> fill(bucket_start_.begin(), bucket_start_.end() - 1);
  for (std::size_t i = 0; i < points_.size(); ++i)
    bucket_points_[fill[bucket_of(points_[i])]++] = std::uint32_t(i);
}

Shape sdf_shape(const SdfNode& root, Vec3* centre_of_mass, int cells) {
  auto field = std::make_shared<const SdfShape>(root, cells);
  if (centre_of_mass != nullptr)
    *centre_of_mass = field->centre_in_tree();
  return Shape::signed_distance_field(std::move(field));
}

}  // namespace tumble
