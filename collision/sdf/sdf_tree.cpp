// SdfTree: the checks, the flattened layout and the evaluation (collision/sdf/sdf_tree.hpp).
#include "collision/sdf/sdf_tree.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "tumble/error.hpp"

namespace tumble {

SdfNode SdfNode::sphere(Real radius) {
  SdfNode n;
  n.kind = SdfKind::sphere;
  n.radius = radius;
  return n;
}

SdfNode SdfNode::box(const Vec3& half_extents) {
  SdfNode n;
  n.kind = SdfKind::box;
  n.half_extents = half_extents;
  return n;
}

SdfNode SdfNode::capsule(Real radius, Real half_length) {
  SdfNode n;
  n.kind = SdfKind::capsule;
  n.radius = radius;
  n.half_length = half_length;
  return n;
}

SdfNode SdfNode::cylinder(Real radius, Real half_length) {
  SdfNode n = capsule(radius, half_length);
  n.kind = SdfKind::cylinder;
  return n;
}

SdfNode SdfNode::torus(Real major_radius, Real minor_radius) {
  SdfNode n;
  n.kind = SdfKind::torus;
  n.major_radius = major_radius;
  n.minor_radius = minor_radius;
  return n;
}

SdfNode SdfNode::plane() {
  SdfNode n;
  n.kind = SdfKind::plane;
  return n;
}

SdfNode SdfNode::from_grid(std::shared_ptr<const SdfGrid> grid, GridInterpolation how) {
  SdfNode n;
  n.kind = SdfKind::grid;
  n.grid = std::move(grid);
  n.interpolation = how;
  return n;
}

SdfNode SdfNode::from_network(std::shared_ptr<const NeuralSdf> network) {
  SdfNode n;
  n.kind = SdfKind::neural;
  n.neural = std::move(network);
  return n;
}

SdfNode SdfNode::morph(SdfNode from, SdfNode to, Real start, Real duration) {
  SdfNode n;
  n.kind = SdfKind::morph;
  n.children = {std::move(from), std::move(to)};
  n.start = start;
  n.duration = duration;
  return n;
}

SdfNode SdfNode::from_level_set(std::shared_ptr<const VdbLevelSet> level_set,
                                GridInterpolation how) {
  SdfNode n;
  n.kind = SdfKind::level_set;
  n.level_set = std::move(level_set);
  n.interpolation = how;
  return n;
}

SdfNode SdfNode::combine(SdfKind operation, std::vector<SdfNode> operands, Real k) {
  SdfNode n;
  n.kind = operation;
  n.children = std::move(operands);
  n.k = k;
  return n;
}

SdfNode SdfNode::placed(const Transform& p) const {
  SdfNode n = *this;
  n.pose = p;
  return n;
}

namespace {

bool is_operation(SdfKind kind) {
  return kind >= SdfKind::union_of;
}

std::string text(Real v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

int count_nodes(const SdfNode& n, int depth, const std::string& path) {
  if (depth > SdfTree::kMaxDepth)
    throw Error("SDF " + path + ": nested deeper than " + std::to_string(SdfTree::kMaxDepth) +
                " levels");
  int total = 1;
  for (std::size_t i = 0; i < n.children.size(); ++i) {
    total += count_nodes(n.children[i], depth + 1, path + ".children[" + std::to_string(i) + "]");
    if (total > SdfTree::kMaxNodes)
      throw Error("SDF: more than " + std::to_string(SdfTree::kMaxNodes) + " nodes");
  }
  return total;
}

void check_size(Real v, const std::string& path, const char* name) {
  if (!(std::isfinite(v) && v > 0 && v <= SdfTree::kMaxSize))
    throw Error("SDF " + path + ": " + name + " must be positive and at most 1e6 m, got " +
                text(v));
}

// The box of `local` seen from the parent frame through `pose`: the box of its eight corners
// (an open axis stays open).
Aabb placed_bounds(const Aabb& local, const Transform& pose) {
  if (!local.min.allFinite() || !local.max.allFinite()) {
    const Real inf = std::numeric_limits<Real>::infinity();
    return {Vec3::Constant(-inf), Vec3::Constant(inf)};
  }
  return local.placed(pose);
}

}  // namespace

SdfTree::SdfTree(const SdfNode& root) {
  nodes_.reserve(std::size_t(count_nodes(root, 1, "root")));
  nodes_.emplace_back();
  flatten(root, 0, "root", 1);
  bounds_ = bounds_of(0);
}

bool SdfTree::is_one_lipschitz() const {
  return std::all_of(nodes_.begin(), nodes_.end(), [](const Flat& f) {
    switch (f.kind) {  // every kind named: a new one must say which it is
      case SdfKind::sphere:
      case SdfKind::box:
      case SdfKind::capsule:
      case SdfKind::cylinder:
      case SdfKind::torus:
      case SdfKind::plane:
      case SdfKind::union_of:
      case SdfKind::intersection_of:
      case SdfKind::difference_of:
      case SdfKind::smooth_union_of:  // its gradient a weighted mean of its operands'
        return true;
      case SdfKind::grid:
      case SdfKind::neural:
      case SdfKind::level_set:
      case SdfKind::morph:
        return false;
    }
    return false;
  });
}

bool SdfTree::is_bounded() const {
  return bounds_.min.allFinite() && bounds_.max.allFinite();
}

void SdfTree::flatten(const SdfNode& n, std::uint32_t slot, const std::string& path, int depth) {
  if (!n.pose.translation.allFinite() || !n.pose.rotation.coeffs().allFinite() ||
      n.pose.translation.cwiseAbs().maxCoeff() > kMaxSize)
    throw Error("SDF " + path + ": the position must be finite and within 1e6 m");
  const Real qn = n.pose.rotation.norm();
  if (!(qn > Real(0.5) && qn < Real(2)))
    throw Error("SDF " + path + ": the orientation is not a rotation (quaternion length " +
                text(qn) + ")");
  Flat f;
  f.kind = n.kind;
  f.pose.translation = n.pose.translation;
  f.pose.rotation = n.pose.rotation.normalized();
  f.moved = !(f.pose.translation.isZero(0) && f.pose.rotation.vec().isZero(0));
  switch (n.kind) {
    case SdfKind::sphere:
      check_size(n.radius, path, "radius");
      f.a = n.radius;
      break;
    case SdfKind::box:
      for (int k = 0; k < 3; ++k)
        check_size(n.half_extents[k], path, "every half extent");
      f.half_extents = n.half_extents;
      break;
    case SdfKind::capsule:
    case SdfKind::cylinder:
      check_size(n.radius, path, "radius");
      check_size(n.half_length, path, "half_length");
      f.a = n.radius;
      f.b = n.half_length;
      break;
    case SdfKind::torus:
      check_size(n.major_radius, path, "major_radius");
      check_size(n.minor_radius, path, "minor_radius");
      if (n.minor_radius >= n.major_radius)
        throw Error("SDF " + path + ": minor_radius " + text(n.minor_radius) +
                    " must be less than major_radius " + text(n.major_radius) + " (a ring torus)");
      f.a = n.major_radius;
      f.b = n.minor_radius;
      break;
    case SdfKind::plane:
      break;
    case SdfKind::grid:
      if (!n.grid)
        throw Error("SDF " + path + ": a grid node without its grid");
      f.interpolation = n.interpolation;
      f.first = std::uint32_t(grids_.size());
      grids_.push_back(n.grid);
      break;
    case SdfKind::neural:
      if (!n.neural)
        throw Error("SDF " + path + ": a neural node without its network");
      f.first = std::uint32_t(networks_.size());
      networks_.push_back(n.neural);
      break;
    case SdfKind::level_set:
      if (!n.level_set)
        throw Error("SDF " + path + ": a level-set node without its level set");
      f.interpolation = n.interpolation;
      f.first = std::uint32_t(level_sets_.size());
      level_sets_.push_back(n.level_set);
      reach_ = std::min(
          reach_, n.level_set->band() - (n.interpolation == GridInterpolation::tricubic ? 2 : 1) *
                                            n.level_set->voxel());
      break;
    case SdfKind::morph:
      if (n.children.size() != 2)
        throw Error("SDF " + path + ": a morph needs two fields, from and to, got " +
                    std::to_string(n.children.size()));
      if (!(std::isfinite(n.start) && std::abs(n.start) <= 1e9))
        throw Error("SDF " + path + ": the start must be finite (at most 1e9 s), got " +
                    text(n.start));
      if (!(std::isfinite(n.duration) && n.duration > 0 && n.duration <= 1e9))
        throw Error("SDF " + path + ": the duration must be positive (at most 1e9 s), got " +
                    text(n.duration));
      f.a = n.start;
      f.b = n.duration;
      changes_from_ = std::min(changes_from_, n.start);
      changes_until_ = std::max(changes_until_, n.start + n.duration);
      break;
    case SdfKind::smooth_union_of:
      if (!(std::isfinite(n.k) && n.k > 0 && n.k <= 1e9))
        throw Error("SDF " + path + ": k must be positive and at most 1e9 (1/m), got " + text(n.k));
      f.a = n.k;
      [[fallthrough]];
    case SdfKind::union_of:
    case SdfKind::intersection_of:
    case SdfKind::difference_of:
      if (n.children.size() < 2)
        throw Error("SDF " + path + ": an operation needs at least two operands, got " +
                    std::to_string(n.children.size()));
      break;
    default:
      throw Error("SDF " + path + ": unknown kind");
  }
  if (!is_operation(n.kind) && !n.children.empty())
    throw Error("SDF " + path + ": a primitive has no operands");
  if (is_operation(n.kind)) {
    f.first = static_cast<std::uint32_t>(nodes_.size());
    f.count = static_cast<std::uint32_t>(n.children.size());
  }
  nodes_[slot] = f;
  // Children sit side by side, so an operation walks a contiguous run of nodes.
  nodes_.resize(nodes_.size() + n.children.size());
  for (std::size_t i = 0; i < n.children.size(); ++i)
    flatten(n.children[i], f.first + std::uint32_t(i),
            path + ".children[" + std::to_string(i) + "]", depth + 1);
}

Aabb SdfTree::bounds_of(std::uint32_t i) const {
  const Flat& f = nodes_[i];
  const Real inf = std::numeric_limits<Real>::infinity();
  Aabb local;
  switch (f.kind) {
    case SdfKind::sphere:
      local = {Vec3::Constant(-f.a), Vec3::Constant(f.a)};
      break;
    case SdfKind::box:
      local = {-f.half_extents, f.half_extents};
      break;
    case SdfKind::capsule:
      local = {Vec3(-f.a, -f.a, -f.a - f.b), Vec3(f.a, f.a, f.a + f.b)};
      break;
    case SdfKind::cylinder:
      local = {Vec3(-f.a, -f.a, -f.b), Vec3(f.a, f.a, f.b)};
      break;
    case SdfKind::torus:
      local = {Vec3(-f.a - f.b, -f.a - f.b, -f.b), Vec3(f.a + f.b, f.a + f.b, f.b)};
      break;
    case SdfKind::plane:
      local = {Vec3(-inf, -inf, -inf), Vec3(inf, inf, 0)};
      break;
    case SdfKind::grid:
      local = grids_[f.first]->box();
      break;
    case SdfKind::neural:
      local = networks_[f.first]->bounds();
      break;
    case SdfKind::level_set:
      local = level_sets_[f.first]->bounds();
      break;
    case SdfKind::union_of:
    case SdfKind::smooth_union_of:
    case SdfKind::morph:  // phi <= 0 somewhere between the two solids' boxes: within their union
      for (std::uint32_t c = 0; c < f.count; ++c)
        local.grow(bounds_of(f.first + c));
      if (f.kind == SdfKind::smooth_union_of && local.min.allFinite())
        local = local.inflated(std::log(Real(f.count)) / f.a);
      break;
    case SdfKind::intersection_of:
      local = {Vec3::Constant(-inf), Vec3::Constant(inf)};
      for (std::uint32_t c = 0; c < f.count; ++c) {
        const Aabb b = bounds_of(f.first + c);
        local.min = local.min.cwiseMax(b.min);
        local.max = local.max.cwiseMin(b.max);
      }
      local.max = local.max.cwiseMax(local.min);  // an empty intersection: a point
      break;
    case SdfKind::difference_of:
      local = bounds_of(f.first);
      break;
  }
  if (!f.moved)
    return local;
  // A half-space turned by the pose opens every axis (the corners would be infinite).
  return placed_bounds(local, f.pose);
}

sdf::Sample SdfTree::sample_node(std::uint32_t i, const Vec3& world, Real time) const {
  const Flat& f = nodes_[i];
  const Vec3 p = f.moved ? f.pose.apply_inverse(world) : world;
  sdf::Sample s;
  switch (f.kind) {
    case SdfKind::sphere:
      s = sdf::sphere(p, f.a);
      break;
    case SdfKind::box:
      s = sdf::box(p, f.half_extents);
      break;
    case SdfKind::capsule:
      s = sdf::capsule(p, f.a, f.b);
      break;
    case SdfKind::cylinder:
      s = sdf::cylinder(p, f.a, f.b);
      break;
    case SdfKind::torus:
      s = sdf::torus(p, f.a, f.b);
      break;
    case SdfKind::plane:
      s = sdf::plane(p);
      break;
    case SdfKind::grid:
      s = grids_[f.first]->sample(p, f.interpolation);
      break;
    case SdfKind::neural:
      s = networks_[f.first]->sample(p);
      break;
    case SdfKind::level_set:
      s = level_sets_[f.first]->sample(p, f.interpolation);
      break;
    case SdfKind::union_of:
    case SdfKind::intersection_of: {
      // min for a union, max for an intersection; the gradient is the chosen operand's.
      const Real side = f.kind == SdfKind::union_of ? Real(1) : Real(-1);
      s = sample_node(f.first, p, time);
      for (std::uint32_t c = 1; c < f.count; ++c) {
        const sdf::Sample o = sample_node(f.first + c, p, time);
        if (side * o.distance < side * s.distance)
          s = o;
      }
      break;
    }
    case SdfKind::difference_of: {
      // max(phi_A, -phi_B1, -phi_B2, ...).
      s = sample_node(f.first, p, time);
      for (std::uint32_t c = 1; c < f.count; ++c) {
        const sdf::Sample o = sample_node(f.first + c, p, time);
        if (-o.distance > s.distance)
          s = {-o.distance, -o.gradient};
      }
      break;
    }
    case SdfKind::morph: {
      // Before the start the first field alone, after the end the second alone (not a blend
      // with a zero weight: a far-away field's value does not leak in).
      const Real w = std::clamp((time - f.a) / f.b, Real(0), Real(1));
      if (w == 0) {
        s = sample_node(f.first, p, time);
      } else if (w == 1) {
        s = sample_node(f.first + 1, p, time);
      } else {
        const sdf::Sample from = sample_node(f.first, p, time);
        const sdf::Sample to = sample_node(f.first + 1, p, time);
        s = {(1 - w) * from.distance + w * to.distance, (1 - w) * from.gradient + w * to.gradient};
      }
      break;
    }
    case SdfKind::smooth_union_of: {
      // -1/k log(sum exp(-k phi_i)) accumulated in one pass with a running maximum of the
      // exponents (no overflow for any phi), and its gradient, the softmin-weighted mean of the
      // operands' gradients.
      const Real k = f.a;
      Real top = -std::numeric_limits<Real>::infinity();
      Real sum = 0;
      Vec3 weighted = Vec3::Zero();
      for (std::uint32_t c = 0; c < f.count; ++c) {
        const sdf::Sample o = sample_node(f.first + c, p, time);
        const Real e = -k * o.distance;
        if (e > top) {
          const Real scale = std::exp(top - e);  // 0 on the first operand
          sum = sum * scale + 1;
          weighted = weighted * scale + o.gradient;
          top = e;
        } else {
          const Real w = std::exp(e - top);
          sum += w;
          weighted += w * o.gradient;
        }
      }
      s = {-(top + std::log(sum)) / k, weighted / sum};
      break;
    }
  }
  if (f.moved)
    s.gradient = f.pose.rotate(s.gradient);
  return s;
}

// sample_node's distances by the same operations in the same order, so the same bits: each
// operation chooses or blends its operands by their distances alone.
Real SdfTree::distance_node(std::uint32_t i, const Vec3& world, Real time) const {
  const Flat& f = nodes_[i];
  const Vec3 p = f.moved ? f.pose.apply_inverse(world) : world;
  switch (f.kind) {
    case SdfKind::sphere:
      return sdf::sphere_distance(p, f.a);
    case SdfKind::box:
      return sdf::box_distance(p, f.half_extents);
    case SdfKind::capsule:
      return sdf::capsule_distance(p, f.a, f.b);
    case SdfKind::cylinder:
      return sdf::cylinder_distance(p, f.a, f.b);
    case SdfKind::torus:
      return sdf::torus_distance(p, f.a, f.b);
    case SdfKind::plane:
      return sdf::plane(p).distance;
    case SdfKind::grid:
    case SdfKind::neural:
    case SdfKind::level_set:
      return sample_node(i, world, time).distance;  // interpolated together with the gradient
    case SdfKind::union_of:
    case SdfKind::intersection_of: {
      const Real side = f.kind == SdfKind::union_of ? Real(1) : Real(-1);
      Real d = distance_node(f.first, p, time);
      for (std::uint32_t c = 1; c < f.count; ++c) {
        const Real o = distance_node(f.first + c, p, time);
        if (side * o < side * d)
          d = o;
      }
      return d;
    }
    case SdfKind::difference_of: {
      Real d = distance_node(f.first, p, time);
      for (std::uint32_t c = 1; c < f.count; ++c) {
        const Real o = distance_node(f.first + c, p, time);
        if (-o > d)
          d = -o;
      }
      return d;
    }
    case SdfKind::morph: {
      const Real w = std::clamp((time - f.a) / f.b, Real(0), Real(1));
      if (w == 0)
        return distance_node(f.first, p, time);
      if (w == 1)
        return distance_node(f.first + 1, p, time);
      return (1 - w) * distance_node(f.first, p, time) + w * distance_node(f.first + 1, p, time);
    }
    case SdfKind::smooth_union_of: {
      const Real k = f.a;
      Real top = -std::numeric_limits<Real>::infinity();
      Real sum = 0;
      for (std::uint32_t c = 0; c < f.count; ++c) {
        const Real e = -k * distance_node(f.first + c, p, time);
        if (e > top) {
          sum = sum * std::exp(top - e) + 1;
          top = e;
        } else {
          sum += std::exp(e - top);
        }
      }
      return -(top + std::log(sum)) / k;
    }
  }
  return sample_node(i, world, time).distance;
}

}  // namespace tumble
