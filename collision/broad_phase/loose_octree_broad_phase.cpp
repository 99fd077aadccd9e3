#include "collision/broad_phase/loose_octree_broad_phase.hpp"
#include "collision/broad_phase/pair_keys.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>

namespace tumble {
namespace {

// A coordinate beyond this is treated as infinite: growing the world to contain it would take
// ~100 doublings and leave no precision for the cells where the bodies are.
constexpr Real kUnboundedCoordinate = 1e30;

bool contains(const Aabb& outer, const Aabb& inner) {
  return (inner.min.array() >= outer.min.array()).all() &&
         (inner.max.array() <= outer.max.array()).all();
}

Vec3 centre_of(const Aabb& b) {
  return Real(0.5) * (b.min + b.max);
}

int octant_of(const Vec3& node_centre, const Vec3& p) {
  return (p.x() >= node_centre.x() ? 1 : 0) | (p.y() >= node_centre.y() ? 2 : 0) |
         (p.z() >= node_centre.z() ? 4 : 0);
}

using detail::pair_key;

}  // namespace

LooseOctreeBroadPhase::LooseOctreeBroadPhase(Real looseness, int max_node_objects, int max_depth)
    : k_(std::clamp(looseness, Real(0.5), Real(1))),
      n_max_(std::max(max_node_objects, 0)),
      d_max_(std::clamp(max_depth, 0, 60)) {
  assert(looseness >= 0.5 && looseness <= 1.0);
}

bool LooseOctreeBroadPhase::is_unbounded(const Aabb& box) {
  // Written so that NaN counts as unbounded too (it then overlaps nothing, like brute force).
  return !((box.min.array() >= -kUnboundedCoordinate).all() &&
           (box.max.array() <= kUnboundedCoordinate).all());
}

Real LooseOctreeBroadPhase::max_half_extent(const Aabb& box) const {
  return Real(0.5) * (box.max - box.min).maxCoeff();
}

// ---------------------------------------------------------------------------------------------
// Nodes

std::int32_t LooseOctreeBroadPhase::new_node() {
  if (!free_nodes_.empty()) {
    const std::int32_t n = free_nodes_.back();
    free_nodes_.pop_back();
    nodes_[n] = Node{};
    return n;
  }
  nodes_.emplace_back();
  return static_cast<std::int32_t>(nodes_.size() - 1);
}

void LooseOctreeBroadPhase::free_node(std::int32_t n) {
  assert(nodes_[n].count == 0);
  free_nodes_.push_back(n);
}

void LooseOctreeBroadPhase::child_geometry(const Node& parent, int octant, Vec3& centre,
                                           Aabb& loose) const {
  const Real h = parent.half * Real(0.5);  // exact: halving a double
  for (int a = 0; a < 3; ++a)
    centre[a] = parent.centre[a] + (((octant >> a) & 1) ? h : -h);
  const Real reach = h * (Real(1) + k_);
  loose.min = centre.array() - reach;
  loose.max = centre.array() + reach;
  // In exact arithmetic the child's loose bound lies inside the parent's with a margin of k h / 2;
  // clamping makes the nesting hold under rounding too, so pruning a subtree by its root's
  // bound is always safe. Boxes are checked against the stored (clamped) bound when placed.
  loose.min = loose.min.cwiseMax(parent.loose.min);
  loose.max = loose.max.cwiseMin(parent.loose.max);
}

std::int32_t LooseOctreeBroadPhase::make_child(std::int32_t parent, int octant) {
  Vec3 centre;
  Aabb loose;
  child_geometry(nodes_[parent], octant, centre, loose);
  const std::int32_t c = new_node();  // may reallocate nodes_
  Node& child = nodes_[c];
  Node& p = nodes_[parent];
  child.centre = centre;
  child.loose = loose;
  child.half = p.half * Real(0.5);
  child.parent = parent;
  child.depth = p.depth + 1;
  p.child[octant] = c;
  return c;
}

// The first finite box sets the world: a root centred on it, just big enough to hold it. The
// world then grows by doubling (grow_to_contain) and shrinks by dropping an idle root
// (collapse_root), so the initial size only decides how the cells are aligned.
void LooseOctreeBroadPhase::set_root_for(const Aabb& box) {
  const Vec3 c = centre_of(box);
  const Real floor_half = std::max(Real(1e-9), Real(1e-9) * c.cwiseAbs().maxCoeff());
  root_ = new_node();
  Node& r = nodes_[root_];
  r.centre = c;
  r.half = std::max(max_half_extent(box) / k_, floor_half);
  const Real reach = r.half * (Real(1) + k_);
  r.loose = {c.array() - reach, c.array() + reach};
}

// Does the world hold the box? Its centre must be in the root's cell (not just its box in the
// root's loose bound): placement follows the centre, and a centre outside the root cell would
// leave the box stuck at the root, too near the world's edge for any child's loose bound.
bool LooseOctreeBroadPhase::world_holds(const Aabb& box) const {
  const Node& r = nodes_[root_];
  const Vec3 c = centre_of(box);
  return contains(r.loose, box) && ((c - r.centre).cwiseAbs().array() <= r.half).all();
}

// Re-rooting (world growth): the new root has twice the side and the old root is the octant of
// it facing away from the box, so every existing cell, loose bound and proxy stays where it is;
// only the depths shift by one. Repeats until the world holds the box.
void LooseOctreeBroadPhase::grow_to_contain(const Aabb& box) {
  const Vec3 target = centre_of(box);
  while (!world_holds(box)) {
    const std::int32_t old = root_;
    const std::int32_t r = new_node();
    Node& o = nodes_[old];
    Node& n = nodes_[r];
    int octant = 0;
    for (int a = 0; a < 3; ++a) {
      if (target[a] >= o.centre[a]) {
        n.centre[a] = o.centre[a] + o.half;  // old root is the lower half on this axis
      } else {
        n.centre[a] = o.centre[a] - o.half;
        octant |= 1 << a;
      }
    }
    n.half = o.half * 2;
    const Real reach = n.half * (Real(1) + k_);
    n.loose = {n.centre.array() - reach, n.centre.array() + reach};
    n.loose.grow(o.loose);  // nesting under rounding
    n.split = true;         // the old root's proxies are below it, as placement requires
    n.child[octant] = old;
    o.parent = r;
    root_ = r;
    // Depths shift by one (rare: only when the world grows).
    stack_.clear();
    stack_.push_back(old);
    while (!stack_.empty()) {
      const std::int32_t m = stack_.back();
      stack_.pop_back();
      ++nodes_[m].depth;
      for (const std::int32_t c : nodes_[m].child) {
        if (c >= 0)
          stack_.push_back(c);
      }
    }
  }
}

// The world shrinks back: a root that holds no proxy and has a single child is dropped.
void LooseOctreeBroadPhase::collapse_root() {
  while (true) {
    const Node& r = nodes_[root_];
    if (r.count != 0)
      return;
    std::int32_t only = -1;
    int children = 0;
    for (const std::int32_t c : r.child) {
      if (c >= 0) {
        only = c;
        ++children;
      }
    }
    if (children != 1)
      return;
    free_node(root_);
    root_ = only;
    nodes_[only].parent = -1;
    stack_.clear();
    stack_.push_back(only);
    while (!stack_.empty()) {
      const std::int32_t m = stack_.back();
      stack_.pop_back();
      --nodes_[m].depth;
      for (const std::int32_t c : nodes_[m].child) {
        if (c >= 0)
          stack_.push_back(c);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Proxies in nodes

void LooseOctreeBroadPhase::link(std::int32_t slot, std::int32_t node) {
  slots_.link(nodes_, slot, node);
}

void LooseOctreeBroadPhase::unlink(std::int32_t slot) {
  slots_.unlink(nodes_, slot);
}

// Ulrich's placement: from the root, follow the box centre's octant while the node is split,
// the depth allows, the box is small enough for the child level (r <= k h_child, which makes it
// fit the child's loose bound wherever its centre is in the child's cell) and the child's stored
// loose bound really holds it (this last check only fails on rounding at a world edge).
void LooseOctreeBroadPhase::place(std::int32_t slot) {
  const Aabb box = slots_.proxies[slot].box;
  if (!world_holds(box))
    grow_to_contain(box);
  const Real r = max_half_extent(box);
  const Vec3 c = centre_of(box);
  std::int32_t n = root_;
  while (true) {
    const Node& node = nodes_[n];
    if (!node.split || node.depth >= d_max_ || r > k_ * (node.half * Real(0.5)))
      break;
    const int octant = octant_of(node.centre, c);
    std::int32_t ch = node.child[octant];
    if (ch < 0) {
      Vec3 cc;
      Aabb cl;
      child_geometry(node, octant, cc, cl);
      if (!contains(cl, box))
        break;
      ch = make_child(n, octant);
    } else if (!contains(nodes_[ch].loose, box)) {
      break;
    }
    n = ch;
  }
  link(slot, n);
  const Node& node = nodes_[n];
  if (!node.split && node.count > n_max_ && node.depth < d_max_)
    split_node(n);
}

// Subdivision: more than n_max proxies and depth below d_max. Proxies small enough for
// the child level move to the child holding their centre; larger ones stay. Children that end up
// crowded split in turn.
void LooseOctreeBroadPhase::split_node(std::int32_t n) {
  nodes_[n].split = true;
  const Real child_slack = k_ * (nodes_[n].half * Real(0.5));
  std::int32_t s = nodes_[n].head;
  while (s >= 0) {
    const std::int32_t next = slots_.proxies[s].next;
    const Aabb& box = slots_.proxies[s].box;
    if (max_half_extent(box) <= child_slack) {
      const int octant = octant_of(nodes_[n].centre, centre_of(box));
      std::int32_t ch = nodes_[n].child[octant];
      if (ch < 0) {
        Vec3 cc;
        Aabb cl;
        child_geometry(nodes_[n], octant, cc, cl);
        if (contains(cl, box))
          ch = make_child(n, octant);
      } else if (!contains(nodes_[ch].loose, box)) {
        ch = -1;
      }
      if (ch >= 0) {
        unlink(s);
        link(s, ch);
      }
    }
    s = next;
  }
  for (int o = 0; o < 8; ++o) {
    const std::int32_t ch = nodes_[n].child[o];
    if (ch >= 0 && !nodes_[ch].split && nodes_[ch].count > n_max_ && nodes_[ch].depth < d_max_)
      split_node(ch);
  }
}

// Post-order housekeeping before each find_pairs: free empty subtrees and merge a split node
// back when its whole subtree holds at most n_max / 2 proxies. Returns the subtree's count.
std::int32_t LooseOctreeBroadPhase::maintain(std::int32_t n) {
  std::int32_t total = nodes_[n].count;
  for (int o = 0; o < 8; ++o) {
    const std::int32_t ch = nodes_[n].child[o];
    if (ch < 0)
      continue;
    const std::int32_t t = maintain(ch);
    if (t == 0) {
      free_node(ch);  // its own empty children were freed by maintain(ch)
      nodes_[n].child[o] = -1;
    } else {
      total += t;
    }
  }
  if (nodes_[n].split && total <= n_max_ / 2) {
    // Merge: every box of the subtree is inside the descendants' loose bounds, hence inside this
    // node's, so the proxies can simply be relinked here.
    stack_.clear();
    for (int o = 0; o < 8; ++o) {
      if (nodes_[n].child[o] >= 0)
        stack_.push_back(nodes_[n].child[o]);
      nodes_[n].child[o] = -1;
    }
    while (!stack_.empty()) {
      const std::int32_t m = stack_.back();
      stack_.pop_back();
      while (nodes_[m].head >= 0) {
        const std::int32_t s = nodes_[m].head;
        unlink(s);
        link(s, n);
      }
      for (const std::int32_t c : nodes_[m].child) {
        if (c >= 0)
          stack_.push_back(c);
      }
      free_node(m);
    }
    nodes_[n].split = false;
  }
  return total;
}

// ---------------------------------------------------------------------------------------------
// BroadPhase interface

void LooseOctreeBroadPhase::insert(std::int32_t id, const Aabb& box, bool is_static) {
  assert(id >= 0);
  if (slots_.slot_of(id) >= 0)
    remove(id);
  const std::int32_t slot = slots_.add(id, box, is_static);
  if (is_unbounded(box)) {
    unbounded_.push_back(slot);
    return;
  }
  if (root_ < 0)
    set_root_for(box);
  place(slot);
}

void LooseOctreeBroadPhase::remove(std::int32_t id) {
  const std::int32_t slot = slots_.slot_of(id);
  if (slot < 0)
    return;
  Proxy& p = slots_.proxies[slot];
  if (p.node >= 0)
    unlink(slot);
  else
    unbounded_.erase(std::find(unbounded_.begin(), unbounded_.end(), slot));
  slots_.free(id);
}

void LooseOctreeBroadPhase::update(std::int32_t id, const Aabb& box) {
  const std::int32_t slot = slots_.slot_of(id);
  Proxy& p = slots_.proxies[slot];
  const bool unbounded = is_unbounded(box);
  p.box = box;
  if (p.node < 0) {  // was unbounded
    if (unbounded)
      return;
    unbounded_.erase(std::find(unbounded_.begin(), unbounded_.end(), slot));
    if (root_ < 0)
      set_root_for(box);
    place(slot);
    return;
  }
  if (unbounded) {
    unlink(slot);
    unbounded_.push_back(slot);
    return;
  }
  // Fast path for coherent motion: the box still fits its node's loose bound and is not small
  // enough to go deeper. This is the point of looseness: a box can drift by up to k h - r
  // before it has to move.
  const Node& n = nodes_[p.node];
  if (contains(n.loose, box) &&
      (!n.split || n.depth >= d_max_ || max_half_extent(box) > k_ * (n.half * Real(0.5))))
    return;
  unlink(slot);
  place(slot);
}

// Writes the live tree out in preorder (collision/broad_phase/packed_proxy_tree.hpp). The proxies
// are scattered by one sequential pass over the slot array into ranges sized from the nodes'
// counts, which is much cheaper than chasing each node's linked list through memory.
void LooseOctreeBroadPhase::pack() {
  std::int32_t count = 0;
  if (root_ >= 0) {
    // Preorder indices first: the packed tree wants its nodes in preorder, in one pass.
    stack_.clear();
    stack_.push_back(root_);
    while (!stack_.empty()) {
      const std::int32_t n = stack_.back();
      stack_.pop_back();
      nodes_[n].pre = count++;
      for (int o = 7; o >= 0; --o) {
        if (nodes_[n].child[o] >= 0)
          stack_.push_back(nodes_[n].child[o]);
      }
    }
  }
  packed_.start(count);
  if (root_ >= 0) {
    stack_.clear();
    stack_.push_back(root_);
    while (!stack_.empty()) {
      const std::int32_t n = stack_.back();
      stack_.pop_back();
      const Node& node = nodes_[n];
      const std::int32_t j = node.pre;
      packed_.set_node(j, n == root_ ? -1 : nodes_[node.parent].pre, j + 1,
                       node.count - node.static_count, node.static_count);
      for (int o = 7; o >= 0; --o) {
        if (node.child[o] >= 0)
          stack_.push_back(node.child[o]);
      }
    }
  }
  packed_.allocate();
  for (const Proxy& p : slots_.proxies) {
    if (p.alive && p.node >= 0)
      packed_.place(nodes_[p.node].pre, p.box, p.id, p.is_static);
  }
  packed_.finish();
}

void LooseOctreeBroadPhase::find_pairs(std::vector<ProxyPair>& out) {
  keys_.clear();
  packed_.reset_counters();
  if (root_ >= 0) {
    maintain(root_);
    collapse_root();
  }
  pack();
  for (std::int32_t n = 0; n < packed_.node_count(); ++n) {
    if (packed_.dynamic_end(n) > packed_.dynamic_begin(n))
      packed_.search_group(n, packed_.dynamic_begin(n), packed_.dynamic_end(n), keys_);
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
}

void LooseOctreeBroadPhase::query_node(std::int32_t n, const Aabb& box,
                                       std::vector<std::int32_t>& out) const {
  const Node& node = nodes_[n];
  if (!node.loose.overlaps(box))
    return;
  for (std::int32_t s = node.head; s >= 0; s = slots_.proxies[s].next) {
    if (slots_.proxies[s].box.overlaps(box))
      out.push_back(slots_.proxies[s].id);
  }
  for (const std::int32_t c : node.child) {
    if (c >= 0)
      query_node(c, box, out);
  }
}

void LooseOctreeBroadPhase::query(const Aabb& box, std::vector<std::int32_t>& out) const {
  out.clear();
  if (root_ >= 0)
    query_node(root_, box, out);
  for (const std::int32_t s : unbounded_) {
    if (slots_.proxies[s].box.overlaps(box))
      out.push_back(slots_.proxies[s].id);
  }
  std::sort(out.begin(), out.end());
}

void LooseOctreeBroadPhase::ray_node(std::int32_t n, const Vec3& o, const Vec3& d, Real max_t,
                                     std::vector<std::int32_t>& out) const {
  const Node& node = nodes_[n];
  if (!segment_touches_aabb(o, d, max_t, node.loose))
    return;
  for (std::int32_t s = node.head; s >= 0; s = slots_.proxies[s].next) {
    if (segment_touches_aabb(o, d, max_t, slots_.proxies[s].box))
      out.push_back(slots_.proxies[s].id);
  }
  for (const std::int32_t c : node.child) {
    if (c >= 0)
      ray_node(c, o, d, max_t, out);
  }
}

void LooseOctreeBroadPhase::ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                                     std::vector<std::int32_t>& out) const {
  out.clear();
  if (root_ >= 0)
    ray_node(root_, origin, direction, max_t, out);
  for (const std::int32_t s : unbounded_) {
    if (segment_touches_aabb(origin, direction, max_t, slots_.proxies[s].box))
      out.push_back(slots_.proxies[s].id);
  }
  std::sort(out.begin(), out.end());
}

// ---------------------------------------------------------------------------------------------
// Inspection

LooseOctreeBroadPhase::Stats LooseOctreeBroadPhase::stats() const {
  Stats s;
  s.nodes = static_cast<int>(nodes_.size() - free_nodes_.size());
  s.unbounded = static_cast<int>(unbounded_.size());
  s.box_tests = packed_.box_tests();
  s.node_visits = packed_.node_visits();
  if (root_ >= 0) {
    std::vector<std::int32_t> stack{root_};
    while (!stack.empty()) {
      const Node& n = nodes_[stack.back()];
      stack.pop_back();
      s.depth = std::max(s.depth, static_cast<int>(n.depth));
      for (const std::int32_t c : n.child) {
        if (c >= 0)
          stack.push_back(c);
      }
    }
  }
  return s;
}

int LooseOctreeBroadPhase::level_of(std::int32_t id) const {
  const Proxy& p = slots_.proxies[slots_.slot_of(id)];
  return p.node < 0 ? -1 : nodes_[p.node].depth;
}

Aabb LooseOctreeBroadPhase::loose_bound_of(std::int32_t id) const {
  const Proxy& p = slots_.proxies[slots_.slot_of(id)];
  if (p.node < 0) {
    const Real inf = std::numeric_limits<Real>::infinity();
    return {Vec3::Constant(-inf), Vec3::Constant(inf)};
  }
  return nodes_[p.node].loose;
}

Real LooseOctreeBroadPhase::root_half_size() const {
  return root_ < 0 ? Real(0) : nodes_[root_].half;
}

Vec3 LooseOctreeBroadPhase::root_centre() const {
  return root_ < 0 ? Vec3::Zero() : nodes_[root_].centre;
}

int LooseOctreeBroadPhase::size_level(const Aabb& box) const {
  const Real r = max_half_extent(box);
  int level = 0;
  Real half = root_half_size();
  while (level < d_max_ && r <= k_ * (half * Real(0.5))) {
    half *= Real(0.5);
    ++level;
  }
  return level;
}

}  // namespace tumble
