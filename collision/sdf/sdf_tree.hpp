// A solid given by its signed distance: analytic primitives (sphere, box, capsule, cylinder,
// torus, half-space), grids, OpenVDB level sets and networks, each placed by a rigid transform,
// combined by constructive solid geometry (union, intersection, difference, smooth union) to any
// depth. SdfTree::sample gives the signed distance of a point and its gradient, evaluated without
// allocating.
//
// Exact and bound: a primitive's distance is exact (|phi| is the distance to the surface and
// |grad phi| = 1). A union's is exact outside it and a bound inside; an intersection's and a
// difference's are bounds everywhere (|phi| <= the true distance, zero exactly on the surface),
// and a smooth union's is within log(n) / k of the union's. The surface phi = 0 is always exact,
// so contacts found at phi < 0 are real; a bound only makes a deep penetration look shallower
// than it is and the push-out direction that of the nearest primitive (docs/sdf.md).
// Combinations follow Ricci, "A constructive geometry for computer graphics" (The Computer
// Journal 16, 1973): min, max and max(a, -b); the smooth union is the log-sum-exp
// -1/k log(sum exp(-k phi_i)), which is below every phi_i by at most log(n) / k.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "collision/aabb.hpp"
#include "collision/math.hpp"
#include "collision/sdf/neural_sdf.hpp"
#include "collision/sdf/sdf_grid.hpp"
#include "collision/sdf/sdf_primitives.hpp"
#include "collision/sdf/vdb_level_set.hpp"

namespace tumble {

enum class SdfKind : std::uint8_t {
  sphere,
  box,
  capsule,
  cylinder,
  torus,
  plane,
  grid,       // a grid of samples (collision/sdf/sdf_grid.hpp), interpolated
  neural,     // a network (collision/sdf/neural_sdf.hpp)
  level_set,  // an OpenVDB narrow-band level set (collision/sdf/vdb_level_set.hpp), interpolated
  union_of,
  intersection_of,
  difference_of,  // the first child minus every other
  smooth_union_of,
  // (1 - w) phi_first + w phi_second, w = clamp((time - start) / duration, 0, 1): a field that
  // morphs from one solid to another over time (a kinematic obstacle only; docs/sdf.md).
  morph,
};

// How a node is described (from YAML, C++ or Python); SdfTree checks it and flattens it.
struct SdfNode {
  SdfKind kind = SdfKind::sphere;
  Transform pose;                    // the node's frame in its parent's
  Real radius = 0;                   // sphere, capsule, cylinder [m]
  Real half_length = 0;              // capsule, cylinder [m]
  Vec3 half_extents = Vec3::Zero();  // box [m]
  Real major_radius = 0;             // torus [m]
  Real minor_radius = 0;             // torus [m]
  Real k = 0;                        // smooth union: sharpness [1/m]; the blend is about 1/k wide
  Real start = 0;                    // morph: when it leaves the first field [s]
  Real duration = 0;                 // morph: how long it takes to reach the second [s]
  std::shared_ptr<const SdfGrid> grid;  // grid
  GridInterpolation interpolation = GridInterpolation::tricubic;
  std::shared_ptr<const NeuralSdf> neural;       // neural
  std::shared_ptr<const VdbLevelSet> level_set;  // level_set
  std::vector<SdfNode> children;                 // the operations' operands

  static SdfNode sphere(Real radius);
  static SdfNode box(const Vec3& half_extents);
  static SdfNode capsule(Real radius, Real half_length);
  static SdfNode cylinder(Real radius, Real half_length);
  static SdfNode torus(Real major_radius, Real minor_radius);
  static SdfNode plane();
  static SdfNode from_grid(std::shared_ptr<const SdfGrid> grid,
                           GridInterpolation how = GridInterpolation::tricubic);
  static SdfNode from_network(std::shared_ptr<const NeuralSdf> network);
  static SdfNode from_level_set(std::shared_ptr<const VdbLevelSet> level_set,
                                GridInterpolation how = GridInterpolation::trilinear);
  static SdfNode combine(SdfKind operation, std::vector<SdfNode> operands, Real k = 0);
  static SdfNode morph(SdfNode from, SdfNode to, Real start, Real duration);
  SdfNode placed(const Transform& pose) const;
};

class SdfTree {
 public:
  static constexpr int kMaxDepth = 64;
  static constexpr int kMaxNodes = 100000;
  static constexpr Real kMaxSize = 1e6;  // m, any length of a primitive

  // Throws tumble::Error naming the node (by its path, "root.children[1]") and what is wrong: a
  // size not positive and finite or above kMaxSize, a torus whose tube is not thinner than its
  // ring, an operation with fewer than two operands, k not positive, a pose not finite, a tree
  // deeper than kMaxDepth or larger than kMaxNodes.
  explicit SdfTree(const SdfNode& root);

  // The signed distance at p (tree frame) and its gradient, at `time` (seconds; only a morph
  // depends on it).
  sdf::Sample sample(const Vec3& p, Real time = 0) const { return sample_node(0, p, time); }
  // The distance alone: the same bits as sample(p, time).distance, without the gradients.
  Real distance(const Vec3& p, Real time = 0) const { return distance_node(0, p, time); }
  // Whether the field changes with time (it holds a morph), and the times it stops changing
  // between: before `changes_from()` and after `changes_until()` it is constant.
  bool changes_with_time() const { return changes_from_ < changes_until_; }
  Real changes_from() const { return changes_from_; }
  Real changes_until() const { return changes_until_; }

  // A box holding every point with phi <= 0; infinite along the axes a half-space leaves open.
  const Aabb& bounds() const { return bounds_; }
  bool is_bounded() const;
  // Whether |phi| is the distance to the surface everywhere (a lone analytic primitive; a grid's
  // and a network's values are approximations of it).
  bool is_exact() const { return nodes_[0].kind <= SdfKind::plane; }
  int node_count() const { return static_cast<int>(nodes_.size()); }
  // How far from the surface the values are distances (or bounds of them, for CSG): infinite
  // unless the tree holds a narrow-band level set, whose values beyond its band are clamped to
  // the band's edge; then the band less the interpolation's reach (one voxel trilinear, two
  // tricubic), the least of all its level sets. A contact or distance that evaluates the field
  // farther from its surface than this (at a sphere's centre) cannot trust the value.
  Real reach() const { return reach_; }
  // Whether phi changes by at most the distance moved (its gradient no longer than 1) everywhere,
  // exactly: analytic primitives under poses and their unions, intersections, differences and
  // smooth unions. Grids, level sets and networks approximate it (an interpolant's slope can pass
  // 1), and a morph moves with time.
  bool is_one_lipschitz() const;

 private:
  struct Flat {
    SdfKind kind;
    bool moved;  // pose is not the identity
    Transform pose;
    Real a = 0;  // radius, major radius, or k
    Real b = 0;  // half length or minor radius
    Vec3 half_extents = Vec3::Zero();
    std::uint32_t first = 0;  // children: nodes_[first, first + count); a leaf's table index
    std::uint32_t count = 0;
    GridInterpolation interpolation = GridInterpolation::tricubic;
  };
  sdf::Sample sample_node(std::uint32_t i, const Vec3& p, Real time) const;
  Real distance_node(std::uint32_t i, const Vec3& p, Real time) const;
  void flatten(const SdfNode& node, std::uint32_t slot, const std::string& path, int depth);
  Aabb bounds_of(std::uint32_t i) const;

  std::vector<Flat> nodes_;
  std::vector<std::shared_ptr<const SdfGrid>> grids_;
  std::vector<std::shared_ptr<const NeuralSdf>> networks_;
  std::vector<std::shared_ptr<const VdbLevelSet>> level_sets_;
  Aabb bounds_;
  Real reach_ = std::numeric_limits<Real>::infinity();
  Real changes_from_ = std::numeric_limits<Real>::infinity();
  Real changes_until_ = -std::numeric_limits<Real>::infinity();
};

}  // namespace tumble
