#include "engine/state.hpp"

#include <bit>
#include <cstring>

namespace tumble {

State initial_state(const Scene& scene) {
  State s;
  initial_state_into(scene, s);
  return s;
}

void initial_state_into(const Scene& scene, State& s) {
  s.time = 0;
  s.step = 0;
  s.bodies.clear();
  s.bodies.reserve(scene.bodies.size());
  for (const BodyDesc& d : scene.bodies) {
    BodyState b;
    b.position = d.position;
    b.orientation = d.orientation;
    b.velocity = d.velocity;
    b.angular_velocity = d.angular_velocity;
    s.bodies.push_back(b);
  }
  s.contacts.clear();
  s.manifolds.clear();
  s.box_axes.clear();
  s.gjk_caches.clear();
  s.hull_axes.clear();
  s.resting_touches.clear();
  s.sleeping_contacts.clear();
  s.slow_time.assign(scene.bodies.size(), 0);
  s.asleep.assign(scene.bodies.size(), 0);
  s.substep_level.assign(scene.bodies.size(), 0);
  s.substep_hold.assign(scene.bodies.size(), 0);
}

namespace {

// FNV-1a, 64 bit (Fowler, Noll, Vo). Values are fed as little-endian bytes of their bit
// patterns so the hash does not depend on struct padding or the host's byte order.
class Fnv1a {
 public:
  void add_u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) {
      hash_ ^= (v >> (8 * i)) & 0xffu;
      hash_ *= 0x100000001b3ull;
    }
  }
  void add(Real x) { add_u64(std::bit_cast<std::uint64_t>(x)); }
  void add(const Vec3& v) {
    add(v.x());
    add(v.y());
    add(v.z());
  }
  void add(const Quat& q) {
    add(q.w());
    add(q.x());
    add(q.y());
    add(q.z());
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace

std::uint64_t state_hash(const State& state) {
  Fnv1a h;
  h.add(state.time);
  h.add_u64(static_cast<std::uint64_t>(state.step));
  h.add_u64(state.bodies.size());
  for (const BodyState& b : state.bodies) {
    h.add(b.position);
    h.add(b.orientation);
    h.add(b.velocity);
    h.add(b.angular_velocity);
  }
  const auto add_impulses = [&h](const std::vector<CachedManifold>& list) {
    h.add_u64(list.size());
    for (const CachedManifold& m : list) {
      h.add_u64(static_cast<std::uint64_t>(m.body_a));
      h.add_u64(static_cast<std::uint64_t>(m.body_b));
      h.add_u64(static_cast<std::uint64_t>(m.count));
      for (int k = 0; k < m.count; ++k) {
        h.add_u64(m.points[k].feature);
        h.add(m.points[k].local_point);
        h.add(m.points[k].normal_impulse);
        h.add(m.points[k].friction_impulse);
      }
    }
  };
  add_impulses(state.contacts);
  h.add_u64(state.manifolds.size());
  for (const RecyclableManifold& m : state.manifolds) {
    h.add_u64(static_cast<std::uint64_t>(m.body_a));
    h.add_u64(static_cast<std::uint64_t>(m.body_b));
    h.add(m.relative_position);
    h.add(m.relative_orientation);
    h.add(m.normal);
    h.add_u64(static_cast<std::uint64_t>(m.count));
    for (int k = 0; k < m.count; ++k) {
      h.add(m.point_a[std::size_t(k)]);
      h.add(m.point_b[std::size_t(k)]);
      h.add_u64(m.feature[std::size_t(k)].key());
    }
  }
  h.add_u64(state.box_axes.size());
  for (const CachedBoxAxis& c : state.box_axes) {
    h.add_u64(static_cast<std::uint64_t>(c.body_a));
    h.add_u64(static_cast<std::uint64_t>(c.body_b));
    h.add_u64(c.axis);
  }
  h.add_u64(state.gjk_caches.size());
  for (const PairGjkCache& c : state.gjk_caches) {
    h.add_u64(static_cast<std::uint64_t>(c.body_a));
    h.add_u64(static_cast<std::uint64_t>(c.body_b));
    h.add(c.cache.axis_in_a);
    h.add_u64(static_cast<std::uint64_t>(c.cache.index_a));
    h.add_u64(static_cast<std::uint64_t>(c.cache.index_b));
    h.add_u64(c.cache.valid ? 1 : 0);
  }
  h.add_u64(state.hull_axes.size());
  for (const CachedHullAxis& c : state.hull_axes) {
    h.add_u64(static_cast<std::uint64_t>(c.body_a));
    h.add_u64(static_cast<std::uint64_t>(c.body_b));
    h.add(c.axis.direction_in_a);
    h.add_u64(static_cast<std::uint64_t>(c.axis.support_a));
    h.add_u64(static_cast<std::uint64_t>(c.axis.support_b));
  }
  h.add_u64(state.asleep.size());
  for (std::size_t i = 0; i < state.asleep.size(); ++i) {
    h.add_u64(state.asleep[i]);
    h.add(state.slow_time[i]);
  }
  // Only a world that has slept has resting pairs and sleeping impulses: an empty list adds
  // nothing, so that the hashes of worlds that never sleep do not depend on these lists.
  if (!state.resting_touches.empty()) {
    h.add_u64(state.resting_touches.size());
    for (const RestingTouch& t : state.resting_touches) {
      h.add_u64(static_cast<std::uint64_t>(t.body_a));
      h.add_u64(static_cast<std::uint64_t>(t.body_b));
    }
  }
  if (!state.sleeping_contacts.empty())
    add_impulses(state.sleeping_contacts);
  h.add_u64(state.substep_level.size());
  for (std::size_t i = 0; i < state.substep_level.size(); ++i) {
    h.add_u64(state.substep_level[i]);
    h.add_u64(i < state.substep_hold.size() ? state.substep_hold[i] : 0);
  }
  return h.value();
}

}  // namespace tumble
