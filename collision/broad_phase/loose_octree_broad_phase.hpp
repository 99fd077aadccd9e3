// Loose octree broad phase.
//
// Based on: T. Ulrich, "Loose Octrees", Game Programming Gems (M. DeLoura ed.), Charles River
// Media, 2000, section 4.11; and C. Ericson, "Real-Time Collision Detection", Morgan Kaufmann
// 2005, section 7.3.6.
//
// Each node is a cubic cell of half side h; its loose bound is the cell scaled by (1 + k) about
// its centre, i.e. the cell grown by the slack k h on every side (k in [0.5, 1], the loose
// factor). A box of largest half extent r whose centre lies in a cell is inside that
// cell's loose bound whenever r <= k h, wherever in the cell the centre is. So a box's level
// follows from its size alone (Ulrich's rule): the deepest level L with r <= k H / 2^L, where H
// is the root's half side. For k = 1 that is L = floor(log2(H / r)).
//
// The tree is sparse and adaptive: a node is split only when it holds more than
// `max_node_objects` proxies and its depth is below `max_depth`; a box descends to min(its size
// level, the deepest split node on its centre's path). Children are created on demand, empty ones
// are freed, and a split node whose whole subtree holds at most max_node_objects / 2 proxies is
// merged back (hysteresis, so a node does not flip every step).
//
// The world adapts: a box outside the root's loose bound (or whose centre is outside the root's
// cell) makes the root grow by re-rooting (a new root of twice the side, the old root one of
// its octants; no cell changes and no proxy moves), and a root
// that holds nothing but one child is dropped so the world shrinks back. Boxes with an infinite
// (or absurdly large) coordinate, such as planes, live in a separate list tested against all.
//
// Storage: nodes in a flat array addressed by index, proxies in a flat slot array; each node
// keeps an intrusive doubly linked list of its proxies (O(1) move between nodes). An update
// leaves a box where it is while it stays inside its node's loose bound and has not shrunk
// enough to go deeper: the point of looseness is that coherent motion rarely moves a proxy.
//
// find_pairs. Two boxes in different nodes overlap only if each node's loose bound meets the
// other's box, and the nodes may be an ancestor/descendant pair OR two unrelated nodes whose
// loose bounds overlap (neighbouring cells: loose bounds of adjacent cells overlap by 2 k h).
// So "own node, ancestors and descendants" alone would miss pairs across neighbouring cells
// (tests/broad_phase/loose_octree_test.cpp has a case that fails that way); the search has to
// visit every node whose bound the box touches. To find each pair exactly once, find_pairs
// first writes the tree out in depth-first preorder: dynamic proxies into one array, static
// proxies into another, each node owning a contiguous range of each and knowing where its
// subtree ends (a skip index) and the exact bounds of the dynamic and of the static boxes of its
// own list and of its subtree (tighter than the loose bound, and exact, so they prune safely).
// Then each dynamic proxy a, at preorder position i in the dynamic array, reports
//   - every dynamic proxy at position j > i that it overlaps: the pair {a, b} is seen from the
//     one earlier in preorder and never from the other. Every node before a's node in preorder
//     is an ancestor of it or in a subtree that ends before it, so its dynamic range lies before
//     i: the walk for dynamic partners starts at a's own node and only goes forward;
//   - every static proxy it overlaps, walking the static bounds from the root (static proxies
//     never search, so this is the only time such a pair is seen, and static-static pairs are
//     never looked at).
// All dynamic proxies of a node share one walk, with the union of their boxes (a node's boxes
// are close together, as its cell is small for their size). A node's own list longer than a
// few boxes is sorted by min along its longest axis, so a scan of it stops at the first box
// that starts beyond the query's end.
//
// query and ray_cast walk the live tree, pruning by loose bounds (which always contain every
// box of the subtree), so they are correct between updates without a find_pairs.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/broad_phase/broad_phase.hpp"
#include "collision/broad_phase/packed_proxy_tree.hpp"
#include "collision/broad_phase/proxy_slots.hpp"

namespace tumble {

class LooseOctreeBroadPhase final : public BroadPhase {
 public:
  // looseness: the loose factor k in [0.5, 1]; the loose bound is the cell scaled by (1 + k).
  // max_node_objects: n_max, split a node holding more proxies than this.
  // max_depth: d_max, never split a node at this depth (the root is depth 0).
  explicit LooseOctreeBroadPhase(Real looseness = 1.0, int max_node_objects = 32,
                                 int max_depth = 20);

  void insert(std::int32_t id, const Aabb& box, bool is_static) override;
  void remove(std::int32_t id) override;
  void update(std::int32_t id, const Aabb& box) override;
  void find_pairs(std::vector<ProxyPair>& out) override;
  void query(const Aabb& box, std::vector<std::int32_t>& out) const override;
  void ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                std::vector<std::int32_t>& out) const override;

  // Inspection, for tests and tuning.
  struct Stats {
    int nodes = 0;                 // live nodes
    int depth = 0;                 // deepest live node (root = 0)
    int unbounded = 0;             // proxies in the separate list of infinite boxes
    std::int64_t box_tests = 0;    // proxy-proxy box tests in the last find_pairs
    std::int64_t node_visits = 0;  // node bound tests in the last find_pairs
  };
  Stats stats() const;
  // Depth of the node holding the proxy (root = 0), or -1 if it is in the unbounded list.
  int level_of(std::int32_t id) const;
  // The loose bound of the node holding the proxy (the whole space for an unbounded proxy).
  Aabb loose_bound_of(std::int32_t id) const;
  Real root_half_size() const;
  Vec3 root_centre() const;
  // The level a box of this size belongs at under Ulrich's rule, given the current root, if
  // every node on its path were split: the largest L <= max_depth with r <= k H / 2^L.
  int size_level(const Aabb& box) const;

 private:
  struct Node {
    Aabb loose;  // cell scaled by (1 + k); contains every box in the subtree
    Vec3 centre = Vec3::Zero();
    Real half = 0;  // half side of the (tight) cell
    std::int32_t child[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
    std::int32_t parent = -1;
    std::int32_t head = -1;  // first proxy slot of this node's list
    std::int32_t count = 0;  // proxies in this node's list
    std::int32_t static_count = 0;
    std::int32_t pre = 0;  // preorder index in the last pack()
    std::int32_t depth = 0;
    bool split = false;  // proxies small enough go to children
  };
  using Proxy = detail::LinkedProxy;

  static bool is_unbounded(const Aabb& box);
  Real max_half_extent(const Aabb& box) const;

  std::int32_t new_node();
  void free_node(std::int32_t n);
  std::int32_t make_child(std::int32_t parent, int octant);
  void child_geometry(const Node& parent, int octant, Vec3& centre, Aabb& loose) const;
  void set_root_for(const Aabb& box);
  bool world_holds(const Aabb& box) const;
  void grow_to_contain(const Aabb& box);
  void link(std::int32_t slot, std::int32_t node);
  void unlink(std::int32_t slot);
  void place(std::int32_t slot);
  std::int32_t descend(std::int32_t start, const Aabb& box) const;
  void split_node(std::int32_t n);
  std::int32_t maintain(std::int32_t n);
  void collapse_root();
  void pack();
  void query_node(std::int32_t n, const Aabb& box, std::vector<std::int32_t>& out) const;
  void ray_node(std::int32_t n, const Vec3& o, const Vec3& d, Real max_t,
                std::vector<std::int32_t>& out) const;

  Real k_;
  int n_max_;
  int d_max_;

  std::vector<Node> nodes_;
  std::vector<std::int32_t> free_nodes_;
  std::int32_t root_ = -1;
  detail::ProxySlots slots_;
  std::vector<std::int32_t> unbounded_;  // slots of proxies with infinite boxes

  // find_pairs scratch, reused so a warmed-up step allocates nothing.
  detail::PackedProxyTree packed_;
  std::vector<std::int32_t> stack_;
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint64_t> sort_scratch_;
};

}  // namespace tumble
