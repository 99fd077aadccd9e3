#include "collision/broad_phase/dynamic_tree_broad_phase.hpp"

#include <algorithm>
#include <cassert>
#include <limits>

namespace tumble {

TreeBox DynamicTreeBroadPhase::fatten(const TreeBox& box, const Real displacement[3]) const {
  Real half = 0;
  for (int k = 0; k < 3; ++k)
    half = std::max(half, (box.max[k] - box.min[k]) * Real(0.5));
  const Real margin = settings_.margin_fraction * half;
  TreeBox fat;
  for (int k = 0; k < 3; ++k) {
    const Real lead = settings_.prediction_factor * displacement[k];
    // Subtracting a non-negative number never rounds up, so fat always contains box.
    fat.min[k] = box.min[k] - margin - std::max(Real(0), -lead);
    fat.max[k] = box.max[k] + margin + std::max(Real(0), lead);
  }
  return fat;
}

void DynamicTreeBroadPhase::file(std::int32_t id, const TreeBox& box, const Real displacement[3]) {
  Proxy& p = proxies_[id];
  p.box = box;
  if (!box.is_finite()) {
    p.fat = box;
    p.where = Where::infinite;
    p.leaf = DynamicAabbTree::null_node;
    infinite_.push_back(id);
  } else if (p.is_static) {
    p.fat = box;
    p.where = Where::static_tree;
    p.leaf = static_tree_.create_leaf(box, id);
  } else {
    p.fat = fatten(box, displacement);
    p.where = Where::dynamic_tree;
    p.leaf = dynamic_tree_.create_leaf(p.fat, id);
  }
}

void DynamicTreeBroadPhase::unfile(std::int32_t id) {
  Proxy& p = proxies_[id];
  switch (p.where) {
    case Where::dynamic_tree:
      dynamic_tree_.destroy_leaf(p.leaf);
      break;
    case Where::static_tree:
      static_tree_.destroy_leaf(p.leaf);
      break;
    case Where::infinite:
      infinite_.erase(std::find(infinite_.begin(), infinite_.end(), id));
      break;
    case Where::none:
      break;
  }
  p.where = Where::none;
  p.leaf = DynamicAabbTree::null_node;
}

void DynamicTreeBroadPhase::mark_moved(std::int32_t id) {
  Proxy& p = proxies_[id];
  if (!p.moved) {
    p.moved = true;
    moved_.push_back(id);
  }
}

void DynamicTreeBroadPhase::insert(std::int32_t id, const Aabb& box, bool is_static) {
  assert(id >= 0);
  if (static_cast<std::size_t>(id) >= proxies_.size())
    proxies_.resize(static_cast<std::size_t>(id) + 1);
  assert(proxies_[id].where == Where::none);
  proxies_[id].is_static = is_static;
  const Real still[3] = {0, 0, 0};
  file(id, TreeBox::from(box), still);
  mark_moved(id);
  ++live_;
}

void DynamicTreeBroadPhase::remove(std::int32_t id) {
  assert(proxies_[id].where != Where::none);
  unfile(id);
  --live_;
  // Pairs naming this id leave the candidate list at the next find_pairs (the scan drops pairs
  // with a dead proxy); a stale moved_ entry is skipped the same way.
}

void DynamicTreeBroadPhase::update(std::int32_t id, const Aabb& aabb) {
  Proxy& p = proxies_[id];
  assert(p.where != Where::none);
  const TreeBox box = TreeBox::from(aabb);
  if (p.where == Where::dynamic_tree && box.is_finite()) {
    Real displacement[3];
    for (int k = 0; k < 3; ++k)
      displacement[k] = ((box.min[k] + box.max[k]) - (p.box.min[k] + p.box.max[k])) * Real(0.5);
    p.box = box;
    if (p.fat.contains(box))
      return;  // the common case of coherent motion: nothing to do
    // Out of its fat box: a new fat box now, the tree work at the next find_pairs.
    p.fat = fatten(box, displacement);
    if (!p.pending) {
      p.pending = true;
      pending_.push_back(id);
    }
    mark_moved(id);
    return;
  }
  if (p.where == Where::static_tree && box.is_finite()) {
    p.box = box;
    if (p.fat.contains(box))
      return;
    p.fat = box;
    static_tree_.move_leaf(p.leaf, box);
    mark_moved(id);
    return;
  }
  // Into, out of or within the infinite list: refile from scratch (rare: planes do not move).
  const Real still[3] = {0, 0, 0};
  unfile(id);
  file(id, box, still);
  mark_moved(id);
}

bool DynamicTreeBroadPhase::fat_box(std::int32_t id, Aabb& out) const {
  if (id < 0 || static_cast<std::size_t>(id) >= proxies_.size() ||
      proxies_[id].where == Where::none)
    return false;
  out = proxies_[id].fat.to_aabb();
  return true;
}

// Rebuilds the candidate list from scratch: every pair of fat boxes that overlap.
void DynamicTreeBroadPhase::collect_full() {
  ++stats_.full_requeries;
  // When a quarter or more of all pairs were candidates last time (everything piled in one
  // place), a hierarchy cannot prune and its traversal and sort cost more than enumerating all
  // pairs in order, which yields the keys sorted for free.
  const auto live = static_cast<std::uint64_t>(live_);
  const bool dense = live > 64 && 8 * candidates_.size() > live * (live - 1);
  new_keys_.clear();
  candidates_.clear();
  if (dense) {
    const auto n = static_cast<std::int32_t>(proxies_.size());
    for (std::int32_t a = 0; a < n; ++a) {
      const Proxy& pa = proxies_[a];
      if (pa.where == Where::none)
        continue;
      for (std::int32_t b = a + 1; b < n; ++b) {
        const Proxy& pb = proxies_[b];
        if (pb.where != Where::none && !(pa.is_static && pb.is_static) && pa.fat.overlaps(pb.fat))
          new_keys_.push_back(tree_detail::pair_key(a, b));
      }
    }
    ++stats_.dense_requeries;
    return;
  }
  const DynamicAabbTree& dyn = dynamic_tree_;
  const DynamicAabbTree& sta = static_tree_;
  for_each_overlapping_leaf_pair(
      dyn, [&](std::int32_t la, std::int32_t lb) { emit(dyn.user_data(la), dyn.user_data(lb)); });
  for_each_overlapping_leaf_pair(dyn, sta, [&](std::int32_t la, std::int32_t lb) {
    emit(dyn.user_data(la), sta.user_data(lb));
  });
  for (std::size_t i = 0; i < infinite_.size(); ++i) {
    const std::int32_t id = infinite_[i];
    const Proxy& p = proxies_[id];
    dyn.query(p.fat, [&](std::int32_t leaf) { emit(id, dyn.user_data(leaf)); });
    if (!p.is_static)
      sta.query(p.fat, [&](std::int32_t leaf) { emit(id, sta.user_data(leaf)); });
    for (std::size_t j = i + 1; j < infinite_.size(); ++j) {
      const Proxy& q = proxies_[infinite_[j]];
      if (!(p.is_static && q.is_static) && p.fat.overlaps(q.fat))
        emit(id, infinite_[j]);
    }
  }
  tree_detail::sort_pair_keys(new_keys_, static_cast<std::int32_t>(proxies_.size()), merged_,
                              sort_counts_);
}

// New candidates of the proxies whose fat box changed. A pair of two moved proxies is found
// from both sides; only the side with the larger id keeps it.
void DynamicTreeBroadPhase::collect_moved() {
  new_keys_.clear();
  const DynamicAabbTree& dyn = dynamic_tree_;
  const DynamicAabbTree& sta = static_tree_;
  order_by_leaf(moved_);
  for (const std::int32_t id : moved_) {
    const Proxy& p = proxies_[id];
    if (p.where == Where::none)
      continue;  // removed since it moved
    const auto take = [&](std::int32_t other) {
      if (other == id || (other < id && proxies_[other].moved))
        return;
      emit(id, other);
    };
    dyn.query(p.fat, [&](std::int32_t leaf) { take(dyn.user_data(leaf)); });
    if (!p.is_static)
      sta.query(p.fat, [&](std::int32_t leaf) { take(sta.user_data(leaf)); });
    for (const std::int32_t other : infinite_) {
      const Proxy& q = proxies_[other];
      if (!(p.is_static && q.is_static) && p.fat.overlaps(q.fat))
        take(other);
    }
  }
  tree_detail::sort_pair_keys(new_keys_, static_cast<std::int32_t>(proxies_.size()), merged_,
                              sort_counts_);
  ++stats_.incremental_requeries;
}

// Brings the dynamic tree up to date with the fat boxes of update(). Few pending leaves: each is
// removed and reinserted (branch and bound, rotations). Many (a wave of proxies leaving their fat
// boxes together, or everything teleported): each leaf is refitted where it stands, with
// rotations on the way up (DynamicAabbTree::refit_leaf), at a fraction of the cost of a
// reinsertion; the SAH check that follows rebuilds the tree if that left it poor.
// Sorts ids by their leaf in the dynamic tree (others last). After a rebuild the leaves lie in
// depth-first order, so neighbouring leaves are neighbours in space: queries and refits taken in
// this order walk the same upper nodes one after another and find them in cache.
void DynamicTreeBroadPhase::order_by_leaf(std::vector<std::int32_t>& ids) {
  if (ids.size() < 64)
    return;
  order_keys_.clear();
  for (const std::int32_t id : ids) {
    const Proxy& p = proxies_[id];
    const std::uint32_t leaf =
        p.where == Where::dynamic_tree ? static_cast<std::uint32_t>(p.leaf) : 0xffffffffu;
    order_keys_.push_back((static_cast<std::uint64_t>(leaf) << 32) |
                          static_cast<std::uint32_t>(id));
  }
  std::sort(order_keys_.begin(), order_keys_.end());
  for (std::size_t i = 0; i < ids.size(); ++i)
    ids[i] = tree_detail::key_second(order_keys_[i]);
}

void DynamicTreeBroadPhase::flush_pending() {
  order_by_leaf(pending_);
  std::int32_t count = 0;
  for (const std::int32_t id : pending_) {
    const Proxy& p = proxies_[id];
    count += p.pending && p.where == Where::dynamic_tree;
  }
  const bool batch =
      static_cast<Real>(count) > settings_.batch_refit_fraction * dynamic_tree_.leaf_count();
  for (const std::int32_t id : pending_) {
    Proxy& p = proxies_[id];
    if (!p.pending)
      continue;
    p.pending = false;
    if (p.where != Where::dynamic_tree)
      continue;  // removed, or refiled elsewhere, since
    if (batch)
      dynamic_tree_.refit_leaf(p.leaf, p.fat);
    else
      dynamic_tree_.move_leaf(p.leaf, p.fat);
  }
  pending_.clear();
  stats_.batch_refits += batch;
  stats_.reinsertions += count;
  reinsertions_since_check_ += count;
}

void DynamicTreeBroadPhase::maybe_rebuild() {
  if (settings_.rebuild_cost_ratio <= 0)
    return;
  const std::int32_t n = dynamic_tree_.leaf_count();
  if (n < 64)
    return;  // small trees are cheap to query whatever their shape
  const bool resized = n > 2 * baseline_leaves_ || 2 * n < baseline_leaves_;
  if (!resized && reinsertions_since_check_ < n / 2)
    return;
  reinsertions_since_check_ = 0;
  if (resized || dynamic_tree_.sah_cost() > settings_.rebuild_cost_ratio * baseline_cost_) {
    dynamic_tree_.rebuild([&](std::int32_t id, std::int32_t leaf) { proxies_[id].leaf = leaf; });
    baseline_cost_ = dynamic_tree_.sah_cost();
    baseline_leaves_ = n;
    ++stats_.rebuilds;
  }
}

void DynamicTreeBroadPhase::find_pairs(std::vector<ProxyPair>& out) {
  flush_pending();
  maybe_rebuild();
  if (static_cast<Real>(moved_.size()) > settings_.full_requery_fraction * static_cast<Real>(live_))
    collect_full();
  else
    collect_moved();
  for (const std::int32_t id : moved_)
    proxies_[id].moved = false;
  moved_.clear();

  // One pass over the union of the old list and the new candidates, both sorted: report pairs
  // whose real boxes overlap, keep pairs whose fat boxes overlap, drop the rest.
  out.clear();
  merged_.clear();
  std::size_t i = 0;
  std::size_t j = 0;
  std::uint64_t last = std::numeric_limits<std::uint64_t>::max();
  while (i < candidates_.size() || j < new_keys_.size()) {
    std::uint64_t k;
    if (j == new_keys_.size() || (i < candidates_.size() && candidates_[i] <= new_keys_[j]))
      k = candidates_[i++];
    else
      k = new_keys_[j++];
    if (k == last)
      continue;
    last = k;
    const std::int32_t a = tree_detail::key_first(k);
    const std::int32_t b = tree_detail::key_second(k);
    const Proxy& pa = proxies_[a];
    const Proxy& pb = proxies_[b];
    if (pa.where == Where::none || pb.where == Where::none || (pa.is_static && pb.is_static))
      continue;
    if (pa.box.overlaps(pb.box)) {
      out.push_back({a, b});
      merged_.push_back(k);
    } else if (pa.fat.overlaps(pb.fat)) {
      merged_.push_back(k);
    }
  }
  candidates_.swap(merged_);
  stats_.candidate_pairs = static_cast<std::int64_t>(candidates_.size());
}

void DynamicTreeBroadPhase::query(const Aabb& aabb, std::vector<std::int32_t>& out) const {
  out.clear();
  const TreeBox box = TreeBox::from(aabb);
  const auto visit = [&](std::int32_t id) {
    if (proxies_[id].box.overlaps(box))
      out.push_back(id);
  };
  // A leaf whose fat box changed since the last find_pairs is still filed under its old box:
  // such proxies are skipped in the tree and tested directly.
  dynamic_tree_.query(box, [&](std::int32_t leaf) {
    const std::int32_t id = dynamic_tree_.user_data(leaf);
    if (!proxies_[id].pending)
      visit(id);
  });
  static_tree_.query(box, [&](std::int32_t leaf) { visit(static_tree_.user_data(leaf)); });
  for (const std::int32_t id : pending_) {
    if (proxies_[id].pending && proxies_[id].where == Where::dynamic_tree)
      visit(id);
  }
  for (const std::int32_t id : infinite_) {
    if (proxies_[id].box.overlaps(box))
      out.push_back(id);
  }
  std::sort(out.begin(), out.end());
}

void DynamicTreeBroadPhase::ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                                     std::vector<std::int32_t>& out) const {
  out.clear();
  const SegmentProbe probe(origin, direction, max_t);
  const auto visit = [&](std::int32_t id) {
    if (segment_touches_aabb(origin, direction, max_t, proxies_[id].box.to_aabb()))
      out.push_back(id);
  };
  dynamic_tree_.ray_cast(probe, [&](std::int32_t leaf) {
    const std::int32_t id = dynamic_tree_.user_data(leaf);
    if (!proxies_[id].pending)
      visit(id);
  });
  static_tree_.ray_cast(probe, [&](std::int32_t leaf) { visit(static_tree_.user_data(leaf)); });
  for (const std::int32_t id : pending_) {
    if (proxies_[id].pending && proxies_[id].where == Where::dynamic_tree)
      visit(id);
  }
  for (const std::int32_t id : infinite_) {
    if (segment_touches_aabb(origin, direction, max_t, proxies_[id].box.to_aabb()))
      out.push_back(id);
  }
  std::sort(out.begin(), out.end());
}

}  // namespace tumble
