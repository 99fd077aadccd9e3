// Pieces the impulse and the penalty solver share (internal): effective masses, the lookup of
// last step's manifold for a pair, and the Jacobian rows of a contact point.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "collision/math.hpp"
#include "dynamics/contact_cache.hpp"
#include "dynamics/contact_solver.hpp"
#include "dynamics/rigid_body.hpp"

namespace tumble::detail {

// 1 / (J M^-1 J^T) for a unit impulse along `axis` applied at r_a on A and -axis at r_b on B.
inline Real effective_mass(Real inv_mass_sum, const Mat3& inv_i_a, const Mat3& inv_i_b,
                           const Vec3& r_a, const Vec3& r_b, const Vec3& axis) {
  const Vec3 ra_x = r_a.cross(axis);
  const Vec3 rb_x = r_b.cross(axis);
  const Real k = inv_mass_sum + ra_x.dot(inv_i_a * ra_x) + rb_x.dot(inv_i_b * rb_x);
  return k > 0 ? Real(1) / k : Real(0);
}

// The cached manifold of pair (a, b) in `previous` (sorted by pair), or null.
inline const CachedManifold* find_cached(std::span<const CachedManifold> previous, std::int32_t a,
                                         std::int32_t b) {
  const auto it = std::lower_bound(previous.begin(), previous.end(), std::pair{a, b},
                                   [](const CachedManifold& m, const std::pair<int, int>& key) {
                                     return std::pair{m.body_a, m.body_b} < key;
                                   });
  if (it == previous.end() || it->body_a != a || it->body_b != b)
    return nullptr;
  return &*it;
}

// The rows of a contact point along the normal and the two tangents, precomputed once per step
// so that applying an impulse is a few vector adds: r x d and I^-1 (r x d) on both bodies, and
// the effective masses. `Point` is either solver's point record (the same field names).
template <class Point>
void fill_contact_rows(Point& p, const Vec3& normal, const Vec3& t1, const Vec3& t2, const Mat3& ia,
                       const Mat3& ib, Real inv_mass_sum) {
  p.rn_a = p.r_a.cross(normal);
  p.rn_b = p.r_b.cross(normal);
  p.rt1_a = p.r_a.cross(t1);
  p.rt1_b = p.r_b.cross(t1);
  p.rt2_a = p.r_a.cross(t2);
  p.rt2_b = p.r_b.cross(t2);
  p.in_a = ia * p.rn_a;
  p.in_b = ib * p.rn_b;
  p.it1_a = ia * p.rt1_a;
  p.it1_b = ib * p.rt1_b;
  p.it2_a = ia * p.rt2_a;
  p.it2_b = ib * p.rt2_b;
  p.normal_mass = effective_mass(inv_mass_sum, ia, ib, p.r_a, p.r_b, normal);
  p.tangent_mass1 = effective_mass(inv_mass_sum, ia, ib, p.r_a, p.r_b, t1);
  p.tangent_mass2 = effective_mass(inv_mass_sum, ia, ib, p.r_a, p.r_b, t2);
}

// Each body's inverse mass and world-frame inverse inertia for this step.
inline void world_inverse_masses(std::span<const BodyState> bodies,
                                 std::span<const BodyMass> masses, std::vector<Real>& inverse_mass,
                                 std::vector<Mat3>& inverse_inertia_world) {
  const std::size_t n = bodies.size();
  inverse_mass.resize(n);
  inverse_inertia_world.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    inverse_mass[i] = masses[i].inverse_mass;
    const Mat3 r = bodies[i].orientation.toRotationMatrix();
    inverse_inertia_world[i] = r * masses[i].inverse_inertia * r.transpose();
  }
}

// The part of a solver's point record both solvers fill the same way from manifold point `cp`
// of pair `pc`: bodies, feature, frame, lever arms (world and body-local), the separation at
// the start of the step (both anchors start at the contact point, so the separation is -depth
// plus how far the anchors move apart along the normal), rows, inverse masses and friction.
template <class Point>
void fill_contact_point(Point& p, const PairContact& pc, const ContactPoint& cp, const Vec3& t1,
                        const Vec3& t2, std::span<const BodyState> bodies,
                        const std::vector<Real>& inverse_mass,
                        const std::vector<Mat3>& inverse_inertia_world) {
  const std::int32_t a = pc.body_a;
  const std::int32_t b = pc.body_b;
  const Vec3& normal = pc.manifold.normal;
  p.a = a;
  p.b = b;
  p.feature = cp.feature.key();
  p.normal = normal;
  p.tangent1 = t1;
  p.tangent2 = t2;
  p.r_a = cp.position - bodies[a].position;
  p.r_b = cp.position - bodies[b].position;
  p.local_a = bodies[a].orientation.conjugate() * p.r_a;
  p.local_b = bodies[b].orientation.conjugate() * p.r_b;
  p.base_separation = -cp.depth;
  fill_contact_rows(p, normal, t1, t2, inverse_inertia_world[a], inverse_inertia_world[b],
                    inverse_mass[a] + inverse_mass[b]);
  p.inv_mass_a = inverse_mass[a];
  p.inv_mass_b = inverse_mass[b];
  p.friction = pc.friction;
}

// Writes every pair's points with their accumulated impulses into `cache`, for the next step's
// warm start (friction as one world vector, so a turned tangent frame keeps it).
template <class Point, class PairInfo>
void store_manifolds(const std::vector<PairInfo>& pairs,
                     const std::vector<std::int32_t>& pair_bodies, const std::vector<Point>& points,
                     std::vector<CachedManifold>& cache) {
  cache.clear();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const PairInfo& info = pairs[i];
    CachedManifold m;
    m.body_a = pair_bodies[2 * i];
    m.body_b = pair_bodies[2 * i + 1];
    m.count = info.count;
    for (int k = 0; k < info.count; ++k) {
      const Point& p = points[std::size_t(info.first_point + k)];
      m.points[k].feature = p.feature;
      m.points[k].local_point = p.local_a;
      m.points[k].normal_impulse = p.normal_impulse;
      m.points[k].friction_impulse =
          p.tangent1 * p.tangent_impulse1 + p.tangent2 * p.tangent_impulse2;
    }
    cache.push_back(m);
  }
}

}  // namespace tumble::detail
