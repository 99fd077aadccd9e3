#include "collision/kd_tree_broad_phase.hpp"
#include "collision/pair_keys.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>

namespace tumble {
namespace {

constexpr Real kInf = std::numeric_limits<Real>::infinity();
// A coordinate beyond this is treated as infinite: the cost model multiplies extents, and boxes
// that large are planes or half spaces in all but name.
constexpr Real kUnboundedCoordinate = 1e30;

bool inside(const Aabb& outer, const Aabb& inner) {
  return (inner.min.array() >= outer.min.array()).all() &&
         (inner.max.array() <= outer.max.array()).all();
}

// Aabb::overlaps without short-circuit branches: in the inner loops the outcome is close to a
// coin flip per comparison, and six well-predicted-or-not branches cost more than six compares.
inline bool touch(const Aabb& a, const Aabb& b) {
  return (a.min.x() <= b.max.x()) & (b.min.x() <= a.max.x()) & (a.min.y() <= b.max.y()) &
         (b.min.y() <= a.max.y()) & (a.min.z() <= b.max.z()) & (b.min.z() <= a.max.z());
}

// A node's own list longer than this is sorted by min along its longest axis, so the loops over
// it can stop at the first box that starts beyond the query's end (sweep and prune within the
// list). Shorter lists are scanned whole: sorting them would cost more than it saves.
constexpr std::int32_t kSweepThreshold = 12;

// Sorts boxes[begin, end) by min along the longest axis of `bound` if the range is long, and
// returns that axis; -1 (unsorted, scan everything) otherwise.
template <class PackedBoxes>
std::int8_t sort_for_sweep(PackedBoxes& boxes, std::int32_t begin, std::int32_t end,
                           const Aabb& bound) {
  if (end - begin <= kSweepThreshold)
    return -1;
  int axis = 0;
  (bound.max - bound.min).maxCoeff(&axis);
  std::sort(boxes.begin() + begin, boxes.begin() + end,
            [axis](const auto& x, const auto& y) { return x.box.min[axis] < y.box.min[axis]; });
  return static_cast<std::int8_t>(axis);
}

// The bound a loop over a node's own list may stop at: the query's max along the list's sort
// axis, or +inf for an unsorted list.
inline Real sweep_limit(const Aabb& query, int axis) {
  return axis >= 0 ? query.max[axis] : std::numeric_limits<Real>::infinity();
}

using detail::pair_key;

Aabb everything() {
  return {Vec3::Constant(-kInf), Vec3::Constant(kInf)};
}

}  // namespace

KdTreeBroadPhase::KdTreeBroadPhase(const KdTreeOptions& options) : options_(options) {
  options_.leaf_size = std::max(options_.leaf_size, 1);
  options_.bins = std::clamp(options_.bins, 2, 256);
  options_.max_depth = std::clamp(options_.max_depth, 0, 200);
  reset_to_single_leaf();
}

bool KdTreeBroadPhase::is_unbounded(const Aabb& box) {
  // Written so that NaN counts as unbounded too (it then overlaps nothing, like brute force).
  return !((box.min.array() >= -kUnboundedCoordinate).all() &&
           (box.max.array() <= kUnboundedCoordinate).all());
}

void KdTreeBroadPhase::reset_to_single_leaf() {
  nodes_.clear();
  nodes_.emplace_back();
  nodes_[0].cell = everything();
  nodes_[0].skip = 1;
}

// ---------------------------------------------------------------------------------------------
// Build

template <class BoxOf>
KdTreeBroadPhase::Split KdTreeBroadPhase::find_split_impl(std::int32_t n, const BoxOf& box_of,
                                                          const Aabb& bounds) const {
  Split best;
  best.cost = kInf;
  if (n < 2)
    return best;
  Vec3 r = Vec3::Zero();  // mean half extent of the boxes: the Minkowski growth of the regions
  for (std::int32_t i = 0; i < n; ++i) {
    const Aabb& b = box_of(i);
    r += b.max - b.min;
  }
  r *= Real(0.5) / Real(n);
  const int bins = options_.bins;
  std::uint32_t count_min[256];
  std::uint32_t count_max[256];
  for (int a = 0; a < 3; ++a) {
    const Real lo = bounds.min[a];
    const Real hi = bounds.max[a];
    const Real len = hi - lo;
    if (!(len > 0))
      continue;
    const Real scale = Real(bins) / len;
    std::fill(count_min, count_min + bins, 0u);
    std::fill(count_max, count_max + bins, 0u);
    for (std::int32_t i = 0; i < n; ++i) {
      const Aabb& b = box_of(i);
      const int bmin = std::min(static_cast<int>((b.min[a] - lo) * scale), bins - 1);
      const int bmax = std::min(static_cast<int>((b.max[a] - lo) * scale), bins - 1);
      ++count_min[std::max(bmin, 0)];
      ++count_max[std::max(bmax, 0)];
    }
    const Real grown = len + 2 * r[a];  // V' along this axis; the other two factors cancel
    std::int64_t left = 0;              // boxes whose max is below the plane
    std::int64_t right = n;             // boxes whose min is at or above the plane
    for (int i = 1; i < bins; ++i) {
      left += count_max[i - 1];
      right -= count_min[i - 1];
      const std::int64_t straddle = n - left - right;
      const Real p = lo + len * (Real(i) / Real(bins));
      const Real cost =
          options_.traversal_cost + (Real(left) * (p - lo + 2 * r[a]) +
                                     Real(right) * (hi - p + 2 * r[a]) + Real(straddle) * grown) /
                                        grown;
      if (cost < best.cost)
        best = {a, p, cost};
    }
  }
  return best;
}

KdTreeBroadPhase::Split KdTreeBroadPhase::find_split(const std::int32_t* slots, std::int32_t n,
                                                     const Aabb& bounds) const {
  return find_split_impl(
      n, [&](std::int32_t i) -> const Aabb& { return proxies_[slots[i]].box; }, bounds);
}

KdTreeBroadPhase::SplitChoice KdTreeBroadPhase::best_split(const std::vector<Aabb>& boxes) const {
  Aabb bounds;
  for (const Aabb& b : boxes)
    bounds.grow(b);
  const auto n = static_cast<std::int32_t>(boxes.size());
  const Split s = find_split_impl(
      n, [&](std::int32_t i) -> const Aabb& { return boxes[i]; }, bounds);
  return {s.axis, s.plane, s.cost, Real(n)};
}

// Builds the subtree of work_[begin, end) in preorder at the end of nodes_; returns its index.
std::int32_t KdTreeBroadPhase::build_node(std::int32_t begin, std::int32_t end, const Aabb& cell,
                                          std::int32_t parent, int depth) {
  const auto j = static_cast<std::int32_t>(nodes_.size());
  nodes_.emplace_back();
  nodes_[j].cell = cell;
  nodes_[j].parent = parent;
  nodes_[j].depth = depth;
  const std::int32_t n = end - begin;
  bool split = false;
  Split s;
  std::int32_t lo = begin, hi = end;
  if (n > options_.leaf_size && depth < options_.max_depth) {
    Aabb bounds;
    for (std::int32_t i = begin; i < end; ++i)
      bounds.grow(proxies_[work_[i]].box);
    s = find_split(work_.data() + begin, n, bounds);
    split = s.axis >= 0 && s.cost < Real(n);
  }
  if (split) {
    // Three-way partition into [straddlers | left | right] with the exact classification.
    const int a = s.axis;
    std::int32_t mid = begin;
    while (mid < hi) {
      const Aabb& b = proxies_[work_[mid]].box;
      if (b.max[a] <= s.plane) {
        ++mid;  // left
      } else if (b.min[a] >= s.plane) {
        std::swap(work_[mid], work_[--hi]);  // right
      } else {
        std::swap(work_[mid++], work_[lo++]);  // straddler
      }
    }
    // The binned estimate can differ from the exact classification; a split that leaves every
    // box on one side (or straddling) makes no progress.
    if (lo - begin == n || hi - lo == n || end - hi == n)
      split = false;
  }
  if (!split) {
    for (std::int32_t i = begin; i < end; ++i)
      link(work_[i], j);
    nodes_[j].skip = j + 1;
    return j;
  }
  for (std::int32_t i = begin; i < lo; ++i)
    link(work_[i], j);
  nodes_[j].axis = static_cast<std::int8_t>(s.axis);
  nodes_[j].split = s.plane;
  Aabb left_cell = cell, right_cell = cell;
  left_cell.max[s.axis] = s.plane;
  right_cell.min[s.axis] = s.plane;
  build_node(lo, hi, left_cell, j, depth + 1);  // lands at j + 1
  const std::int32_t right = build_node(hi, end, right_cell, j, depth + 1);
  nodes_[j].right = right;
  nodes_[j].skip = static_cast<std::int32_t>(nodes_.size());
  return j;
}

void KdTreeBroadPhase::rebuild() {
  work_.clear();
  for (std::size_t s = 0; s < proxies_.size(); ++s) {
    if (proxies_[s].alive && proxies_[s].node >= 0)
      work_.push_back(static_cast<std::int32_t>(s));
  }
  nodes_.clear();
  build_node(0, static_cast<std::int32_t>(work_.size()), everything(), -1, 0);
  ++rebuilds_;
  built_count_ = static_cast<std::int32_t>(work_.size());
  inserted_since_build_ = 0;
  measure_baseline_ = true;
  rebuild_due_ = false;
}

// ---------------------------------------------------------------------------------------------
// Proxies in nodes

void KdTreeBroadPhase::link(std::int32_t slot, std::int32_t node) {
  Proxy& p = proxies_[slot];
  Node& n = nodes_[node];
  p.node = node;
  p.prev = -1;
  p.next = n.head;
  if (n.head >= 0)
    proxies_[n.head].prev = slot;
  n.head = slot;
  ++n.count;
  n.static_count += p.is_static ? 1 : 0;
}

void KdTreeBroadPhase::unlink(std::int32_t slot) {
  Proxy& p = proxies_[slot];
  Node& n = nodes_[p.node];
  if (p.prev >= 0)
    proxies_[p.prev].next = p.next;
  else
    n.head = p.next;
  if (p.next >= 0)
    proxies_[p.next].prev = p.prev;
  --n.count;
  n.static_count -= p.is_static ? 1 : 0;
  p.node = -1;
  p.next = p.prev = -1;
}

// From a node whose cell holds the box, down while the box is on one side of the plane.
std::int32_t KdTreeBroadPhase::descend(std::int32_t from, const Aabb& box) const {
  std::int32_t n = from;
  while (nodes_[n].axis >= 0) {
    const Node& node = nodes_[n];
    if (box.max[node.axis] <= node.split)
      n = n + 1;
    else if (box.min[node.axis] >= node.split)
      n = node.right;
    else
      break;
  }
  return n;
}

// ---------------------------------------------------------------------------------------------
// BroadPhase interface

void KdTreeBroadPhase::insert(std::int32_t id, const Aabb& box, bool is_static) {
  assert(id >= 0);
  if (static_cast<std::size_t>(id) >= slot_of_id_.size())
    slot_of_id_.resize(static_cast<std::size_t>(id) + 1, -1);
  if (slot_of_id_[id] >= 0)
    remove(id);
  std::int32_t slot;
  if (!free_slots_.empty()) {
    slot = free_slots_.back();
    free_slots_.pop_back();
  } else {
    slot = static_cast<std::int32_t>(proxies_.size());
    proxies_.emplace_back();
  }
  slot_of_id_[id] = slot;
  Proxy& p = proxies_[slot];
  p = Proxy{};
  p.box = box;
  p.id = id;
  p.is_static = is_static;
  p.alive = true;
  if (is_unbounded(box)) {
    unbounded_.push_back(slot);
    return;
  }
  link(slot, descend(0, box));
  ++bounded_count_;
  ++inserted_since_build_;
}

void KdTreeBroadPhase::remove(std::int32_t id) {
  if (id < 0 || static_cast<std::size_t>(id) >= slot_of_id_.size() || slot_of_id_[id] < 0)
    return;
  const std::int32_t slot = slot_of_id_[id];
  Proxy& p = proxies_[slot];
  if (p.node >= 0) {
    unlink(slot);
    --bounded_count_;
  } else {
    unbounded_.erase(std::find(unbounded_.begin(), unbounded_.end(), slot));
  }
  p.alive = false;
  slot_of_id_[id] = -1;
  free_slots_.push_back(slot);
}

void KdTreeBroadPhase::update(std::int32_t id, const Aabb& box) {
  const std::int32_t slot = slot_of_id_[id];
  Proxy& p = proxies_[slot];
  const bool unbounded = is_unbounded(box);
  p.box = box;
  if (p.node < 0) {  // was unbounded
    if (unbounded)
      return;
    unbounded_.erase(std::find(unbounded_.begin(), unbounded_.end(), slot));
    link(slot, descend(0, box));
    ++bounded_count_;
    return;
  }
  if (unbounded) {
    unlink(slot);
    --bounded_count_;
    unbounded_.push_back(slot);
    return;
  }
  // Fast path for coherent motion: still inside the node's cell, and at an internal node still
  // across its plane.
  const std::int32_t n = p.node;
  const Node& node = nodes_[n];
  std::int32_t from = n;
  if (inside(node.cell, box)) {
    if (node.axis < 0)
      return;
    if (!(box.max[node.axis] <= node.split) && !(box.min[node.axis] >= node.split))
      return;
  } else {
    // Up to the first ancestor whose cell holds the box (the root's cell is all of space).
    from = node.parent;
    while (!inside(nodes_[from].cell, box))
      from = nodes_[from].parent;
  }
  const std::int32_t to = descend(from, box);
  if (to != n) {
    unlink(slot);
    link(slot, to);
  }
}

// Writes the proxies out in node preorder (nodes_ is in preorder already): dynamic and static
// proxies in two arrays, each node a contiguous range of both, with its subtree's end and the
// exact bounds of its subtree's boxes (the refit).
void KdTreeBroadPhase::pack() {
  const auto count = static_cast<std::int32_t>(nodes_.size());
  dyn_nodes_.resize(static_cast<std::size_t>(count));
  st_nodes_.resize(static_cast<std::size_t>(count));
  std::int32_t dyn_total = 0, st_total = 0;
  for (std::int32_t j = 0; j < count; ++j) {
    const Node& node = nodes_[j];
    PackedNode& d = dyn_nodes_[j];
    PackedNode& st = st_nodes_[j];
    d.skip = st.skip = node.skip;
    d.bound = st.bound = Aabb{};
    d.begin = d.end = dyn_total;  // end is the scatter cursor for now
    dyn_total += node.count - node.static_count;
    st.begin = st.end = st_total;
    st_total += node.static_count;
  }
  dyn_axis_.resize(static_cast<std::size_t>(count));
  st_axis_.resize(static_cast<std::size_t>(count));
  dyn_own_.resize(static_cast<std::size_t>(count));
  st_own_.resize(static_cast<std::size_t>(count));
  dyn_.resize(static_cast<std::size_t>(dyn_total));
  st_.resize(static_cast<std::size_t>(st_total));
  for (const Proxy& p : proxies_) {
    if (!p.alive || p.node < 0)
      continue;
    if (p.is_static)
      st_[st_nodes_[p.node].end++] = {p.box, p.id};
    else
      dyn_[dyn_nodes_[p.node].end++] = {p.box, p.id};
  }
  for (std::int32_t j = 0; j < count; ++j) {
    PackedNode& d = dyn_nodes_[j];
    PackedNode& st = st_nodes_[j];
    d.sub_end = d.end;
    st.sub_end = st.end;
    for (std::int32_t i = d.begin; i < d.end; ++i)
      d.bound.grow(dyn_[i].box);
    for (std::int32_t i = st.begin; i < st.end; ++i)
      st.bound.grow(st_[i].box);
    dyn_own_[j] = d.bound;
    st_own_[j] = st.bound;
    dyn_axis_[j] = sort_for_sweep(dyn_, d.begin, d.end, d.bound);
    st_axis_[j] = sort_for_sweep(st_, st.begin, st.end, st.bound);
  }
  for (std::int32_t j = count - 1; j > 0; --j) {
    const std::int32_t p = nodes_[j].parent;
    for (std::vector<PackedNode>* v : {&dyn_nodes_, &st_nodes_}) {
      const PackedNode& c = (*v)[j];
      PackedNode& q = (*v)[p];
      q.sub_end = std::max(q.sub_end, c.sub_end);
      q.bound.grow(c.bound);
    }
  }
}

void KdTreeBroadPhase::search_node(std::int32_t n) {
  const std::int32_t begin = dyn_nodes_[n].begin;
  const std::int32_t end = dyn_nodes_[n].end;
  if (nodes_[n].axis < 0) {
    search_group(n, begin, end);
    return;
  }
  // Straddlers of one plane spread over the whole plane, so the union of their boxes is a slab
  // that would meet most of the subtree: each one searches with its own box instead.
  for (std::int32_t i = begin; i < end; ++i)
    search_group(n, i, i + 1);
}

// The dynamic proxies [db, de) of packed node n (a leaf's whole range, or one straddler) against
// the rest, sharing one walk with the union of their boxes.
void KdTreeBroadPhase::search_group(std::int32_t n, std::int32_t db, std::int32_t de) {
  Aabb u;
  for (std::int32_t i = db; i < de; ++i)
    u.grow(dyn_[i].box);
  const auto count = static_cast<std::int32_t>(dyn_nodes_.size());
  // Dynamic partners come later in preorder: every node before n is an ancestor of n or in a
  // subtree that ends before n, so its dynamic range lies before db. Walk forward from n.
  std::int32_t j = n;
  while (j < count) {
    const PackedNode& m = dyn_nodes_[j];
    ++node_visits_;
    if (m.sub_end <= std::max(m.begin, db + 1) || !touch(m.bound, u)) {
      j = m.skip;
      continue;
    }
    const Aabb& own = dyn_own_[j];
    const int sort_axis = dyn_axis_[j];
    const int axis = std::max(sort_axis, 0);
    for (std::int32_t i = db; i < de; ++i) {
      const std::int32_t kb = std::max(m.begin, i + 1);
      if (kb >= m.end)
        break;  // kb only grows with i
      const Aabb& a = dyn_[i].box;
      if (!touch(a, own))
        continue;
      // The range is sorted by min along `axis` when long: stop at the first box starting
      // beyond a's end (a sweep over the node's own list).
      const Real limit = sweep_limit(a, sort_axis);
      std::int32_t k = kb;
      for (; k < m.end && dyn_[k].box.min[axis] <= limit; ++k) {
        if (touch(a, dyn_[k].box))
          keys_.push_back(pair_key(dyn_[i].id, dyn_[k].id));
      }
      box_tests_ += k - kb;
    }
    ++j;
  }
  // Static partners can be anywhere: walk the static hierarchy from the root.
  if (st_.empty())
    return;
  j = 0;
  while (j < count) {
    const PackedNode& m = st_nodes_[j];
    ++node_visits_;
    if (m.sub_end == m.begin || !touch(m.bound, u)) {
      j = m.skip;
      continue;
    }
    if (m.end > m.begin && touch(st_own_[j], u)) {
      const Aabb& own = st_own_[j];
      const int sort_axis = st_axis_[j];
      const int axis = std::max(sort_axis, 0);
      for (std::int32_t i = db; i < de; ++i) {
        const Aabb& a = dyn_[i].box;
        if (!touch(a, own))
          continue;
        const Real limit = sweep_limit(a, sort_axis);
        std::int32_t k = m.begin;
        for (; k < m.end && st_[k].box.min[axis] <= limit; ++k) {
          if (touch(a, st_[k].box))
            keys_.push_back(pair_key(dyn_[i].id, st_[k].id));
        }
        box_tests_ += k - m.begin;
      }
    }
    ++j;
  }
}

// An unbounded proxy against every bounded one (bounded proxies never look at the unbounded
// list, so each such pair is seen once, here). Comparisons with infinities are well defined.
void KdTreeBroadPhase::search_unbounded(std::int32_t slot) {
  const Proxy& x = proxies_[slot];
  const auto count = static_cast<std::int32_t>(dyn_nodes_.size());
  for (int kind = 0; kind < 2; ++kind) {
    if (kind == 1 && x.is_static)
      break;  // static-static pairs are never reported
    const std::vector<PackedNode>& tree = kind == 0 ? dyn_nodes_ : st_nodes_;
    const std::vector<PackedBox>& boxes = kind == 0 ? dyn_ : st_;
    const std::vector<Aabb>& own = kind == 0 ? dyn_own_ : st_own_;
    const std::vector<std::int8_t>& axes = kind == 0 ? dyn_axis_ : st_axis_;
    std::int32_t j = 0;
    while (j < count) {
      const PackedNode& m = tree[j];
      ++node_visits_;
      if (m.sub_end == m.begin || !touch(m.bound, x.box)) {
        j = m.skip;
        continue;
      }
      if (!touch(own[j], x.box)) {
        ++j;
        continue;
      }
      const int axis = std::max<int>(axes[j], 0);
      const Real limit = sweep_limit(x.box, axes[j]);
      std::int32_t k = m.begin;
      for (; k < m.end && boxes[k].box.min[axis] <= limit; ++k) {
        if (touch(x.box, boxes[k].box))
          keys_.push_back(pair_key(x.id, boxes[k].id));
      }
      box_tests_ += k - m.begin;
      ++j;
    }
  }
}

void KdTreeBroadPhase::find_pairs(std::vector<ProxyPair>& out) {
  keys_.clear();
  box_tests_ = 0;
  node_visits_ = 0;
  const bool many_inserted = inserted_since_build_ > built_count_ / 4 + options_.leaf_size;
  if (options_.rebuild == KdTreeOptions::Rebuild::every_step || rebuild_due_ || many_inserted)
    rebuild();
  pack();
  for (auto n = 0; n < static_cast<std::int32_t>(dyn_nodes_.size()); ++n) {
    if (dyn_nodes_[n].end > dyn_nodes_[n].begin)
      search_node(n);
  }
  for (const std::int32_t s : unbounded_)
    search_unbounded(s);
  for (std::size_t i = 0; i < unbounded_.size(); ++i) {
    const Proxy& a = proxies_[unbounded_[i]];
    for (std::size_t j = i + 1; j < unbounded_.size(); ++j) {
      const Proxy& b = proxies_[unbounded_[j]];
      if (!(a.is_static && b.is_static) && a.box.overlaps(b.box))
        keys_.push_back(pair_key(a.id, b.id));
    }
  }
  detail::radix_sort_pair_keys(keys_, sort_scratch_);
  out.resize(keys_.size());
  for (std::size_t i = 0; i < keys_.size(); ++i) {
    out[i].a = static_cast<std::int32_t>(keys_[i] >> 32);
    out[i].b = static_cast<std::int32_t>(keys_[i] & 0xffffffffu);
  }
  // Rebuild trigger: the work of this search per unit of output (pairs found plus proxies, so
  // an empty scene is not free) against the same right after the build. Relative to the output,
  // so that both a tree whose leaves fill up (work grows) and a tree built for a crowd that has
  // since spread out (pairs fall, work does not) are caught.
  if (options_.rebuild == KdTreeOptions::Rebuild::on_degradation && bounded_count_ > 0) {
    const double work = double(box_tests_ + node_visits_) /
                        double(keys_.size() + static_cast<std::size_t>(bounded_count_));
    if (measure_baseline_) {
      baseline_work_ = work;
      measure_baseline_ = false;
    } else if (work > options_.degradation * baseline_work_ + 0.5) {
      rebuild_due_ = true;
    }
  }
}

void KdTreeBroadPhase::query_node(std::int32_t n, const Aabb& box,
                                  std::vector<std::int32_t>& out) const {
  while (true) {
    const Node& node = nodes_[n];
    for (std::int32_t s = node.head; s >= 0; s = proxies_[s].next) {
      if (proxies_[s].box.overlaps(box))
        out.push_back(proxies_[s].id);
    }
    if (node.axis < 0)
      return;
    const bool left = box.min[node.axis] <= node.split;
    const bool right = box.max[node.axis] >= node.split;
    if (left && right)
      query_node(n + 1, box, out);
    else if (!left && !right)
      return;  // NaN query
    n = right ? node.right : n + 1;
  }
}

void KdTreeBroadPhase::query(const Aabb& box, std::vector<std::int32_t>& out) const {
  out.clear();
  query_node(0, box, out);
  for (const std::int32_t s : unbounded_) {
    if (proxies_[s].box.overlaps(box))
      out.push_back(proxies_[s].id);
  }
  std::sort(out.begin(), out.end());
}

// Cells contain every box of their subtree, and the slab test is monotone in the box, so a
// segment that misses a cell misses everything below it.
void KdTreeBroadPhase::ray_node(std::int32_t n, const Vec3& o, const Vec3& d, Real max_t,
                                std::vector<std::int32_t>& out) const {
  const Node& node = nodes_[n];
  if (!segment_touches_aabb(o, d, max_t, node.cell))
    return;
  for (std::int32_t s = node.head; s >= 0; s = proxies_[s].next) {
    if (segment_touches_aabb(o, d, max_t, proxies_[s].box))
      out.push_back(proxies_[s].id);
  }
  if (node.axis >= 0) {
    ray_node(n + 1, o, d, max_t, out);
    ray_node(node.right, o, d, max_t, out);
  }
}

void KdTreeBroadPhase::ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                                std::vector<std::int32_t>& out) const {
  out.clear();
  ray_node(0, origin, direction, max_t, out);
  for (const std::int32_t s : unbounded_) {
    if (segment_touches_aabb(origin, direction, max_t, proxies_[s].box))
      out.push_back(proxies_[s].id);
  }
  std::sort(out.begin(), out.end());
}

// ---------------------------------------------------------------------------------------------
// Inspection

KdTreeBroadPhase::Stats KdTreeBroadPhase::stats() const {
  Stats s;
  s.nodes = static_cast<int>(nodes_.size());
  for (const Node& n : nodes_) {
    s.depth = std::max(s.depth, static_cast<int>(n.depth));
    if (n.axis < 0)
      ++s.leaves;
    else
      s.straddlers += n.count;
  }
  s.unbounded = static_cast<int>(unbounded_.size());
  s.rebuilds = rebuilds_;
  s.box_tests = box_tests_;
  s.node_visits = node_visits_;
  return s;
}

std::vector<KdTreeBroadPhase::NodeInfo> KdTreeBroadPhase::node_infos() const {
  std::vector<NodeInfo> infos(nodes_.size());
  for (std::size_t j = 0; j < nodes_.size(); ++j) {
    const Node& n = nodes_[j];
    infos[j] = {n.depth, n.axis < 0, n.axis, n.split, n.count, n.count};
  }
  for (std::size_t j = nodes_.size(); j-- > 1;)
    infos[static_cast<std::size_t>(nodes_[j].parent)].subtree += infos[j].subtree;
  return infos;
}

}  // namespace tumble
