// Linear BVH broad phase, the "lbvh" choice of the scene format: no incremental structure at all;
// every find_pairs builds a hierarchy from scratch over the current boxes and enumerates the
// overlapping pairs by the tree's self traversal.
//
// Two builders, chosen by a constructor parameter:
// - morton_karras (default): 30-bit Morton codes of the box centres, normalised to the bounds of
//   the centres (Morton, "A computer oriented geodetic data base...", IBM 1966); an LSD radix
//   sort of the codes; the radix-tree topology of Karras, "Maximizing Parallelism in the
//   Construction of BVHs, Octrees, and k-d Trees", HPG 2012, section 4 (each internal node finds
//   its range and split from the codes alone, so it is O(n) and needs no recursion); then boxes
//   bottom-up (each internal node is finished by the second of its children to arrive).
// - binned_sah: top-down surface area heuristic with 16 bins per axis (Wald, "On fast
//   Construction of SAH-based Bounding Volume Hierarchies", RT 2007).
// Both give a binary tree with one proxy per leaf, laid out the same way, so the traversals
// are shared. Build time and tree quality are the trade-off (see docs and stats()).
//
// Proxies are kept in dense arrays (swap-remove), one for dynamic, one for static, one for boxes
// with an infinite side. The dynamic hierarchy is rebuilt at every find_pairs; the static one
// only when a static proxy was inserted, removed or moved. Pairs: self traversal of the dynamic
// hierarchy, dual traversal dynamic vs static (static pairs are never visited), and the
// infinite list against everything. When an eighth or more of all pairs overlapped at the last
// call (everything piled in one place), all pairs are enumerated in id order instead: no
// hierarchy prunes there, and the output comes out sorted. query() and ray_cast() traverse the
// hierarchies built at
// the last find_pairs; if a proxy changed since, they scan the dense arrays instead (correct,
// O(n)), since this structure has nothing to update incrementally.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/broad_phase/broad_phase.hpp"
#include "collision/broad_phase/dynamic_aabb_tree.hpp"

namespace tumble {

namespace lbvh {

// Spreads the low 10 bits of v so that bit i lands on bit 3i.
inline std::uint32_t expand_bits_10(std::uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

// Interleaves three 10-bit cell coordinates into a 30-bit Morton code, x in the most significant
// position of each triple: bits (x9 y9 z9 x8 y8 z8 ... x0 y0 z0).
inline std::uint32_t morton_code(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  return (expand_bits_10(x) << 2) | (expand_bits_10(y) << 1) | expand_bits_10(z);
}

// Cell of a coordinate in [lo, lo + 1024 / scale]: floor((c - lo) * scale) clamped to [0, 1023].
// scale == 0 (all centres equal on this axis) gives cell 0.
inline std::uint32_t morton_cell(Real c, Real lo, Real scale) {
  const Real q = (c - lo) * scale;
  if (!(q > 0))
    return 0;
  return q >= Real(1023) ? 1023u : static_cast<std::uint32_t>(q);
}

// A node of the hierarchy. A child reference >= 0 is an internal node, < 0 is leaf ~ref.
// Internal node 0 is the root when there are two or more leaves.
struct Node {
  TreeBox box;
  std::int32_t left;
  std::int32_t right;
};

struct Leaf {
  TreeBox box;
  std::int32_t id;
};

// A hierarchy over n leaves: n - 1 internal nodes.
struct Hierarchy {
  std::vector<Node> nodes;
  std::vector<Leaf> leaves;

  // The root as a child reference (~0 for a single leaf); only valid if !leaves.empty().
  std::int32_t root() const { return leaves.size() == 1 ? ~0 : 0; }
  const TreeBox& box(std::int32_t ref) const {
    return ref >= 0 ? nodes[ref].box : leaves[~ref].box;
  }
  // Sum of the internal nodes' surface areas over the root's (0 below two leaves).
  Real sah_cost() const;
};

// Reused buffers of the builders; nothing is allocated once they have grown.
struct BuildScratch {
  std::vector<std::uint64_t> keys;
  std::vector<std::uint64_t> keys_tmp;
  std::vector<std::uint32_t> codes;
  std::vector<std::int32_t> parents;  // internal nodes' parents, then leaves' parents
  std::vector<std::uint8_t> visits;
  struct Ref {
    TreeBox box;
    std::int32_t id;
  };
  std::vector<Ref> refs;
  struct Task {
    std::int32_t node;
    std::int32_t begin;
    std::int32_t end;
  };
  std::vector<Task> tasks;
};

// Karras 2012 topology for sorted, distinct-or-not 30-bit codes (ties broken by index, as in the
// paper): fills nodes[0..n-2].left/right and the parent table (n - 1 internal entries, then n
// leaf entries; the root's parent is -1). Boxes are not touched.
void karras_topology(const std::uint32_t* codes, std::int32_t n, Node* nodes,
                     std::int32_t* parents);

// The two builders over boxes[i] with ids[i], i < n.
void build_morton_karras(const TreeBox* boxes, const std::int32_t* ids, std::int32_t n,
                         Hierarchy& out, BuildScratch& scratch);
void build_binned_sah(const TreeBox* boxes, const std::int32_t* ids, std::int32_t n, Hierarchy& out,
                      BuildScratch& scratch);

}  // namespace lbvh

class LinearBvhBroadPhase final : public BroadPhase {
 public:
  enum class Builder : std::uint8_t { morton_karras, binned_sah };

  explicit LinearBvhBroadPhase(Builder builder = Builder::morton_karras) : builder_(builder) {}

  void insert(std::int32_t id, const Aabb& box, bool is_static) override;
  void remove(std::int32_t id) override;
  void update(std::int32_t id, const Aabb& box) override;
  void find_pairs(std::vector<ProxyPair>& out) override;
  void query(const Aabb& box, std::vector<std::int32_t>& out) const override;
  void ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                std::vector<std::int32_t>& out) const override;

  // Timings of the last find_pairs, for the builders' comparison and for statistics.
  struct Stats {
    double build_seconds = 0;     // building the dynamic (and, if changed, static) hierarchy
    double traverse_seconds = 0;  // traversals, infinite list, sort of the pairs
    std::int64_t builds = 0;
    std::int64_t static_builds = 0;
    std::int64_t dense = 0;  // find_pairs calls answered by enumerating all pairs
  };
  const Stats& stats() const { return stats_; }
  const lbvh::Hierarchy& dynamic_hierarchy() const { return dynamic_; }
  const lbvh::Hierarchy& static_hierarchy() const { return static_; }

 private:
  enum class Kind : std::uint8_t { none, dynamic, fixed, infinite };
  struct Proxy {
    Kind kind = Kind::none;
    bool is_static = false;
    std::int32_t slot = -1;  // index in the dense list of its kind
  };
  struct DenseList {  // boxes and ids side by side, swap-remove
    std::vector<TreeBox> boxes;
    std::vector<std::int32_t> ids;
  };

  DenseList& list_of(Kind k);
  void add_to(Kind k, std::int32_t id, const TreeBox& box);
  void remove_from(std::int32_t id);
  void build(lbvh::Hierarchy& h, const DenseList& list);
  void find_pairs_dense(std::vector<ProxyPair>& out);
  void emit(std::int32_t a, std::int32_t b) {
    keys_.push_back(a < b ? tree_detail::pair_key(a, b) : tree_detail::pair_key(b, a));
  }

  Builder builder_;
  std::vector<Proxy> proxies_;  // indexed by id
  DenseList dynamic_list_;
  DenseList static_list_;
  DenseList infinite_list_;
  std::vector<std::uint8_t> infinite_static_;  // parallel to infinite_list_
  lbvh::Hierarchy dynamic_;
  lbvh::Hierarchy static_;
  lbvh::BuildScratch scratch_;
  bool static_dirty_ = true;
  bool fresh_ = false;  // nothing changed since the hierarchies were built
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint64_t> keys_tmp_;
  std::vector<std::int32_t> sort_counts_;
  std::size_t last_pair_count_ = 0;
  Stats stats_;
};

}  // namespace tumble
