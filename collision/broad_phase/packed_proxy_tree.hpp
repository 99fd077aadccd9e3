// The preorder snapshot that the k-d tree and the loose octree search for pairs (internal).
//
// Both structures keep proxies in per-node linked lists, which are cheap to update but slow to
// walk. Before a search they write the tree out in preorder: per node and per kind (dynamic,
// static) a contiguous range of boxes, the end of the subtree's range, the exact bound of the
// subtree's boxes (a refit) and the preorder index just past the subtree (skip). A search then
// walks forward through flat arrays. Long node lists are sorted along their longest axis so
// loops over them stop early (sweep and prune within a list).
//
// Building, once per search: start(count); set_node(j, ...) for j = 0 .. count-1 in preorder;
// allocate(); place(...) for every bounded proxy; finish().
#pragma once

#include <cstdint>
#include <vector>

#include "collision/aabb.hpp"

namespace tumble::detail {

class PackedProxyTree {
 public:
  void start(std::int32_t node_count);
  // Node j (preorder) with its parent's preorder index (-1 for the root), a lower bound on its
  // skip (j + 1 when unknown: finish() completes it from the children) and its own counts.
  void set_node(std::int32_t j, std::int32_t parent, std::int32_t skip, std::int32_t dynamic_count,
                std::int32_t static_count);
  void allocate();
  void place(std::int32_t j, const Aabb& box, std::int32_t id, bool is_static);
  void finish();

  std::int32_t node_count() const { return static_cast<std::int32_t>(dynamic_nodes_.size()); }
  std::int32_t dynamic_begin(std::int32_t j) const { return dynamic_nodes_[j].begin; }
  std::int32_t dynamic_end(std::int32_t j) const { return dynamic_nodes_[j].end; }

  // Pairs of the dynamic proxies [db, de) of node n (its whole range or part of it) with every
  // dynamic proxy after them in preorder and with every static proxy, appended as pair keys.
  // Searching every node's range once reports each dynamic-dynamic pair once.
  void search_group(std::int32_t n, std::int32_t db, std::int32_t de,
                    std::vector<std::uint64_t>& keys);
  // Pairs of one proxy held outside the tree (an unbounded box) with every proxy in it.
  void search_outsider(const Aabb& box, std::int32_t id, bool is_static,
                       std::vector<std::uint64_t>& keys);

  void reset_counters() { box_tests_ = node_visits_ = 0; }
  std::int64_t box_tests() const { return box_tests_; }      // proxy-proxy box tests
  std::int64_t node_visits() const { return node_visits_; }  // node bound tests

 private:
  struct Node {
    Aabb bound;  // the subtree's boxes of this kind
    std::int32_t skip = 0;
    std::int32_t begin = 0;
    std::int32_t end = 0;
    std::int32_t sub_end = 0;
  };
  struct Box {
    Aabb box;
    std::int32_t id = 0;
  };

  std::vector<Node> dynamic_nodes_;
  std::vector<Node> static_nodes_;
  std::vector<std::int32_t> parent_;
  std::vector<std::int8_t> dynamic_axis_;  // per node: sort axis of its own list, -1 if none
  std::vector<std::int8_t> static_axis_;
  std::vector<Aabb> dynamic_own_;  // per node: bound of its own dynamic boxes
  std::vector<Aabb> static_own_;   // per node: bound of its own static boxes
  std::vector<Box> dynamic_;
  std::vector<Box> static_;
  std::int32_t dynamic_total_ = 0;
  std::int32_t static_total_ = 0;
  std::int64_t box_tests_ = 0;
  std::int64_t node_visits_ = 0;
};

}  // namespace tumble::detail
