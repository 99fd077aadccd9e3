#include "collision/broad_phase/brute_force_broad_phase.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace tumble {

bool segment_touches_aabb(const Vec3& origin, const Vec3& direction, Real max_t, const Aabb& box) {
  Real t_enter = 0;
  Real t_exit = max_t;
  for (int k = 0; k < 3; ++k) {
    if (direction[k] == 0) {
      // Parallel to this slab: inside it or never.
      if (origin[k] < box.min[k] || origin[k] > box.max[k])
        return false;
      continue;
    }
    const Real inv = Real(1) / direction[k];
    Real t0 = (box.min[k] - origin[k]) * inv;
    Real t1 = (box.max[k] - origin[k]) * inv;
    if (t0 > t1)
      std::swap(t0, t1);
    t_enter = std::max(t_enter, t0);
    t_exit = std::min(t_exit, t1);
    if (t_enter > t_exit)
      return false;
  }
  return true;
}

void BruteForceBroadPhase::insert(std::int32_t id, const Aabb& box, bool is_static) {
  assert(id >= 0);
  if (static_cast<std::size_t>(id) >= proxies_.size())
    proxies_.resize(id + 1);
  proxies_[id] = {box, true, is_static};
}

void BruteForceBroadPhase::remove(std::int32_t id) {
  proxies_[id].alive = false;
}

void BruteForceBroadPhase::update(std::int32_t id, const Aabb& box) {
  proxies_[id].box = box;
}

void BruteForceBroadPhase::find_pairs(std::vector<ProxyPair>& out) {
  out.clear();
  const auto n = static_cast<std::int32_t>(proxies_.size());
  for (std::int32_t i = 0; i < n; ++i) {
    const Proxy& p = proxies_[i];
    if (!p.alive)
      continue;
    for (std::int32_t j = i + 1; j < n; ++j) {
      const Proxy& q = proxies_[j];
      if (!q.alive || (p.is_static && q.is_static))
        continue;
      if (p.box.overlaps(q.box))
        out.push_back({i, j});
    }
  }
}

void BruteForceBroadPhase::query(const Aabb& box, std::vector<std::int32_t>& out) const {
  out.clear();
  for (std::size_t i = 0; i < proxies_.size(); ++i) {
    if (proxies_[i].alive && proxies_[i].box.overlaps(box)) {
      out.push_back(static_cast<std::int32_t>(i));
    }
  }
}

void BruteForceBroadPhase::ray_cast(const Vec3& origin, const Vec3& direction, Real max_t,
                                    std::vector<std::int32_t>& out) const {
  out.clear();
  for (std::size_t i = 0; i < proxies_.size(); ++i) {
    if (proxies_[i].alive && segment_touches_aabb(origin, direction, max_t, proxies_[i].box)) {
      out.push_back(static_cast<std::int32_t>(i));
    }
  }
}

}  // namespace tumble
