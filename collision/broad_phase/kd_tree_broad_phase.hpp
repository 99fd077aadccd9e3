// k-d tree broad phase with SAH splits.
//
// Based on: J. D. MacDonald and K. S. Booth, "Heuristics for ray tracing using space
// subdivision", The Visual Computer 6(3), 1990 (the cost heuristic); I. Wald and V. Havran, "On
// building fast kd-trees for ray tracing, and on doing that in O(N log N)", IEEE Symposium on
// Interactive Ray Tracing 2006 (candidate planes at box boundaries, termination when splitting
// does not pay); I. Wald, "On fast construction of SAH-based bounding volume hierarchies", IEEE
// RT 2007 (binning); C. Waechter and A. Keller, "Instant ray tracing: the bounding interval
// hierarchy", EGSR 2006 (boxes that straddle a plane).
//
// Build (top down). At a node holding n boxes with bounds B, each axis a is cut into `bins`
// equal bins over B; every box's min and max are counted in the bins, and the bins-1 planes
// between bins are the candidates (binned box boundaries: O(n) per axis per level instead of the
// O(n log n) sort of an exact sweep). A plane p sends a box left if box.max[a] <= p, right if
// box.min[a] >= p, and otherwise the box straddles p and stays at the node.
//
// Cost (n_L V_L + n_R V_R with V a volume, extended): a proxy's own box is the query in a broad
// phase, and a box of half extent r overlaps a region R exactly when its centre is in R grown
// by r (the Minkowski sum). So V is taken as the volume of the region grown by the mean half
// extent of the node's boxes, not the bare volume (which is right only for point queries) and
// not the surface area (which is the hit probability of a random ray, not of a box).
// Straddlers are met by every query that reaches the node, so they are charged the parent's
// volume:
//     C(p) = C_trav + (n_L V'_L + n_R V'_R + n_S V') / V',   leaf cost = n.
// The node is split at the cheapest candidate if n > leaf_size and C < n; otherwise it is a
// leaf. For a plane on axis a the other two factors of V' cancel, so C compares lengths.
//
// Straddlers: kept at the internal node (a straddler list, as a bounding interval hierarchy
// keeps one box per child) rather than copied into both children. Each proxy then lives in
// exactly one node, so no pair can be found twice and nothing needs deduplicating, an update
// moves one list entry, and memory stays O(n). The price: a straddler list is a thin slab
// across the node's cell, met by every search that reaches the node, and a fresh tree of
// uniform boxes keeps about 30% of them at internal nodes (a box crosses some plane on its way
// down). Three things keep that cheap, and the straddler test in
// tests/broad_phase/kd_tree_test.cpp checks the result (equal to brute force, and under a
// tenth of the n(n-1)/2 box tests of brute force): each straddler searches with its own box (the
// union of a slab would meet most of the subtree), every node's own list is tested only when its
// exact own bound is hit, and a long own list is sorted by min along its longest axis so a scan of
// it stops early (a sweep within the slab).
//
// Motion. Two policies (KdTreeOptions::rebuild):
//  - every_step: rebuild the whole tree in every find_pairs;
//  - on_degradation (default): keep the planes, and on update move a box to the node whose cell
//    holds it (up to the first ancestor whose cell contains it, down while it is on one side of
//    the plane); the subtree bounds used for pruning are recomputed exactly in every find_pairs
//    (that is the "refit"). The tree is rebuilt when the measured work of find_pairs (box tests
//    + node visits) per unit of output (pairs + proxies) exceeds `degradation` times what it was
//    right after the last build, or when many proxies were inserted since.
//  Measured (uniform boxes of half size ~1, moving 0.05 per step, update of every box plus
//  find_pairs, Release, 2-core VM): 1k boxes 0.10 ms (refit) vs 0.23 ms (rebuild every step),
//  10k 1.3 vs 3.1 ms, 100k 20 vs 54 ms. Refit with the trigger is 2.3-2.7x faster for coherent
//  motion, so it is the default; the build itself (binned SAH over all boxes) is what a
//  rebuild every step pays.
//
// find_pairs is the same each-pair-once preorder search as the loose octree's (see
// loose_octree_broad_phase.hpp): the nodes are stored in preorder already, each dynamic proxy
// at preorder position i reports the static proxies it overlaps and the dynamic ones at
// positions j > i; the proxies of a leaf share one walk, a straddler walks alone. Infinite
// boxes (planes) are kept in a separate list and tested against everything.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/broad_phase/broad_phase.hpp"
#include "collision/broad_phase/packed_proxy_tree.hpp"
#include "collision/broad_phase/proxy_slots.hpp"

namespace tumble {

struct KdTreeOptions {
  enum class Rebuild : std::uint8_t { every_step, on_degradation };

  int leaf_size = 16;         // proxies; a node with at most this many is never split
  int bins = 32;              // candidate planes per axis are the bins - 1 bin boundaries
  Real traversal_cost = 1.0;  // cost of visiting a node, in units of one box test
  int max_depth = 48;         // hard limit, for layouts no plane can separate
  Rebuild rebuild = Rebuild::on_degradation;
  Real degradation = 1.5;  // rebuild when work per pair or proxy grows by this factor
};

class KdTreeBroadPhase final : public BroadPhase {
 public:
  explicit KdTreeBroadPhase(const KdTreeOptions& options = {});

  void insert(std::int32_t id, const Aabb& box, bool is_static) override;
  void remove(std::int32_t id) override;
  void update(std::int32_t id, const Aabb& box) override;
  void find_pairs(std::vector<ProxyPair>& out) override;
  void query(const Aabb& box, std::vector<std::int32_t>& out) const override;
  void ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                std::vector<std::int32_t>& out) const override;

  // Inspection, for tests and tuning.
  struct Stats {
    int nodes = 0;
    int leaves = 0;
    int depth = 0;                 // deepest node (root = 0)
    int straddlers = 0;            // proxies held by internal nodes
    int unbounded = 0;             // proxies in the separate list of infinite boxes
    std::int64_t rebuilds = 0;     // builds since construction
    std::int64_t box_tests = 0;    // proxy-proxy box tests in the last find_pairs
    std::int64_t node_visits = 0;  // node bound tests in the last find_pairs
  };
  Stats stats() const;

  struct NodeInfo {
    int depth = 0;
    bool leaf = true;
    int axis = -1;    // split axis of an internal node
    Real split = 0;   // split plane of an internal node
    int own = 0;      // proxies held by this node (straddlers if internal)
    int subtree = 0;  // proxies in the whole subtree
  };
  // Every node in preorder.
  std::vector<NodeInfo> node_infos() const;
  // The cost rule applied at build time to a set of boxes: the cheapest candidate plane's cost
  // and the leaf cost (n). Exposed so tests can check the rule on their own layouts.
  struct SplitChoice {
    int axis = -1;
    Real plane = 0;
    Real cost = 0;
    Real leaf_cost = 0;
  };
  SplitChoice best_split(const std::vector<Aabb>& boxes) const;
  // Builds now (also done automatically by find_pairs when due).
  void rebuild();

 private:
  struct Node {
    Aabb cell;  // closed region holding every box of the subtree (+-inf at the root)
    Real split = 0;
    std::int32_t right = -1;  // left child is this index + 1 (preorder); -1 for a leaf
    std::int32_t parent = -1;
    std::int32_t skip = 0;   // preorder index just past the subtree
    std::int32_t head = -1;  // first proxy slot of this node's list
    std::int32_t count = 0;
    std::int32_t static_count = 0;
    std::int32_t depth = 0;
    std::int8_t axis = -1;  // -1: leaf
  };
  using Proxy = detail::LinkedProxy;
  struct Split {
    int axis = -1;
    Real plane = 0;
    Real cost = 0;
  };

  static bool is_unbounded(const Aabb& box);
  Split find_split(const std::int32_t* slots, std::int32_t n, const Aabb& bounds) const;
  template <class BoxOf>
  Split find_split_impl(std::int32_t n, const BoxOf& box_of, const Aabb& bounds) const;
  std::int32_t build_node(std::int32_t begin, std::int32_t end, const Aabb& cell,
                          std::int32_t parent, int depth);
  void reset_to_single_leaf();
  void link(std::int32_t slot, std::int32_t node);
  void unlink(std::int32_t slot);
  std::int32_t descend(std::int32_t from, const Aabb& box) const;
  void pack();
  void search_node(std::int32_t n);
  void query_node(std::int32_t n, const Aabb& box, std::vector<std::int32_t>& out) const;
  void ray_node(std::int32_t n, const Vec3& o, const Vec3& d, Real max_t,
                std::vector<std::int32_t>& out) const;

  KdTreeOptions options_;

  std::vector<Node> nodes_;  // preorder, root at 0
  detail::ProxySlots slots_;
  std::vector<std::int32_t> unbounded_;  // slots of proxies with infinite boxes
  std::int32_t bounded_count_ = 0;       // proxies in the tree

  // Rebuild policy state.
  std::int32_t built_count_ = 0;  // proxies in the tree at the last build
  std::int32_t inserted_since_build_ = 0;
  bool measure_baseline_ = true;  // next find_pairs sets the baseline
  double baseline_work_ = 0;      // work per proxy right after the last build
  bool rebuild_due_ = true;
  std::int64_t rebuilds_ = 0;

  // Scratch, reused so a warmed-up step allocates nothing.
  std::vector<std::int32_t> work_;
  detail::PackedProxyTree packed_;
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint64_t> sort_scratch_;
};

}  // namespace tumble
