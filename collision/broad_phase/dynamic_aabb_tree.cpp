#include "collision/broad_phase/dynamic_aabb_tree.hpp"

#include "collision/broad_phase/binned_sah.hpp"

#include <algorithm>
#include <limits>

namespace tumble {

namespace tree_detail {

void sort_pair_keys(std::vector<std::uint64_t>& keys, std::int32_t id_bound,
                    std::vector<std::uint64_t>& scratch, std::vector<std::int32_t>& counts) {
  const std::size_t n = keys.size();
  if (n < 2)
    return;
  if (n < 256) {
    // Too few keys to repay a pass over id_bound counters.
    std::sort(keys.begin(), keys.end());
    return;
  }
  if (n > 8 * static_cast<std::size_t>(id_bound)) {
    // Dense (most proxies overlap most others): two stable counting sorts, on the second id and
    // then on the first (least significant digit first), with no comparison sort at all.
    scratch.resize(n);
    counts.assign(static_cast<std::size_t>(id_bound) + 1, 0);
    for (const std::uint64_t k : keys)
      ++counts[static_cast<std::size_t>(key_second(k)) + 1];
    for (std::int32_t i = 0; i < id_bound; ++i)
      counts[i + 1] += counts[i];
    for (const std::uint64_t k : keys)
      scratch[counts[key_second(k)]++] = k;
    counts.assign(static_cast<std::size_t>(id_bound) + 1, 0);
    for (const std::uint64_t k : scratch)
      ++counts[static_cast<std::size_t>(key_first(k)) + 1];
    for (std::int32_t i = 0; i < id_bound; ++i)
      counts[i + 1] += counts[i];
    for (const std::uint64_t k : scratch)
      keys[counts[key_first(k)]++] = k;
    return;
  }
  counts.assign(static_cast<std::size_t>(id_bound) + 1, 0);
  for (const std::uint64_t k : keys)
    ++counts[static_cast<std::size_t>(key_first(k)) + 1];
  for (std::int32_t i = 0; i < id_bound; ++i)
    counts[i + 1] += counts[i];
  scratch.resize(n);
  // After the scatter counts[a] is the end of bucket a, i.e. the start of bucket a + 1.
  for (const std::uint64_t k : keys)
    scratch[counts[key_first(k)]++] = k;
  std::int32_t begin = 0;
  for (std::int32_t a = 0; a < id_bound; ++a) {
    const std::int32_t end = counts[a];
    const std::int32_t size = end - begin;
    if (size > 16) {
      std::sort(scratch.begin() + begin, scratch.begin() + end);
    } else if (size > 1) {
      // Insertion sort: buckets hold the few neighbours of one proxy.
      for (std::int32_t i = begin + 1; i < end; ++i) {
        const std::uint64_t v = scratch[i];
        std::int32_t j = i;
        while (j > begin && scratch[j - 1] > v) {
          scratch[j] = scratch[j - 1];
          --j;
        }
        scratch[j] = v;
      }
    }
    begin = end;
  }
  keys.swap(scratch);
}

}  // namespace tree_detail

std::int32_t DynamicAabbTree::allocate_node() {
  std::int32_t i;
  if (free_list_ != null_node) {
    i = free_list_;
    free_list_ = nodes_[i].parent;
  } else {
    i = static_cast<std::int32_t>(nodes_.size());
    nodes_.emplace_back();
  }
  Node& n = nodes_[i];
  n.parent = null_node;
  n.child1 = null_node;
  n.child2 = null_node;
  n.height = 0;
  return i;
}

void DynamicAabbTree::free_node(std::int32_t i) {
  nodes_[i].parent = free_list_;
  nodes_[i].child1 = null_node;
  nodes_[i].height = -1;
  free_list_ = i;
}

void DynamicAabbTree::clear() {
  nodes_.clear();
  root_ = null_node;
  free_list_ = null_node;
  leaf_count_ = 0;
}

std::int32_t DynamicAabbTree::create_leaf(const TreeBox& box, std::int32_t user_data) {
  assert(box.is_finite());
  const std::int32_t leaf = allocate_node();
  nodes_[leaf].box = box;
  nodes_[leaf].child2 = user_data;
  ++leaf_count_;
  insert_leaf(leaf);
  return leaf;
}

void DynamicAabbTree::destroy_leaf(std::int32_t leaf) {
  assert(nodes_[leaf].is_leaf() && nodes_[leaf].height == 0);
  remove_leaf(leaf);
  free_node(leaf);
  --leaf_count_;
}

void DynamicAabbTree::move_leaf(std::int32_t leaf, const TreeBox& box) {
  assert(box.is_finite());
  remove_leaf(leaf);
  nodes_[leaf].box = box;
  insert_leaf(leaf);
}

void DynamicAabbTree::refit_leaf(std::int32_t leaf, const TreeBox& box) {
  assert(box.is_finite());
  nodes_[leaf].box = box;
  refit_and_rotate_upwards(nodes_[leaf].parent);
}

void DynamicAabbTree::replace_child(std::int32_t parent, std::int32_t old_child,
                                    std::int32_t new_child) {
  if (parent == null_node) {
    root_ = new_child;
    return;
  }
  Node& p = nodes_[parent];
  if (p.child1 == old_child)
    p.child1 = new_child;
  else
    p.child2 = new_child;
}

// Branch and bound over the tree (Bittner et al. 2013, algorithm 1). Placing the new leaf L as
// the sibling of node X creates a parent of area A(L u X) and grows every ancestor Y of X by
// A(L u Y) - A(Y). The total is cost(X) = A(L u X) + sum of those growths, the "inherited" part.
// Every node below X costs at least A(L) + inherited(X) + A(L u X) - A(X), so a subtree whose
// bound is no better than the best found so far is skipped. Nodes are expanded cheapest
// inherited cost first (a binary heap on a reused vector).
std::int32_t DynamicAabbTree::find_best_sibling(const TreeBox& box) const {
  const Real area_l = box.half_area();
  std::int32_t best = root_;
  Real best_cost = TreeBox::merge(box, nodes_[root_].box).half_area();
  const auto later = [](const HeapEntry& x, const HeapEntry& y) {
    return x.inherited > y.inherited || (x.inherited == y.inherited && x.node > y.node);
  };
  heap_.clear();
  {
    const Node& r = nodes_[root_];
    if (!r.is_leaf()) {
      const Real inherited = best_cost - r.box.half_area();
      if (area_l + inherited < best_cost) {
        heap_.push_back({inherited, r.child1});
        heap_.push_back({inherited, r.child2});
        std::make_heap(heap_.begin(), heap_.end(), later);
      }
    }
  }
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    const HeapEntry e = heap_.back();
    heap_.pop_back();
    // The heap is ordered by inherited cost, so once the bound fails it fails for all the rest.
    if (area_l + e.inherited >= best_cost)
      break;
    const Node& n = nodes_[e.node];
    const Real direct = TreeBox::merge(box, n.box).half_area();
    const Real cost = direct + e.inherited;
    if (cost < best_cost) {
      best_cost = cost;
      best = e.node;
    }
    if (!n.is_leaf()) {
      const Real inherited = e.inherited + direct - n.box.half_area();
      if (area_l + inherited < best_cost) {
        heap_.push_back({inherited, n.child1});
        std::push_heap(heap_.begin(), heap_.end(), later);
        heap_.push_back({inherited, n.child2});
        std::push_heap(heap_.begin(), heap_.end(), later);
      }
    }
  }
  return best;
}

void DynamicAabbTree::insert_leaf(std::int32_t leaf) {
  if (root_ == null_node) {
    root_ = leaf;
    nodes_[leaf].parent = null_node;
    return;
  }
  const std::int32_t sibling = find_best_sibling(nodes_[leaf].box);
  const std::int32_t old_parent = nodes_[sibling].parent;
  const std::int32_t p = allocate_node();  // may grow nodes_: no references held across it
  Node& np = nodes_[p];
  np.parent = old_parent;
  np.child1 = sibling;
  np.child2 = leaf;
  np.box = TreeBox::merge(nodes_[sibling].box, nodes_[leaf].box);
  np.height = nodes_[sibling].height + 1;
  replace_child(old_parent, sibling, p);
  nodes_[sibling].parent = p;
  nodes_[leaf].parent = p;
  // The new parent's box is already right; rotate there, then refit upwards from above it.
  if (options_.rotate)
    rotate(p);
  refit_and_rotate_upwards(old_parent);
}

void DynamicAabbTree::remove_leaf(std::int32_t leaf) {
  if (leaf == root_) {
    root_ = null_node;
    return;
  }
  const std::int32_t p = nodes_[leaf].parent;
  const std::int32_t grand = nodes_[p].parent;
  const std::int32_t sibling = nodes_[p].child1 == leaf ? nodes_[p].child2 : nodes_[p].child1;
  replace_child(grand, p, sibling);
  nodes_[sibling].parent = grand;
  free_node(p);
  if (grand != null_node)
    refit_and_rotate_upwards(grand);
}

// Walks from node i to the root, refitting boxes and heights and rotating. The walk stops at the
// first ancestor whose box and height come out unchanged and that does not rotate: nothing above
// it changed (for a leaf reinserted near its old place that is a few levels up, not the root).
void DynamicAabbTree::refit_and_rotate_upwards(std::int32_t i) {
  while (i != null_node) {
    Node& n = nodes_[i];
    const Node& c1 = nodes_[n.child1];
    const Node& c2 = nodes_[n.child2];
    const TreeBox box = TreeBox::merge(c1.box, c2.box);
    const std::int32_t height = 1 + std::max(c1.height, c2.height);
    const bool same = std::equal(box.min, box.min + 3, n.box.min) &&
                      std::equal(box.max, box.max + 3, n.box.max) && height == n.height;
    n.box = box;
    n.height = height;
    const bool rotated = options_.rotate && rotate(i);
    if (same && !rotated)
      break;
    i = n.parent;
  }
}

// Kopta et al. 2012: at node A with children B and C, try swapping a child with a grandchild
// on the other side (B<->F, B<->G, C<->D, C<->E) or two grandchildren (D<->F, D<->G). A's box
// holds the same leaves either way, so only the boxes of B and/or C change; take the swap that
// lowers their summed area most, if any does. Each swap strictly lowers the tree's cost, so
// rotations never cycle.
bool DynamicAabbTree::rotate(std::int32_t a) {
  Node& na = nodes_[a];
  const std::int32_t b = na.child1;
  const std::int32_t c = na.child2;
  Node& nb = nodes_[b];
  Node& nc = nodes_[c];
  if (nb.height < 1 && nc.height < 1)
    return false;

  enum Swap { none, bf, bg, cd, ce, df, dg };
  Swap best = none;
  Real best_gain = 0;
  const Real area_b = nb.box.half_area();
  const Real area_c = nc.box.half_area();
  const auto consider = [&](Swap s, Real gain) {
    if (gain > best_gain) {
      best_gain = gain;
      best = s;
    }
  };
  if (!nc.is_leaf()) {
    const TreeBox& f = nodes_[nc.child1].box;
    const TreeBox& g = nodes_[nc.child2].box;
    consider(bf, area_c - TreeBox::merge(nb.box, g).half_area());
    consider(bg, area_c - TreeBox::merge(nb.box, f).half_area());
  }
  if (!nb.is_leaf()) {
    const TreeBox& d = nodes_[nb.child1].box;
    const TreeBox& e = nodes_[nb.child2].box;
    consider(cd, area_b - TreeBox::merge(nc.box, e).half_area());
    consider(ce, area_b - TreeBox::merge(nc.box, d).half_area());
    if (!nc.is_leaf()) {
      const TreeBox& f = nodes_[nc.child1].box;
      const TreeBox& g = nodes_[nc.child2].box;
      const Real before = area_b + area_c;
      consider(df, before - TreeBox::merge(f, e).half_area() - TreeBox::merge(d, g).half_area());
      consider(dg, before - TreeBox::merge(g, e).half_area() - TreeBox::merge(f, d).half_area());
    }
  }
  if (best == none)
    return false;

  // Swaps the child `x` of node `px` (in the slot it occupies) with child `y` of node `py`.
  const auto exchange = [&](std::int32_t px, std::int32_t x, std::int32_t py, std::int32_t y) {
    Node& npx = nodes_[px];
    Node& npy = nodes_[py];
    (npx.child1 == x ? npx.child1 : npx.child2) = y;
    (npy.child1 == y ? npy.child1 : npy.child2) = x;
    nodes_[x].parent = py;
    nodes_[y].parent = px;
  };
  const auto refresh = [&](std::int32_t i) {
    Node& n = nodes_[i];
    n.box = TreeBox::merge(nodes_[n.child1].box, nodes_[n.child2].box);
    n.height = 1 + std::max(nodes_[n.child1].height, nodes_[n.child2].height);
  };
  switch (best) {
    case bf:
      exchange(a, b, c, nc.child1);
      refresh(c);
      break;
    case bg:
      exchange(a, b, c, nc.child2);
      refresh(c);
      break;
    case cd:
      exchange(a, c, b, nb.child1);
      refresh(b);
      break;
    case ce:
      exchange(a, c, b, nb.child2);
      refresh(b);
      break;
    case df:
      exchange(b, nb.child1, c, nc.child1);
      refresh(b);
      refresh(c);
      break;
    case dg:
      exchange(b, nb.child1, c, nc.child2);
      refresh(b);
      refresh(c);
      break;
    case none:
      break;
  }
  na.height = 1 + std::max(nodes_[na.child1].height, nodes_[na.child2].height);
  return true;
}

void DynamicAabbTree::refit() {
  if (root_ == null_node)
    return;
  // Pre-order list of internal nodes; walked backwards, every child comes before its parent.
  scratch_nodes_.clear();
  scratch_nodes_.push_back(root_);
  for (std::size_t k = 0; k < scratch_nodes_.size(); ++k) {
    const Node& n = nodes_[scratch_nodes_[k]];
    if (n.is_leaf())
      continue;
    scratch_nodes_.push_back(n.child1);
    scratch_nodes_.push_back(n.child2);
  }
  for (std::size_t k = scratch_nodes_.size(); k-- > 0;) {
    Node& n = nodes_[scratch_nodes_[k]];
    if (n.is_leaf())
      continue;
    n.box = TreeBox::merge(nodes_[n.child1].box, nodes_[n.child2].box);
    n.height = 1 + std::max(nodes_[n.child1].height, nodes_[n.child2].height);
  }
}

Real DynamicAabbTree::sah_cost() const {
  if (root_ == null_node || nodes_[root_].is_leaf())
    return 0;
  Real sum = 0;
  for (const Node& n : nodes_) {
    if (n.height > 0)
      sum += n.box.half_area();
  }
  const Real root_area = nodes_[root_].box.half_area();
  return root_area > 0 ? sum / root_area : 0;
}

// Copies the leaves under `node` into build_refs_; frees the internal nodes if asked.
void DynamicAabbTree::collect_build_refs(std::int32_t node, bool free_internal) {
  build_refs_.clear();
  scratch_nodes_.clear();
  scratch_nodes_.push_back(node);
  while (!scratch_nodes_.empty()) {
    const std::int32_t i = scratch_nodes_.back();
    scratch_nodes_.pop_back();
    const Node& n = nodes_[i];
    if (n.is_leaf()) {
      build_refs_.push_back({n.box, i, n.child2});
      continue;
    }
    scratch_nodes_.push_back(n.child2);
    scratch_nodes_.push_back(n.child1);
    if (free_internal)
      free_node(i);
  }
}

void DynamicAabbTree::rebuild_compact() {
  if (root_ == null_node)
    return;
  collect_build_refs(root_, false);
  nodes_.clear();
  free_list_ = null_node;
  root_ = build_binned(null_node, true);
}

void DynamicAabbTree::rebuild_subtree(std::int32_t node) {
  if (node == null_node || nodes_[node].is_leaf())
    return;
  const std::int32_t parent = nodes_[node].parent;
  collect_build_refs(node, true);
  const std::int32_t new_root = build_binned(parent, false);
  replace_child(parent, node, new_root);
  // The subtree holds the same leaves, so the ancestors' boxes stand; their heights may not.
  for (std::int32_t i = parent; i != null_node; i = nodes_[i].parent) {
    Node& n = nodes_[i];
    n.height = 1 + std::max(nodes_[n.child1].height, nodes_[n.child2].height);
  }
}

// Top-down binned SAH over build_refs_ (Wald 2007). Each range is split where the cost
// A(left) N(left) + A(right) N(right) is least among the 15 boundaries of 16 equal bins of the
// box centres, on whichever axis is best; a range whose centres coincide is split in the
// middle. Leaves hold one object each, as everywhere in this tree. Three sequential passes per
// level: bounds, binning (all three axes at once), partition.
//
// compact: nodes are appended to nodes_ (emptied by the caller) in depth-first order, leaves
// included, so every child has a larger index than its parent. Otherwise internal nodes come
// from the free list and the leaves keep their indices (a partial rebuild).
// Returns the new subtree's root, linked to `parent`.
std::int32_t DynamicAabbTree::build_binned(std::int32_t parent, bool compact) {
  const auto n = static_cast<std::int32_t>(build_refs_.size());
  assert(n >= 1);
  std::int32_t result = null_node;
  build_tasks_.clear();
  build_tasks_.push_back({parent, 0, n, true});
  scratch_nodes_.clear();  // the internal nodes created, in creation (pre-)order
  while (!build_tasks_.empty()) {
    const BuildTask task = build_tasks_.back();
    build_tasks_.pop_back();
    std::int32_t self;
    if (task.end - task.begin == 1) {
      const BuildRef& r = build_refs_[task.begin];
      if (compact) {
        self = allocate_node();
        nodes_[self].box = r.box;
        nodes_[self].child2 = r.user_data;
      } else {
        self = r.leaf;
      }
    } else {
      self = allocate_node();
      scratch_nodes_.push_back(self);
      const detail::BinnedSplit split =
          detail::binned_sah_split(build_refs_.data(), task.begin, task.end);
      nodes_[self].box = split.bounds;
      const std::int32_t mid = split.mid;
      // The left half is popped next, so it follows its parent in memory (depth-first order).
      build_tasks_.push_back({self, mid, task.end, false});
      build_tasks_.push_back({self, task.begin, mid, true});
    }
    nodes_[self].parent = task.parent;
    if (result == null_node) {
      result = self;  // the first task popped is the subtree's root
    } else {
      (task.first_child ? nodes_[task.parent].child1 : nodes_[task.parent].child2) = self;
    }
  }
  // Heights bottom-up: children were created after their parents.
  for (std::size_t k = scratch_nodes_.size(); k-- > 0;) {
    Node& nd = nodes_[scratch_nodes_[k]];
    nd.height = 1 + std::max(nodes_[nd.child1].height, nodes_[nd.child2].height);
  }
  return result;
}

}  // namespace tumble
