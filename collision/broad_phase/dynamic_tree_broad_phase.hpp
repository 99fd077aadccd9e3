// Broad phase on dynamic AABB trees (docs/broad-phase.md), the "bvh" choice of the scene format.
//
// Two DynamicAabbTree instances: one for dynamic proxies, one for static ones, so static pairs
// are never even looked at. Proxies whose box has an infinite side (planes) go in a short list
// tested against everything.
//
// Fattening (the rule, in the order the terms are applied): a dynamic proxy's tree box is its
// real box enlarged on every side by `margin_fraction` times its largest half extent, and then
// on the side it is moving towards by `prediction_factor` times its last displacement on that
// axis (the displacement of the box centre between the last two updates). Both terms are
// relative, so the rule has no length in it and works for millimetre parts and 100 m buildings
// alike. update() does nothing to the tree while the new real box stays inside the fat box;
// otherwise the proxy gets a new fat box and its leaf is queued. The next find_pairs removes and
// reinserts each queued leaf (DynamicAabbTree::move_leaf) or, when more than
// `batch_refit_fraction` of the leaves are queued at once (a synchronised wave, everything
// teleported), refits them in place with rotations (DynamicAabbTree::refit_leaf), which costs a
// fraction of a reinsertion. Queries in between test queued proxies directly. Static and
// infinite proxies are not fattened.
//
// Pairs: the structure keeps a sorted list of candidate pairs, a superset of the pairs whose
// FAT boxes overlap (the persistent pair set of Box2D's b2BroadPhase, Catto GDC 2019). Only
// proxies whose fat box changed since the last find_pairs (the "moved" buffer) are queried
// against the trees, and their new candidates are merged into the list. find_pairs then walks
// the list once: a pair whose REAL boxes overlap is reported (so the output is exactly brute
// force's, already in (a, b) order), a pair whose fat boxes no longer overlap is dropped. When
// more than `full_requery_fraction` of the proxies moved (teleports, the first call) the list is
// rebuilt from scratch instead, by the self traversal of the dynamic tree and the dual traversal
// dynamic vs static tree (or, if a quarter of all pairs were candidates last time, by
// enumerating all pairs: no hierarchy prunes a pile where everything touches everything).
//
// Tree quality: insertion by branch and bound plus rotations keeps the tree good, but a long
// run of reinsertions and in-place refits can still degrade it. The rebuild trigger: every
// `leaf count / 2` reinsertions or refits, the dynamic tree's SAH cost (DynamicAabbTree::
// sah_cost, the sum of internal areas over the root's, so scale-free) is compared with its value
// right after the last full rebuild; past `rebuild_cost_ratio` times that, the tree is rebuilt
// top-down by binned SAH (which also lays it out depth-first for the cache). It is also rebuilt
// at the first find_pairs with 64 or more dynamic leaves and whenever the leaf count has doubled
// or halved since the last rebuild (a bulk load builds better top-down than by insertion).
#pragma once

#include <cstdint>
#include <vector>

#include "collision/broad_phase/broad_phase.hpp"
#include "collision/broad_phase/dynamic_aabb_tree.hpp"

namespace tumble {

struct DynamicTreeSettings {
  // Fat margin on every side, as a fraction of the proxy's largest half extent (unitless).
  // Larger: fewer reinsertions, more candidate pairs to filter. 0 reinserts on every move.
  Real margin_fraction = Real(0.25);
  // Extra margin on the leading side, in multiples of the last displacement (unitless). Covers
  // this many more steps of steady motion before a reinsertion. 0 disables prediction.
  Real prediction_factor = Real(4);
  // When more than this fraction of the live proxies moved out of their fat boxes since the
  // last find_pairs, the candidate list is rebuilt by tree traversal instead of one query per
  // moved proxy (unitless, 0..1; 0 always traverses, above 1 never does).
  Real full_requery_fraction = Real(0.25);
  // When more than this fraction of the dynamic leaves left their fat boxes since the last
  // find_pairs, they are refitted in place instead of reinserted (unitless, 0..1; 0 always
  // refits, above 1 always reinserts).
  Real batch_refit_fraction = Real(0.05);
  // Rebuild the dynamic tree by binned SAH when its SAH cost exceeds this multiple of its cost
  // right after the last rebuild (unitless, > 1). 0 never rebuilds.
  Real rebuild_cost_ratio = Real(1.3);
};

class DynamicTreeBroadPhase final : public BroadPhase {
 public:
  DynamicTreeBroadPhase() = default;
  explicit DynamicTreeBroadPhase(const DynamicTreeSettings& settings) : settings_(settings) {}

  void insert(std::int32_t id, const Aabb& box, bool is_static) override;
  void remove(std::int32_t id) override;
  void update(std::int32_t id, const Aabb& box) override;
  void find_pairs(std::vector<ProxyPair>& out) override;
  void query(const Aabb& box, std::vector<std::int32_t>& out) const override;
  void ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                std::vector<std::int32_t>& out) const override;

  // Counters since construction, for tests and statistics.
  struct Stats {
    std::int64_t reinsertions = 0;           // leaves that left their fat box (moved in the tree)
    std::int64_t batch_refits = 0;           // find_pairs calls that refitted instead
    std::int64_t incremental_requeries = 0;  // find_pairs calls that queried moved proxies
    std::int64_t full_requeries = 0;         // find_pairs calls that rebuilt the candidates
    std::int64_t dense_requeries = 0;        // ... of which by enumerating all pairs
    std::int64_t rebuilds = 0;               // binned SAH rebuilds of the dynamic tree
    std::int64_t candidate_pairs = 0;        // size of the candidate list after find_pairs
  };
  const Stats& stats() const { return stats_; }
  const DynamicAabbTree& dynamic_tree() const { return dynamic_tree_; }
  const DynamicAabbTree& static_tree() const { return static_tree_; }
  // The box the structure files the proxy under (fat for dynamic proxies). False if unknown.
  bool fat_box(std::int32_t id, Aabb& out) const;

 private:
  enum class Where : std::uint8_t { none, dynamic_tree, static_tree, infinite };
  struct Proxy {
    TreeBox box;  // the real box, as last given
    TreeBox fat;  // the box filed in the tree (== box for static and infinite proxies)
    std::int32_t leaf = DynamicAabbTree::null_node;
    Where where = Where::none;
    bool is_static = false;
    bool moved = false;    // in moved_ (its fat box changed since the last find_pairs)
    bool pending = false;  // in pending_ (the tree still files it under its old fat box)
  };

  TreeBox fatten(const TreeBox& box, const Real displacement[3]) const;
  void file(std::int32_t id, const TreeBox& box, const Real displacement[3]);
  void unfile(std::int32_t id);
  void mark_moved(std::int32_t id);
  void emit(std::int32_t a, std::int32_t b) {
    new_keys_.push_back(a < b ? tree_detail::pair_key(a, b) : tree_detail::pair_key(b, a));
  }
  void order_by_leaf(std::vector<std::int32_t>& ids);
  void flush_pending();
  void collect_full();
  void collect_moved();
  void maybe_rebuild();

  DynamicTreeSettings settings_;
  DynamicAabbTree dynamic_tree_;
  DynamicAabbTree static_tree_;
  std::vector<Proxy> proxies_;             // indexed by id
  std::vector<std::int32_t> infinite_;     // ids of proxies with an infinite side
  std::vector<std::int32_t> moved_;        // ids whose fat box changed since the last find_pairs
  std::vector<std::int32_t> pending_;      // dynamic ids whose tree leaf awaits its new fat box
  std::vector<std::uint64_t> candidates_;  // sorted pair keys, superset of fat-overlapping pairs
  std::vector<std::uint64_t> new_keys_;
  std::vector<std::uint64_t> merged_;
  std::vector<std::int32_t> sort_counts_;
  std::vector<std::uint64_t> order_keys_;
  std::int32_t live_ = 0;
  std::int64_t reinsertions_since_check_ = 0;
  Real baseline_cost_ = 0;            // SAH cost after the last rebuild (0: none yet)
  std::int32_t baseline_leaves_ = 0;  // leaf count at that rebuild
  Stats stats_;
};

}  // namespace tumble
