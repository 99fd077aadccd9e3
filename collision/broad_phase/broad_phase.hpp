// The broad phase interface (docs/broad-phase.md): every structure keeps one proxy per body and
// reports the pairs whose boxes overlap. Output is the same pair set as brute force, in one
// deterministic order, whatever the structure, so the choice of structure never changes a
// simulation's result.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/aabb.hpp"
#include "collision/cache_prefetch.hpp"
#include "tumble/settings.hpp"

namespace tumble {

// A candidate pair of proxy ids with a < b. Pairs sort by (a, b).
struct ProxyPair {
  std::int32_t a = 0;
  std::int32_t b = 0;

  auto operator<=>(const ProxyPair&) const = default;
};

class BroadPhase {
 public:
  virtual ~BroadPhase() = default;

  // Proxy ids are chosen by the caller (the body index), non-negative and unique.
  virtual void insert(std::int32_t id, const Aabb& box, bool is_static) = 0;
  virtual void remove(std::int32_t id) = 0;
  virtual void update(std::int32_t id, const Aabb& box) = 0;

  // Replaces `out` with every overlapping pair that has at least one non-static proxy, sorted by
  // (a, b). Static proxies are never paired with each other.
  virtual void find_pairs(std::vector<ProxyPair>& out) = 0;

  // Replaces `out` with the ids of proxies whose box overlaps `box`, ascending.
  virtual void query(const Aabb& box, std::vector<std::int32_t>& out) const = 0;

  // Replaces `out` with the ids of proxies whose box the segment origin + t * direction,
  // t in [0, max_t], touches, ascending.
  virtual void ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                        std::vector<std::int32_t>& out) const = 0;

  // Records the structure's arrays, to be asked for ahead of a step that will read them
  // (collision/cache_prefetch.hpp). A structure that does not say records nothing.
  virtual void prefetch(CachePrefetch& /*requests*/) const {}
};

// Slab test (Kay and Kajiya, "Ray tracing complex scenes", SIGGRAPH 1986): does the segment
// origin + t * direction, t in [0, max_t], touch the box? Shared by every structure so they all
// agree on the boundary cases.
bool segment_touches_aabb(const Vec3& origin, const Vec3& direction, Real max_t, const Aabb& box);

}  // namespace tumble
