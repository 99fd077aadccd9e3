// All-pairs broad phase: O(n^2) box tests. The reference every other structure is checked
// against, and the fastest choice for a handful of bodies.
#pragma once

#include <vector>

#include "collision/broad_phase/broad_phase.hpp"

namespace tumble {

class BruteForceBroadPhase final : public BroadPhase {
 public:
  void insert(std::int32_t id, const Aabb& box, bool is_static) override;
  void remove(std::int32_t id) override;
  void update(std::int32_t id, const Aabb& box) override;
  void find_pairs(std::vector<ProxyPair>& out) override;
  void query(const Aabb& box, std::vector<std::int32_t>& out) const override;
  void ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                std::vector<std::int32_t>& out) const override;
  void prefetch(CachePrefetch& requests) const override { requests.record(proxies_); }

 private:
  struct Proxy {
    Aabb box;
    bool alive = false;
    bool is_static = false;
  };
  std::vector<Proxy> proxies_;  // indexed by id
};

}  // namespace tumble
