#include "collision/broad_phase/linear_bvh_broad_phase.hpp"

#include "collision/broad_phase/binned_sah.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <chrono>
#include <limits>

namespace tumble {

namespace lbvh {

namespace {

constexpr Real inf = std::numeric_limits<Real>::infinity();

// Self traversal: visit(leaf_a, leaf_b) for every unordered pair of distinct leaves whose boxes
// overlap, each once. Same scheme as the dynamic tree's dual traversal (a node against itself
// expanding to its children against themselves and each other); only pairs that overlap and are
// not both leaves are pushed.
template <class Visit>
void self_pairs(const Hierarchy& h, Visit&& visit) {
  using Pair = tree_detail::NodePair;
  if (h.leaves.size() < 2)
    return;
  tree_detail::TraversalStack<Pair, 256> stack;
  stack.push({0, 0});
  while (!stack.empty()) {
    const Pair p = stack.pop();
    if (p.a == p.b) {
      const Node& n = h.nodes[p.a];
      if (n.right >= 0)
        stack.push({n.right, n.right});
      if (n.left >= 0)
        stack.push({n.left, n.left});
      if (h.box(n.left).overlaps(h.box(n.right))) {
        if (n.left < 0 && n.right < 0)
          visit(~n.left, ~n.right);
        else
          stack.push({n.left, n.right});
      }
      continue;
    }
    const TreeBox& ba = h.box(p.a);
    const TreeBox& bb = h.box(p.b);
    const bool split_a = p.b < 0 || (p.a >= 0 && ba.half_area() >= bb.half_area());
    const Node& split = h.nodes[split_a ? p.a : p.b];
    const std::int32_t other = split_a ? p.b : p.a;
    const TreeBox& bo = split_a ? bb : ba;
    for (const std::int32_t c : {split.right, split.left}) {
      if (!h.box(c).overlaps(bo))
        continue;
      if (c < 0 && other < 0)
        visit(~c, ~other);
      else
        stack.push({c, other});
    }
  }
}

// Dual traversal of two hierarchies: visit(leaf_a, leaf_b) for every overlapping pair.
template <class Visit>
void dual_pairs(const Hierarchy& a, const Hierarchy& b, Visit&& visit) {
  using Pair = tree_detail::NodePair;
  if (a.leaves.empty() || b.leaves.empty())
    return;
  const std::int32_t ra = a.root();
  const std::int32_t rb = b.root();
  if (!a.box(ra).overlaps(b.box(rb)))
    return;
  if (ra < 0 && rb < 0) {
    visit(~ra, ~rb);
    return;
  }
  tree_detail::TraversalStack<Pair, 256> stack;
  stack.push({ra, rb});
  while (!stack.empty()) {
    const Pair p = stack.pop();
    const TreeBox& ba = a.box(p.a);
    const TreeBox& bb = b.box(p.b);
    if (p.b < 0 || (p.a >= 0 && ba.half_area() >= bb.half_area())) {
      const Node& n = a.nodes[p.a];
      for (const std::int32_t c : {n.right, n.left}) {
        if (!a.box(c).overlaps(bb))
          continue;
        if (c < 0 && p.b < 0)
          visit(~c, ~p.b);
        else
          stack.push({c, p.b});
      }
    } else {
      const Node& n = b.nodes[p.b];
      for (const std::int32_t c : {n.right, n.left}) {
        if (!ba.overlaps(b.box(c)))
          continue;
        if (p.a < 0 && c < 0)
          visit(~p.a, ~c);
        else
          stack.push({p.a, c});
      }
    }
  }
}

// visit(leaf) for every leaf whose box passes `test` (a test monotone in the box, so that a
// node failing it has no leaf passing it).
template <class Test, class Visit>
void descend(const Hierarchy& h, Test&& test, Visit&& visit) {
  if (h.leaves.empty())
    return;
  tree_detail::TraversalStack<std::int32_t, 256> stack;
  stack.push(h.root());
  while (!stack.empty()) {
    const std::int32_t r = stack.pop();
    if (!test(h.box(r)))
      continue;
    if (r < 0) {
      visit(~r);
    } else {
      stack.push(h.nodes[r].right);
      stack.push(h.nodes[r].left);
    }
  }
}

}  // namespace

Real Hierarchy::sah_cost() const {
  if (nodes.empty())
    return 0;
  Real sum = 0;
  for (const Node& n : nodes)
    sum += n.box.half_area();
  const Real root_area = nodes[0].box.half_area();
  return root_area > 0 ? sum / root_area : 0;
}

// Karras 2012, figure 4, run for every internal node i (independent of each other, which is what
// makes it parallel on a GPU; here a plain loop). delta(i, j) is the length of the common prefix
// of keys i and j, with equal codes made distinct by appending the index (section 4, last
// paragraph), and -1 outside [0, n).
void karras_topology(const std::uint32_t* codes, std::int32_t n, Node* nodes,
                     std::int32_t* parents) {
  const auto delta = [&](std::int32_t i, std::int32_t j) -> int {
    if (j < 0 || j >= n)
      return -1;
    const std::uint32_t a = codes[i];
    const std::uint32_t b = codes[j];
    if (a != b)
      return std::countl_zero(a ^ b);
    return 32 + std::countl_zero(static_cast<std::uint32_t>(i) ^ static_cast<std::uint32_t>(j));
  };
  const std::int32_t leaf_base = n - 1;  // parents[leaf_base + k] is the parent of leaf k
  parents[0] = -1;
  for (std::int32_t i = 0; i < n - 1; ++i) {
    // Direction of the node's range: towards the neighbour sharing the longer prefix.
    const int d = delta(i, i + 1) - delta(i, i - 1) > 0 ? 1 : -1;
    // Upper bound for the range's length, then its exact other end j by binary search.
    const int delta_min = delta(i, i - d);
    std::int32_t l_max = 2;
    while (delta(i, i + l_max * d) > delta_min)
      l_max *= 2;
    std::int32_t l = 0;
    for (std::int32_t t = l_max / 2; t >= 1; t /= 2) {
      if (delta(i, i + (l + t) * d) > delta_min)
        l += t;
    }
    const std::int32_t j = i + l * d;
    // The split: the last key sharing more than delta_node bits with key i, by binary search.
    const int delta_node = delta(i, j);
    std::int32_t s = 0;
    std::int32_t t = l;
    do {
      t = (t + 1) / 2;
      if (delta(i, i + (s + t) * d) > delta_node)
        s += t;
    } while (t > 1);
    const std::int32_t gamma = i + s * d + std::min(d, 0);
    Node& node = nodes[i];
    if (std::min(i, j) == gamma) {
      node.left = ~gamma;
      parents[leaf_base + gamma] = i;
    } else {
      node.left = gamma;
      parents[gamma] = i;
    }
    if (std::max(i, j) == gamma + 1) {
      node.right = ~(gamma + 1);
      parents[leaf_base + gamma + 1] = i;
    } else {
      node.right = gamma + 1;
      parents[gamma + 1] = i;
    }
  }
}

void build_morton_karras(const TreeBox* boxes, const std::int32_t* ids, std::int32_t n,
                         Hierarchy& out, BuildScratch& scratch) {
  out.leaves.resize(static_cast<std::size_t>(n));
  out.nodes.resize(static_cast<std::size_t>(std::max(n - 1, 0)));
  if (n == 0)
    return;
  // Codes of the box centres (kept doubled, min + max: only their order matters) in the bounds
  // of the centres, 1024 cells per axis. A flat axis (all centres equal) scales by 0.
  Real lo[3] = {inf, inf, inf};
  Real hi[3] = {-inf, -inf, -inf};
  for (std::int32_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      const Real c = boxes[i].min[k] + boxes[i].max[k];
      lo[k] = std::min(lo[k], c);
      hi[k] = std::max(hi[k], c);
    }
  }
  Real scale[3];
  for (int k = 0; k < 3; ++k)
    scale[k] = hi[k] > lo[k] ? Real(1024) / (hi[k] - lo[k]) : 0;
  std::vector<std::uint64_t>& keys = scratch.keys;
  keys.resize(static_cast<std::size_t>(n));
  for (std::int32_t i = 0; i < n; ++i) {
    const TreeBox& b = boxes[i];
    const std::uint32_t code = morton_code(morton_cell(b.min[0] + b.max[0], lo[0], scale[0]),
                                           morton_cell(b.min[1] + b.max[1], lo[1], scale[1]),
                                           morton_cell(b.min[2] + b.max[2], lo[2], scale[2]));
    keys[i] = (static_cast<std::uint64_t>(code) << 32) | static_cast<std::uint32_t>(i);
  }
  // LSD radix sort on the 30 code bits, three stable passes of 10 bits. The index in the low
  // half starts ascending and the passes are stable, so equal codes stay in index order.
  std::vector<std::uint64_t>& tmp = scratch.keys_tmp;
  tmp.resize(static_cast<std::size_t>(n));
  for (int pass = 0; pass < 3; ++pass) {
    const int shift = 32 + 10 * pass;
    std::int32_t count[1025] = {};
    for (const std::uint64_t k : keys)
      ++count[((k >> shift) & 1023u) + 1];
    if (count[((keys[0] >> shift) & 1023u) + 1] == n)
      continue;  // every key has the same digit: the pass would not move anything
    for (int b = 0; b < 1024; ++b)
      count[b + 1] += count[b];
    for (const std::uint64_t k : keys)
      tmp[count[(k >> shift) & 1023u]++] = k;
    keys.swap(tmp);
  }
  std::vector<std::uint32_t>& codes = scratch.codes;
  codes.resize(static_cast<std::size_t>(n));
  for (std::int32_t i = 0; i < n; ++i) {
    const std::uint64_t k = keys[i];
    codes[i] = static_cast<std::uint32_t>(k >> 32);
    const auto src = static_cast<std::int32_t>(k & 0xffffffffu);
    out.leaves[i] = {boxes[src], ids[src]};
  }
  if (n == 1)
    return;
  scratch.parents.resize(static_cast<std::size_t>(2 * n - 1));
  karras_topology(codes.data(), n, out.nodes.data(), scratch.parents.data());
  // Boxes bottom-up: walk up from every leaf; the first child to reach a node marks it and
  // stops, the second computes the node's box and carries on.
  scratch.visits.assign(static_cast<std::size_t>(n - 1), 0);
  const std::int32_t* parents = scratch.parents.data();
  for (std::int32_t leaf = 0; leaf < n; ++leaf) {
    std::int32_t p = parents[n - 1 + leaf];
    while (p >= 0) {
      if (scratch.visits[p] == 0) {
        scratch.visits[p] = 1;
        break;
      }
      Node& node = out.nodes[p];
      node.box = TreeBox::merge(out.box(node.left), out.box(node.right));
      p = parents[p];
    }
  }
}

// Wald 2007, binned: every range is split at the best of the 15 boundaries of 16 equal bins of
// the centres, on the best axis, by the cost A(left) N(left) + A(right) N(right); coincident
// centres split in the middle. Leaves end up in the order of the final partition, so a
// subtree's leaves are contiguous.
void build_binned_sah(const TreeBox* boxes, const std::int32_t* ids, std::int32_t n, Hierarchy& out,
                      BuildScratch& scratch) {
  out.leaves.resize(static_cast<std::size_t>(n));
  out.nodes.resize(static_cast<std::size_t>(std::max(n - 1, 0)));
  if (n == 0)
    return;
  auto& refs = scratch.refs;
  refs.resize(static_cast<std::size_t>(n));
  for (std::int32_t i = 0; i < n; ++i)
    refs[i] = {boxes[i], ids[i]};
  if (n >= 2) {
    auto& tasks = scratch.tasks;
    tasks.clear();
    tasks.push_back({0, 0, n});
    std::int32_t next_node = 1;
    while (!tasks.empty()) {
      const BuildScratch::Task task = tasks.back();
      tasks.pop_back();
      const detail::BinnedSplit split = detail::binned_sah_split(refs.data(), task.begin, task.end);
      const TreeBox& bounds = split.bounds;
      const std::int32_t mid = split.mid;
      Node& node = out.nodes[task.node];
      node.box = bounds;
      if (mid - task.begin == 1) {
        node.left = ~task.begin;
      } else {
        node.left = next_node++;
      }
      if (task.end - mid == 1) {
        node.right = ~mid;
      } else {
        node.right = next_node++;
      }
      if (node.right >= 0)
        tasks.push_back({node.right, mid, task.end});
      if (node.left >= 0)
        tasks.push_back({node.left, task.begin, mid});
    }
  }
  for (std::int32_t i = 0; i < n; ++i)
    out.leaves[i] = {refs[i].box, refs[i].id};
}

}  // namespace lbvh

LinearBvhBroadPhase::DenseList& LinearBvhBroadPhase::list_of(Kind k) {
  switch (k) {
    case Kind::fixed:
      return static_list_;
    case Kind::infinite:
      return infinite_list_;
    default:
      return dynamic_list_;
  }
}

void LinearBvhBroadPhase::add_to(Kind k, std::int32_t id, const TreeBox& box) {
  DenseList& list = list_of(k);
  Proxy& p = proxies_[id];
  p.kind = k;
  p.slot = static_cast<std::int32_t>(list.ids.size());
  list.boxes.push_back(box);
  list.ids.push_back(id);
  if (k == Kind::infinite)
    infinite_static_.push_back(p.is_static);
  if (k == Kind::fixed)
    static_dirty_ = true;
}

void LinearBvhBroadPhase::remove_from(std::int32_t id) {
  Proxy& p = proxies_[id];
  DenseList& list = list_of(p.kind);
  const auto last = static_cast<std::int32_t>(list.ids.size()) - 1;
  // Swap-remove: the last entry takes the freed slot.
  list.boxes[p.slot] = list.boxes[last];
  list.ids[p.slot] = list.ids[last];
  proxies_[list.ids[p.slot]].slot = p.slot;
  if (p.kind == Kind::infinite) {
    infinite_static_[p.slot] = infinite_static_[last];
    infinite_static_.pop_back();
  }
  list.boxes.pop_back();
  list.ids.pop_back();
  if (p.kind == Kind::fixed)
    static_dirty_ = true;
  p.kind = Kind::none;
  p.slot = -1;
}

void LinearBvhBroadPhase::insert(std::int32_t id, const Aabb& aabb, bool is_static) {
  assert(id >= 0);
  if (static_cast<std::size_t>(id) >= proxies_.size())
    proxies_.resize(static_cast<std::size_t>(id) + 1);
  assert(proxies_[id].kind == Kind::none);
  const TreeBox box = TreeBox::from(aabb);
  proxies_[id].is_static = is_static;
  add_to(!box.is_finite() ? Kind::infinite : is_static ? Kind::fixed : Kind::dynamic, id, box);
  fresh_ = false;
}

void LinearBvhBroadPhase::remove(std::int32_t id) {
  assert(proxies_[id].kind != Kind::none);
  remove_from(id);
  fresh_ = false;
}

void LinearBvhBroadPhase::update(std::int32_t id, const Aabb& aabb) {
  Proxy& p = proxies_[id];
  assert(p.kind != Kind::none);
  const TreeBox box = TreeBox::from(aabb);
  const Kind kind = !box.is_finite() ? Kind::infinite : p.is_static ? Kind::fixed : Kind::dynamic;
  if (kind == p.kind) {
    list_of(kind).boxes[p.slot] = box;
    if (kind == Kind::fixed)
      static_dirty_ = true;
  } else {
    remove_from(id);
    add_to(kind, id, box);
  }
  fresh_ = false;
}

void LinearBvhBroadPhase::build(lbvh::Hierarchy& h, const DenseList& list) {
  const auto n = static_cast<std::int32_t>(list.ids.size());
  if (builder_ == Builder::morton_karras)
    lbvh::build_morton_karras(list.boxes.data(), list.ids.data(), n, h, scratch_);
  else
    lbvh::build_binned_sah(list.boxes.data(), list.ids.data(), n, h, scratch_);
}

// All pairs in id order, for piles where most pairs overlap anyway: no hierarchy can prune
// there, and enumerating in order makes the output sorted without a sort.
void LinearBvhBroadPhase::find_pairs_dense(std::vector<ProxyPair>& out) {
  out.clear();
  const auto n = static_cast<std::int32_t>(proxies_.size());
  for (std::int32_t a = 0; a < n; ++a) {
    const Proxy& pa = proxies_[a];
    if (pa.kind == Kind::none)
      continue;
    const TreeBox box = list_of(pa.kind).boxes[pa.slot];
    for (std::int32_t b = a + 1; b < n; ++b) {
      const Proxy& pb = proxies_[b];
      if (pb.kind != Kind::none && !(pa.is_static && pb.is_static) &&
          box.overlaps(list_of(pb.kind).boxes[pb.slot]))
        out.push_back({a, b});
    }
  }
}

void LinearBvhBroadPhase::find_pairs(std::vector<ProxyPair>& out) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const auto live = static_cast<std::uint64_t>(dynamic_list_.ids.size() + static_list_.ids.size() +
                                               infinite_list_.ids.size());
  if (live > 64 && 16 * last_pair_count_ > live * (live - 1)) {
    // An eighth or more of all pairs overlapped last time.
    find_pairs_dense(out);
    last_pair_count_ = out.size();
    ++stats_.dense;
    stats_.build_seconds = 0;
    stats_.traverse_seconds = std::chrono::duration<double>(clock::now() - t0).count();
    return;
  }
  build(dynamic_, dynamic_list_);
  ++stats_.builds;
  if (static_dirty_) {
    build(static_, static_list_);
    static_dirty_ = false;
    ++stats_.static_builds;
  }
  fresh_ = true;
  const auto t1 = clock::now();

  keys_.clear();
  lbvh::self_pairs(dynamic_, [&](std::int32_t a, std::int32_t b) {
    emit(dynamic_.leaves[a].id, dynamic_.leaves[b].id);
  });
  lbvh::dual_pairs(dynamic_, static_, [&](std::int32_t a, std::int32_t b) {
    emit(dynamic_.leaves[a].id, static_.leaves[b].id);
  });
  const auto n_inf = static_cast<std::int32_t>(infinite_list_.ids.size());
  for (std::int32_t i = 0; i < n_inf; ++i) {
    const TreeBox& box = infinite_list_.boxes[i];
    const std::int32_t id = infinite_list_.ids[i];
    const auto overlaps = [&](const TreeBox& b) { return b.overlaps(box); };
    lbvh::descend(dynamic_, overlaps,
                  [&](std::int32_t leaf) { emit(id, dynamic_.leaves[leaf].id); });
    if (!infinite_static_[i]) {
      lbvh::descend(static_, overlaps,
                    [&](std::int32_t leaf) { emit(id, static_.leaves[leaf].id); });
    }
    for (std::int32_t j = i + 1; j < n_inf; ++j) {
      if (!(infinite_static_[i] && infinite_static_[j]) && box.overlaps(infinite_list_.boxes[j]))
        emit(id, infinite_list_.ids[j]);
    }
  }
  // Each pair is found exactly once (a binary tree's self traversal and a dual traversal of two
  // disjoint sets never repeat a pair), so sorting is all that is left.
  tree_detail::sort_pair_keys(keys_, static_cast<std::int32_t>(proxies_.size()), keys_tmp_,
                              sort_counts_);
  out.resize(keys_.size());
  for (std::size_t i = 0; i < keys_.size(); ++i)
    out[i] = {tree_detail::key_first(keys_[i]), tree_detail::key_second(keys_[i])};
  last_pair_count_ = out.size();
  const auto t2 = clock::now();
  stats_.build_seconds = std::chrono::duration<double>(t1 - t0).count();
  stats_.traverse_seconds = std::chrono::duration<double>(t2 - t1).count();
}

void LinearBvhBroadPhase::query(const Aabb& aabb, std::vector<std::int32_t>& out) const {
  out.clear();
  const TreeBox box = TreeBox::from(aabb);
  const auto overlaps = [&](const TreeBox& b) { return b.overlaps(box); };
  if (fresh_) {
    lbvh::descend(dynamic_, overlaps,
                  [&](std::int32_t leaf) { out.push_back(dynamic_.leaves[leaf].id); });
    lbvh::descend(static_, overlaps,
                  [&](std::int32_t leaf) { out.push_back(static_.leaves[leaf].id); });
  } else {
    for (const DenseList* list : {&dynamic_list_, &static_list_}) {
      for (std::size_t i = 0; i < list->ids.size(); ++i) {
        if (list->boxes[i].overlaps(box))
          out.push_back(list->ids[i]);
      }
    }
  }
  for (std::size_t i = 0; i < infinite_list_.ids.size(); ++i) {
    if (infinite_list_.boxes[i].overlaps(box))
      out.push_back(infinite_list_.ids[i]);
  }
  std::sort(out.begin(), out.end());
}

void LinearBvhBroadPhase::ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                                   std::vector<std::int32_t>& out) const {
  out.clear();
  const SegmentProbe probe(origin, direction, max_t);
  const auto touches = [&](const TreeBox& b) { return probe.touches(b); };
  const auto hit = [&](const TreeBox& b) {
    return segment_touches_aabb(origin, direction, max_t, b.to_aabb());
  };
  if (fresh_) {
    for (const lbvh::Hierarchy* h : {&dynamic_, &static_}) {
      lbvh::descend(*h, touches, [&](std::int32_t leaf) {
        if (hit(h->leaves[leaf].box))
          out.push_back(h->leaves[leaf].id);
      });
    }
  } else {
    for (const DenseList* list : {&dynamic_list_, &static_list_}) {
      for (std::size_t i = 0; i < list->ids.size(); ++i) {
        if (hit(list->boxes[i]))
          out.push_back(list->ids[i]);
      }
    }
  }
  for (std::size_t i = 0; i < infinite_list_.ids.size(); ++i) {
    if (hit(infinite_list_.boxes[i]))
      out.push_back(infinite_list_.ids[i]);
  }
  std::sort(out.begin(), out.end());
}

}  // namespace tumble
