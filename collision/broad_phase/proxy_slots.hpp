// The proxy store of the k-d tree and the loose octree (internal): both link proxies into
// per-node lists by slot, so a proxy's slot must stay put while others come and go. Slots live
// in one vector; a freed slot goes on a free list and is reused by the next insertion, and an
// id -> slot table finds a body's proxy in O(1). Each node keeps a doubly linked list of its
// proxies (head in the node, next/prev in the proxies).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "collision/aabb.hpp"

namespace tumble::detail {

struct LinkedProxy {
  Aabb box;
  std::int32_t id = -1;
  std::int32_t node = -1;  // -1: unbounded list, or free slot
  std::int32_t next = -1;  // neighbours in the node's list
  std::int32_t prev = -1;
  bool is_static = false;
  bool alive = false;
};

struct ProxySlots {
  std::vector<LinkedProxy> proxies;  // by slot, free slots included (alive = false)

  // The slot of `id`, or -1 when it has none.
  std::int32_t slot_of(std::int32_t id) const {
    return id >= 0 && std::size_t(id) < slot_of_id_.size() ? slot_of_id_[std::size_t(id)] : -1;
  }

  // Stores a fresh proxy for `id`, which must have no slot, and returns its slot.
  std::int32_t add(std::int32_t id, const Aabb& box, bool is_static) {
    if (std::size_t(id) >= slot_of_id_.size())
      slot_of_id_.resize(std::size_t(id) + 1, -1);
    std::int32_t slot;
    if (!free_slots_.empty()) {
      slot = free_slots_.back();
      free_slots_.pop_back();
    } else {
      slot = static_cast<std::int32_t>(proxies.size());
      proxies.emplace_back();
    }
    slot_of_id_[std::size_t(id)] = slot;
    LinkedProxy& p = proxies[std::size_t(slot)];
    p = LinkedProxy{};
    p.box = box;
    p.id = id;
    p.is_static = is_static;
    p.alive = true;
    return slot;
  }

  // Frees the slot of `id` (which the caller has unlinked from its node).
  void free(std::int32_t id) {
    const std::int32_t slot = slot_of_id_[std::size_t(id)];
    proxies[std::size_t(slot)].alive = false;
    slot_of_id_[std::size_t(id)] = -1;
    free_slots_.push_back(slot);
  }

  // Puts `slot` at the head of node `node`'s list; Node has head, count and static_count.
  template <class Node>
  void link(std::vector<Node>& nodes, std::int32_t slot, std::int32_t node) {
    LinkedProxy& p = proxies[std::size_t(slot)];
    Node& n = nodes[std::size_t(node)];
    p.node = node;
    p.prev = -1;
    p.next = n.head;
    if (n.head >= 0)
      proxies[std::size_t(n.head)].prev = slot;
    n.head = slot;
    ++n.count;
    n.static_count += p.is_static ? 1 : 0;
  }

  // Takes `slot` out of its node's list.
  template <class Node>
  void unlink(std::vector<Node>& nodes, std::int32_t slot) {
    LinkedProxy& p = proxies[std::size_t(slot)];
    Node& n = nodes[std::size_t(p.node)];
    if (p.prev >= 0)
      proxies[std::size_t(p.prev)].next = p.next;
    else
      n.head = p.next;
    if (p.next >= 0)
      proxies[std::size_t(p.next)].prev = p.prev;
    --n.count;
    n.static_count -= p.is_static ? 1 : 0;
    p.node = -1;
    p.next = p.prev = -1;
  }

 private:
  std::vector<std::int32_t> free_slots_;
  std::vector<std::int32_t> slot_of_id_;  // id -> slot, -1 if absent
};

}  // namespace tumble::detail
