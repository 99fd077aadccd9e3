#include "collision/broad_phase/packed_proxy_tree.hpp"

#include <algorithm>
#include <limits>

#include "collision/broad_phase/pair_keys.hpp"

namespace tumble::detail {
namespace {

// Aabb::overlaps without short-circuit branches: in the inner loops the outcome is close to a
// coin flip per comparison, and six well-predicted-or-not branches cost more than six compares.
inline bool touch(const Aabb& a, const Aabb& b) {
  return (int(a.min.x() <= b.max.x()) & int(b.min.x() <= a.max.x()) & int(a.min.y() <= b.max.y()) &
          int(b.min.y() <= a.max.y()) & int(a.min.z() <= b.max.z()) &
          int(b.min.z() <= a.max.z())) != 0;
}

// A node's own list longer than this is sorted by min along its longest axis, so the loops over
// it can stop at the first box that starts beyond the query's end (sweep and prune within the
// list). Shorter lists are scanned whole: sorting them would cost more than it saves.
constexpr std::int32_t kSweepThreshold = 12;

// Sorts boxes[begin, end) by min along the longest axis of `bound` if the range is long, and
// returns that axis; -1 (unsorted, scan everything) otherwise.
template <class Boxes>
std::int8_t sort_for_sweep(Boxes& boxes, std::int32_t begin, std::int32_t end, const Aabb& bound) {
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

}  // namespace

void PackedProxyTree::start(std::int32_t node_count) {
  const auto n = static_cast<std::size_t>(node_count);
  dynamic_nodes_.resize(n);
  static_nodes_.resize(n);
  parent_.resize(n);
  dynamic_axis_.resize(n);
  static_axis_.resize(n);
  dynamic_own_.resize(n);
  static_own_.resize(n);
  dynamic_total_ = static_total_ = 0;
}

void PackedProxyTree::set_node(std::int32_t j, std::int32_t parent, std::int32_t skip,
                               std::int32_t dynamic_count, std::int32_t static_count) {
  Node& d = dynamic_nodes_[j];
  Node& s = static_nodes_[j];
  parent_[j] = parent;
  d.skip = s.skip = skip;
  d.bound = s.bound = Aabb{};
  d.begin = d.end = dynamic_total_;  // end is the scatter cursor until finish()
  dynamic_total_ += dynamic_count;
  s.begin = s.end = static_total_;
  static_total_ += static_count;
}

void PackedProxyTree::allocate() {
  dynamic_.resize(static_cast<std::size_t>(dynamic_total_));
  static_.resize(static_cast<std::size_t>(static_total_));
}

void PackedProxyTree::place(std::int32_t j, const Aabb& box, std::int32_t id, bool is_static) {
  if (is_static)
    static_[static_nodes_[j].end++] = {box, id};
  else
    dynamic_[dynamic_nodes_[j].end++] = {box, id};
}

void PackedProxyTree::finish() {
  const std::int32_t count = node_count();
  for (std::int32_t j = 0; j < count; ++j) {
    Node& d = dynamic_nodes_[j];
    Node& s = static_nodes_[j];
    d.sub_end = d.end;
    s.sub_end = s.end;
    for (std::int32_t i = d.begin; i < d.end; ++i)
      d.bound.grow(dynamic_[i].box);
    for (std::int32_t i = s.begin; i < s.end; ++i)
      s.bound.grow(static_[i].box);
    dynamic_own_[j] = d.bound;
    static_own_[j] = s.bound;
    dynamic_axis_[j] = sort_for_sweep(dynamic_, d.begin, d.end, d.bound);
    static_axis_[j] = sort_for_sweep(static_, s.begin, s.end, s.bound);
  }
  // Children follow their parent in preorder, so one backward sweep completes every subtree.
  for (std::int32_t j = count - 1; j > 0; --j) {
    const std::int32_t p = parent_[j];
    for (std::vector<Node>* v : {&dynamic_nodes_, &static_nodes_}) {
      const Node& c = (*v)[j];
      Node& q = (*v)[p];
      q.skip = std::max(q.skip, c.skip);
      q.sub_end = std::max(q.sub_end, c.sub_end);
      q.bound.grow(c.bound);
    }
  }
}

void PackedProxyTree::search_group(std::int32_t n, std::int32_t db, std::int32_t de,
                                   std::vector<std::uint64_t>& keys) {
  Aabb u;
  for (std::int32_t i = db; i < de; ++i)
    u.grow(dynamic_[i].box);
  const std::int32_t count = node_count();
  // Dynamic partners come later in preorder: every node before n is an ancestor of n or in a
  // subtree that ends before n, so its dynamic range lies before db. Walk forward from n.
  std::int32_t j = n;
  while (j < count) {
    const Node& m = dynamic_nodes_[j];
    ++node_visits_;
    if (m.sub_end <= std::max(m.begin, db + 1) || !touch(m.bound, u)) {
      j = m.skip;
      continue;
    }
    const Aabb& own = dynamic_own_[j];
    const int sort_axis = dynamic_axis_[j];
    const int axis = std::max(sort_axis, 0);
    for (std::int32_t i = db; i < de; ++i) {
      const std::int32_t kb = std::max(m.begin, i + 1);
      if (kb >= m.end)
        break;  // kb only grows with i
      const Aabb& a = dynamic_[i].box;
      if (!touch(a, own))
        continue;
      // The range is sorted by min along `axis` when long: stop at the first box starting
      // beyond a's end (a sweep over the node's own list).
      const Real limit = sweep_limit(a, sort_axis);
      std::int32_t k = kb;
      for (; k < m.end && dynamic_[k].box.min[axis] <= limit; ++k) {
        if (touch(a, dynamic_[k].box))
          keys.push_back(pair_key(dynamic_[i].id, dynamic_[k].id));
      }
      box_tests_ += k - kb;
    }
    ++j;
  }
  // Static partners can be anywhere: walk the static hierarchy from the root.
  if (static_.empty())
    return;
  j = 0;
  while (j < count) {
    const Node& m = static_nodes_[j];
    ++node_visits_;
    if (m.sub_end == m.begin || !touch(m.bound, u)) {
      j = m.skip;
      continue;
    }
    if (m.end > m.begin && touch(static_own_[j], u)) {
      const Aabb& own = static_own_[j];
      const int sort_axis = static_axis_[j];
      const int axis = std::max(sort_axis, 0);
      for (std::int32_t i = db; i < de; ++i) {
        const Aabb& a = dynamic_[i].box;
        if (!touch(a, own))
          continue;
        const Real limit = sweep_limit(a, sort_axis);
        std::int32_t k = m.begin;
        for (; k < m.end && static_[k].box.min[axis] <= limit; ++k) {
          if (touch(a, static_[k].box))
            keys.push_back(pair_key(dynamic_[i].id, static_[k].id));
        }
        box_tests_ += k - m.begin;
      }
    }
    ++j;
  }
}

// Comparisons with infinities are well defined, so an unbounded box walks the tree like any.
void PackedProxyTree::search_outsider(const Aabb& box, std::int32_t id, bool is_static,
                                      std::vector<std::uint64_t>& keys) {
  const std::int32_t count = node_count();
  for (int kind = 0; kind < 2; ++kind) {
    if (kind == 1 && is_static)
      break;  // static-static pairs are never reported
    const std::vector<Node>& tree = kind == 0 ? dynamic_nodes_ : static_nodes_;
    const std::vector<Box>& boxes = kind == 0 ? dynamic_ : static_;
    const std::vector<Aabb>& own = kind == 0 ? dynamic_own_ : static_own_;
    const std::vector<std::int8_t>& axes = kind == 0 ? dynamic_axis_ : static_axis_;
    std::int32_t j = 0;
    while (j < count) {
      const Node& m = tree[j];
      ++node_visits_;
      if (m.sub_end == m.begin || !touch(m.bound, box)) {
        j = m.skip;
        continue;
      }
      if (!touch(own[j], box)) {
        ++j;
        continue;
      }
      const int axis = std::max<int>(axes[j], 0);
      const Real limit = sweep_limit(box, axes[j]);
      std::int32_t k = m.begin;
      for (; k < m.end && boxes[k].box.min[axis] <= limit; ++k) {
        if (touch(box, boxes[k].box))
          keys.push_back(pair_key(id, boxes[k].id));
      }
      box_tests_ += k - m.begin;
      ++j;
    }
  }
}

}  // namespace tumble::detail
