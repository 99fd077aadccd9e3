// Dynamic AABB tree: a binary bounding volume hierarchy over boxes that can be inserted, removed
// and moved one at a time (incremental updates: refit, rebuild, insert and delete).
//
// Sources:
// - Insertion picks the sibling that minimises the growth of the tree's surface-area cost by
//   branch and bound: Bittner, Hapala, Havran, "Fast Insertion-Based Optimization of Bounding
//   Volume Hierarchies", Computer Graphics Forum 32(1), 2013, section 3.1; presented for games
//   in Erin Catto, "Dynamic Bounding Volume Hierarchies", GDC 2019 ("sibling selection by
//   surface area cost").
// - After an insertion or removal, every ancestor is refitted and then rotated: a child is
//   swapped with a grandchild (or two grandchildren swapped) when that lowers the surface area.
//   Kopta, Ize, Spjut, Brunvand, Davis, Kensler, "Fast, Effective BVH Updates for Animated
//   Scenes", I3D 2012, section 3.
// - rebuild() is a top-down build with the surface area heuristic evaluated at 16 bin
//   boundaries per axis: Wald, "On fast Construction of SAH-based Bounding Volume
//   Hierarchies", IEEE Symposium on Interactive Ray Tracing 2007.
// - The pair traversals descend two hierarchies together: at each pair of nodes, descend the
//   node with the larger surface area.
//
// Layout: nodes live in one flat array and refer to each other by index, never by pointer, so
// the array can grow and the tree can be copied; freed nodes form a free list threaded through
// `parent`. A node is exactly one cache line. Every traversal uses an explicit stack with inline
// storage, so queries allocate nothing.
//
// The tree stores whatever boxes it is given. Fattening them for moving objects is the caller's
// policy (see DynamicTreeBroadPhase). Boxes must be finite: a box with an infinite side has an
// infinite area and the cost arithmetic would produce NaN, so callers keep such boxes elsewhere.
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "collision/aabb.hpp"
#include "collision/broad_phase/tree_box.hpp"

namespace tumble {

// The segment origin + t * direction, t in [0, max_t], prepared for testing many boxes. The
// arithmetic is exactly that of segment_touches_aabb (the reciprocal is computed once instead of
// per box, which gives the same bits), so the test is monotone in the box: a segment that
// touches a leaf's box also touches every enclosing node's box, and no hit is lost to rounding.
struct SegmentProbe {
  Real origin[3];
  Real inv[3];
  bool parallel[3];
  Real max_t;

  SegmentProbe(const Vec3& o, const Vec3& d, Real t) : max_t(t) {
    for (int k = 0; k < 3; ++k) {
      origin[k] = o[k];
      parallel[k] = d[k] == 0;
      inv[k] = parallel[k] ? Real(0) : Real(1) / d[k];
    }
  }
  bool touches(const TreeBox& b) const {
    Real t_enter = 0;
    Real t_exit = max_t;
    for (int k = 0; k < 3; ++k) {
      if (parallel[k]) {
        if (origin[k] < b.min[k] || origin[k] > b.max[k])
          return false;
        continue;
      }
      Real t0 = (b.min[k] - origin[k]) * inv[k];
      Real t1 = (b.max[k] - origin[k]) * inv[k];
      if (t0 > t1)
        std::swap(t0, t1);
      t_enter = std::max(t_enter, t0);
      t_exit = std::min(t_exit, t1);
      if (t_enter > t_exit)
        return false;
    }
    return true;
  }
};

namespace tree_detail {

// A LIFO stack with inline storage for the common depth; deeper traversals (a degenerate tree)
// spill into a vector instead of overflowing. Elements are plain values (no initialisation).
template <class T, std::size_t N>
class TraversalStack {
 public:
  void push(const T& v) {
    if (size_ < N) [[likely]]
      inline_[size_] = v;
    else
      spill(v);
    ++size_;
  }
  T pop() {
    --size_;
    if (size_ < N) [[likely]]
      return inline_[size_];
    return unspill();
  }
  bool empty() const { return size_ == 0; }

 private:
  // Out of line, so that push and pop stay small enough to inline in the traversal loops.
  [[gnu::noinline]] void spill(const T& v) { spill_.push_back(v); }
  [[gnu::noinline]] T unspill() {
    const T v = spill_.back();
    spill_.pop_back();
    return v;
  }

  std::array<T, N> inline_;
  std::vector<T> spill_;
  std::size_t size_ = 0;
};

struct NodePair {
  std::int32_t a;
  std::int32_t b;
};

// A pair of non-negative ids packed so that integer order is (a, b) order.
inline std::uint64_t pair_key(std::int32_t a, std::int32_t b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}
inline std::int32_t key_first(std::uint64_t k) {
  return static_cast<std::int32_t>(k >> 32);
}
inline std::int32_t key_second(std::uint64_t k) {
  return static_cast<std::int32_t>(k & 0xffffffffu);
}

// Sorts pair keys whose ids are all below `id_bound`: a counting sort on the first id, then each
// bucket (the pairs of one proxy, a handful) sorted on the second id. Two passes over the keys
// instead of the five to eight of a byte-wise radix sort. When there are many more keys than
// ids (dense overlap), two stable counting sorts instead (second id, then first). `scratch` and
// `counts` are reusable buffers; nothing is allocated once they have grown.
void sort_pair_keys(std::vector<std::uint64_t>& keys, std::int32_t id_bound,
                    std::vector<std::uint64_t>& scratch, std::vector<std::int32_t>& counts);

}  // namespace tree_detail

class DynamicAabbTree {
 public:
  static constexpr std::int32_t null_node = -1;

  struct alignas(64) Node {
    TreeBox box;          // a leaf: the box it was given; internal: union of the children
    std::int32_t parent;  // null_node at the root; the next free node while on the free list
    std::int32_t child1;  // null_node for a leaf
    std::int32_t child2;  // a leaf: the caller's payload (user data)
    std::int32_t height;  // 0 for a leaf, 1 + max of the children otherwise, -1 when free

    bool is_leaf() const { return child1 == null_node; }
  };
  static_assert(sizeof(Node) == 64, "one node, one cache line");

  struct Options {
    bool rotate = true;  // tree rotations after insert/remove (off only to measure their worth)
  };

  DynamicAabbTree() = default;
  explicit DynamicAabbTree(const Options& options) : options_(options) {}

  // Inserts a leaf holding `box` and `user_data`; returns its node index, stable until the leaf
  // is destroyed or the whole tree is rebuilt (rotations and partial rebuilds move internal
  // nodes only).
  std::int32_t create_leaf(const TreeBox& box, std::int32_t user_data);
  void destroy_leaf(std::int32_t leaf);
  // Gives the leaf a new box: removes it and reinserts it where the cost is lowest.
  void move_leaf(std::int32_t leaf, const TreeBox& box);
  // Gives the leaf a new box where it stands: its ancestors are refitted and rotated upwards
  // until one comes out unchanged (Kopta et al.'s refit-with-rotations update). Much cheaper
  // than move_leaf, and as good for a small move; a teleport is better served by move_leaf.
  void refit_leaf(std::int32_t leaf, const TreeBox& box);
  // Gives the leaf a new box without restructuring; ancestors are stale until refit().
  void set_leaf_box(std::int32_t leaf, const TreeBox& box) { nodes_[leaf].box = box; }

  // Recomputes every internal box and height bottom-up, O(n). Topology is unchanged.
  void refit();
  // Rebuilds the whole tree top-down by binned SAH, O(n log n), into a fresh array in depth-first
  // order: a subtree is a contiguous run of nodes and the top levels share a few cache lines,
  // which is what makes traversals of a large tree fast. Every leaf gets a new index, reported
  // as leaf_moved(user_data, new_leaf) for each leaf.
  template <class LeafMoved>
  void rebuild(LeafMoved&& leaf_moved) {
    rebuild_compact();
    for (std::int32_t i = 0; i < static_cast<std::int32_t>(nodes_.size()); ++i) {
      if (nodes_[i].height == 0)
        leaf_moved(nodes_[i].child2, i);
    }
  }
  // Rebuilds the subtree under `node` in place (a partial rebuild: leaf indices are kept), then
  // refits the heights of its ancestors.
  void rebuild_subtree(std::int32_t node);
  void clear();

  // visit(leaf) for every leaf whose box overlaps `box` (closed intervals).
  template <class Visit>
  void query(const TreeBox& box, Visit&& visit) const;
  // visit(leaf) for every leaf whose box the segment touches (SegmentProbe).
  template <class Visit>
  void ray_cast(const SegmentProbe& segment, Visit&& visit) const;

  std::int32_t root() const { return root_; }
  const Node& node(std::int32_t i) const { return nodes_[i]; }
  const TreeBox& box(std::int32_t i) const { return nodes_[i].box; }
  std::int32_t user_data(std::int32_t leaf) const { return nodes_[leaf].child2; }
  std::int32_t node_capacity() const { return static_cast<std::int32_t>(nodes_.size()); }
  std::int32_t leaf_count() const { return leaf_count_; }
  std::int32_t height() const { return root_ == null_node ? 0 : nodes_[root_].height; }
  // Sum of the internal nodes' surface areas over the root's: the SAH cost of the tree (the
  // expected number of internal nodes a random ray visits, Goldsmith and Salmon 1987). 0 for a
  // tree of fewer than two leaves.
  Real sah_cost() const;

 private:
  std::int32_t allocate_node();
  void free_node(std::int32_t i);
  void insert_leaf(std::int32_t leaf);
  void remove_leaf(std::int32_t leaf);
  std::int32_t find_best_sibling(const TreeBox& box) const;
  void refit_and_rotate_upwards(std::int32_t i);
  bool rotate(std::int32_t a);  // true if it rotated
  void replace_child(std::int32_t parent, std::int32_t old_child, std::int32_t new_child);
  void rebuild_compact();
  void collect_build_refs(std::int32_t node, bool free_internal);
  std::int32_t build_binned(std::int32_t parent, bool compact);

  struct HeapEntry {
    Real inherited;  // cost added to every ancestor if the new leaf goes below this node
    std::int32_t node;
  };
  struct BuildRef {  // a copy of the leaf, so the build reads memory in order
    TreeBox box;
    std::int32_t leaf;
    std::int32_t user_data;
  };
  struct BuildTask {
    std::int32_t parent;
    std::int32_t begin;
    std::int32_t end;
    bool first_child;
  };

  Options options_;
  std::vector<Node> nodes_;
  std::int32_t root_ = null_node;
  std::int32_t free_list_ = null_node;
  std::int32_t leaf_count_ = 0;
  // Reused scratch space (insertion's priority queue, rebuild's work lists).
  mutable std::vector<HeapEntry> heap_;
  std::vector<BuildRef> build_refs_;
  std::vector<BuildTask> build_tasks_;
  std::vector<std::int32_t> scratch_nodes_;
};

template <class Visit>
void DynamicAabbTree::query(const TreeBox& box, Visit&& visit) const {
  if (root_ == null_node)
    return;
  tree_detail::TraversalStack<std::int32_t, 256> stack;
  stack.push(root_);
  while (!stack.empty()) {
    const Node& n = nodes_[stack.pop()];
    if (!n.box.overlaps(box))
      continue;
    if (n.is_leaf()) {
      visit(static_cast<std::int32_t>(&n - nodes_.data()));
    } else {
      stack.push(n.child2);
      stack.push(n.child1);
    }
  }
}

template <class Visit>
void DynamicAabbTree::ray_cast(const SegmentProbe& segment, Visit&& visit) const {
  if (root_ == null_node)
    return;
  tree_detail::TraversalStack<std::int32_t, 256> stack;
  stack.push(root_);
  while (!stack.empty()) {
    const Node& n = nodes_[stack.pop()];
    if (!segment.touches(n.box))
      continue;
    if (n.is_leaf()) {
      visit(static_cast<std::int32_t>(&n - nodes_.data()));
    } else {
      stack.push(n.child2);
      stack.push(n.child1);
    }
  }
}

// Dual traversal of two trees, iterative: visit(leaf_a, leaf_b) for every leaf of `a` and leaf of
// `b` whose boxes overlap, each pair once. At a pair of nodes the one with the larger surface
// area is split, which keeps the two boxes of similar size and prunes soonest. For tree vs tree
// (static against dynamic proxies, mesh against mesh).
template <class Visit>
void for_each_overlapping_leaf_pair(const DynamicAabbTree& a, const DynamicAabbTree& b,
                                    Visit&& visit) {
  using Pair = tree_detail::NodePair;
  if (a.root() == DynamicAabbTree::null_node || b.root() == DynamicAabbTree::null_node)
    return;
  if (!a.box(a.root()).overlaps(b.box(b.root())))
    return;
  if (a.node(a.root()).is_leaf() && b.node(b.root()).is_leaf()) {
    visit(a.root(), b.root());
    return;
  }
  // Only pairs whose boxes overlap and that are not both leaves are pushed; leaf pairs are
  // visited on the spot.
  tree_detail::TraversalStack<Pair, 256> stack;
  stack.push({a.root(), b.root()});
  while (!stack.empty()) {
    const Pair p = stack.pop();
    const DynamicAabbTree::Node& na = a.node(p.a);
    const DynamicAabbTree::Node& nb = b.node(p.b);
    const bool split_a =
        nb.is_leaf() || (!na.is_leaf() && na.box.half_area() >= nb.box.half_area());
    if (split_a) {
      for (const std::int32_t c : {na.child2, na.child1}) {
        const DynamicAabbTree::Node& nc = a.node(c);
        if (!nc.box.overlaps(nb.box))
          continue;
        if (nc.is_leaf() && nb.is_leaf())
          visit(c, p.b);
        else
          stack.push({c, p.b});
      }
    } else {
      for (const std::int32_t c : {nb.child2, nb.child1}) {
        const DynamicAabbTree::Node& nc = b.node(c);
        if (!na.box.overlaps(nc.box))
          continue;
        if (na.is_leaf() && nc.is_leaf())
          visit(p.a, c);
        else
          stack.push({p.a, c});
      }
    }
  }
}

// Self-collision traversal: visit(leaf_a, leaf_b) for every unordered pair of distinct leaves of
// `tree` whose boxes overlap, each pair once (leaf_a, leaf_b in no particular order). A node
// against itself expands to its two children against themselves and against each other; a pair
// of different nodes proceeds as in the dual traversal.
template <class Visit>
void for_each_overlapping_leaf_pair(const DynamicAabbTree& tree, Visit&& visit) {
  using Pair = tree_detail::NodePair;
  if (tree.root() == DynamicAabbTree::null_node)
    return;
  tree_detail::TraversalStack<Pair, 256> stack;
  stack.push({tree.root(), tree.root()});
  while (!stack.empty()) {
    const Pair p = stack.pop();
    const DynamicAabbTree::Node& na = tree.node(p.a);
    if (p.a == p.b) {
      if (na.is_leaf())
        continue;
      const DynamicAabbTree::Node& c1 = tree.node(na.child1);
      const DynamicAabbTree::Node& c2 = tree.node(na.child2);
      if (!c2.is_leaf())
        stack.push({na.child2, na.child2});
      if (!c1.is_leaf())
        stack.push({na.child1, na.child1});
      if (c1.box.overlaps(c2.box)) {
        if (c1.is_leaf() && c2.is_leaf())
          visit(na.child1, na.child2);
        else
          stack.push({na.child1, na.child2});
      }
      continue;
    }
    const DynamicAabbTree::Node& nb = tree.node(p.b);
    // Here the two differ and at least one is internal (leaf pairs are visited, not pushed).
    const bool split_a =
        nb.is_leaf() || (!na.is_leaf() && na.box.half_area() >= nb.box.half_area());
    const DynamicAabbTree::Node& split = split_a ? na : nb;
    const std::int32_t other = split_a ? p.b : p.a;
    const DynamicAabbTree::Node& no = split_a ? nb : na;
    for (const std::int32_t c : {split.child2, split.child1}) {
      const DynamicAabbTree::Node& nc = tree.node(c);
      if (!nc.box.overlaps(no.box))
        continue;
      if (nc.is_leaf() && no.is_leaf())
        visit(c, other);
      else
        stack.push({c, other});
    }
  }
}

}  // namespace tumble
