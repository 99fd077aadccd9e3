#include "collision/broad_phase/kd_tree_broad_phase.hpp"
#include "collision/broad_phase/pair_keys.hpp"

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
      n, [&](std::int32_t i) -> const Aabb& { return slots_.proxies[slots[i]].box; }, bounds);
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
      bounds.grow(slots_.proxies[work_[i]].box);
    s = find_split(work_.data() + begin, n, bounds);
    split = s.axis >= 0 && s.cost < Real(n);
  }
  if (split) {
    // Three-way partition into [straddlers | left | right] with the exact classification.
    const int a = s.axis;
    std::int32_t mid = begin;
    while (mid < hi) {
      const Aabb& b = slots_.proxies[work_[mid]].box;
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
  for (std::size_t s = 0; s < slots_.proxies.size(); ++s) {
    if (slots_.proxies[s].alive && slots_.proxies[s].node >= 0)
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
  slots_.link(nodes_, slot, node);
}

void KdTreeBroadPhase::unlink(std::int32_t slot) {
  slots_.unlink(nodes_, slot);
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
  if (slots_.slot_of(id) >= 0)
    remove(id);
  const std::int32_t slot = slots_.add(id, box, is_static);
  if (is_unbounded(box)) {
    unbounded_.push_back(slot);
    return;
  }
  link(slot, descend(0, box));
  ++bounded_count_;
  ++inserted_since_build_;
}

void KdTreeBroadPhase::remove(std::int32_t id) {
  const std::int32_t slot = slots_.slot_of(id);
  if (slot < 0)
    return;
  Proxy& p = slots_.proxies[slot];
  if (p.node >= 0) {
    unlink(slot);
    --bounded_count_;
  } else {
    unbounded_.erase(std::find(unbounded_.begin(), unbounded_.end(), slot));
  }
  slots_.free(id);
}

void KdTreeBroadPhase::update(std::int32_t id, const Aabb& box) {
  const std::int32_t slot = slots_.slot_of(id);
  Proxy& p = slots_.proxies[slot];
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

// Writes the proxies out in node preorder (nodes_ is in preorder already): see
// collision/broad_phase/packed_proxy_tree.hpp.
void KdTreeBroadPhase::pack() {
  const auto count = static_cast<std::int32_t>(nodes_.size());
  packed_.start(count);
  for (std::int32_t j = 0; j < count; ++j) {
    const Node& node = nodes_[j];
    packed_.set_node(j, node.parent, node.skip, node.count - node.static_count, node.static_count);
  }
  packed_.allocate();
  for (const Proxy& p : slots_.proxies) {
    if (p.alive && p.node >= 0)
      packed_.place(p.node, p.box, p.id, p.is_static);
  }
  packed_.finish();
}

void KdTreeBroadPhase::search_node(std::int32_t n) {
  const std::int32_t begin = packed_.dynamic_begin(n);
  const std::int32_t end = packed_.dynamic_end(n);
  if (nodes_[n].axis < 0) {
    packed_.search_group(n, begin, end, keys_);
    return;
  }
  // Straddlers of one plane spread over the whole plane, so the union of their boxes is a slab
  // that would meet most of the subtree: each one searches with its own box instead.
  for (std::int32_t i = begin; i < end; ++i)
    packed_.search_group(n, i, i + 1, keys_);
}

void KdTreeBroadPhase::find_pairs(std::vector<ProxyPair>& out) {
  keys_.clear();
  packed_.reset_counters();
  const bool many_inserted = inserted_since_build_ > built_count_ / 4 + options_.leaf_size;
  if (options_.rebuild == KdTreeOptions::Rebuild::every_step || rebuild_due_ || many_inserted)
    rebuild();
  pack();
  for (std::int32_t n = 0; n < packed_.node_count(); ++n) {
    if (packed_.dynamic_end(n) > packed_.dynamic_begin(n))
      search_node(n);
  }
  // Unbounded proxies stay outside the tree; bounded proxies never look at them, so each such
  // pair is seen once, here.
  for (const std::int32_t s : unbounded_)
    packed_.search_outsider(slots_.proxies[s].box, slots_.proxies[s].id,
                            slots_.proxies[s].is_static, keys_);
  for (std::size_t i = 0; i < unbounded_.size(); ++i) {
    const Proxy& a = slots_.proxies[unbounded_[i]];
    for (std::size_t j = i + 1; j < unbounded_.size(); ++j) {
      const Proxy& b = slots_.proxies[unbounded_[j]];
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
    const double work = double(packed_.box_tests() + packed_.node_visits()) /
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
    for (std::int32_t s = node.head; s >= 0; s = slots_.proxies[s].next) {
      if (slots_.proxies[s].box.overlaps(box))
        out.push_back(slots_.proxies[s].id);
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
    if (slots_.proxies[s].box.overlaps(box))
      out.push_back(slots_.proxies[s].id);
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
  for (std::int32_t s = node.head; s >= 0; s = slots_.proxies[s].next) {
    if (segment_touches_aabb(o, d, max_t, slots_.proxies[s].box))
      out.push_back(slots_.proxies[s].id);
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
    if (segment_touches_aabb(origin, direction, max_t, slots_.proxies[s].box))
      out.push_back(slots_.proxies[s].id);
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
  s.box_tests = packed_.box_tests();
  s.node_visits = packed_.node_visits();
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
