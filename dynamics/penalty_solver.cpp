#include "dynamics/penalty_solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "dynamics/contact_rows.hpp"

namespace tumble {
using detail::find_cached;

void PenaltySolver::prepare(std::span<const PairContact> contacts,
                            std::span<const PenaltyPair> springs,
                            std::span<const CachedManifold> previous,
                            std::span<const BodyState> bodies, std::span<const BodyMass> masses,
                            const PenaltySolverSettings& settings) {
  settings_ = settings;
  points_.clear();
  pairs_.clear();
  pair_bodies_.clear();
  detail::world_inverse_masses(bodies, masses, inverse_mass_, inverse_inertia_world_);
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const PairContact& pc = contacts[c];
    const std::int32_t a = pc.body_a;
    const std::int32_t b = pc.body_b;
    const PairInfo info{static_cast<std::int32_t>(points_.size()), pc.manifold.count};
    const Vec3 normal = pc.manifold.normal;
    Vec3 t1, t2;
    orthonormal_basis(normal, t1, t2);
    for (int k = 0; k < pc.manifold.count; ++k) {
      const ContactPoint& cp = pc.manifold.points[k];
      Point p;
      detail::fill_contact_point(p, pc, cp, t1, t2, bodies, inverse_mass_, inverse_inertia_world_);
      // A manifold of several points shares the pair's spring: each point carries its share,
      // so a box face resting on a floor is as stiff as k, whatever the manifold reduction
      // kept.
      p.stiffness = springs[c].stiffness / pc.manifold.count;
      p.damping = springs[c].damping / pc.manifold.count;
      points_.push_back(p);
    }
    // Warm start by feature id (the fixed point does not depend on it; it saves iterations).
    if (const CachedManifold* cached = find_cached(previous, a, b)) {
      std::array<bool, kMaxManifoldPoints> used{};
      for (int k = 0; k < info.count; ++k) {
        Point& p = points_[info.first_point + k];
        for (int m = 0; m < cached->count; ++m) {
          if (!used[m] && cached->points[m].feature == p.feature) {
            used[m] = true;
            p.normal_impulse = cached->points[m].normal_impulse;
            p.tangent_impulse1 = cached->points[m].friction_impulse.dot(t1);
            p.tangent_impulse2 = cached->points[m].friction_impulse.dot(t2);
            break;
          }
        }
      }
    }
    pairs_.push_back(info);
    pair_bodies_.push_back(a);
    pair_bodies_.push_back(b);
  }
}

Real PenaltySolver::separation(const Point& p, std::span<const BodyState> bodies) const {
  const BodyState& a = bodies[p.a];
  const BodyState& b = bodies[p.b];
  const Vec3 anchor_a = a.position + a.orientation * p.local_a;
  const Vec3 anchor_b = b.position + b.orientation * p.local_b;
  return p.base_separation + (anchor_a - anchor_b).dot(p.normal);
}

void PenaltySolver::apply(const Point& p, Real normal, Real tangent1, Real tangent2,
                          std::span<BodyState> bodies) {
  BodyState& a = bodies[p.a];
  BodyState& b = bodies[p.b];
  const Vec3 linear = normal * p.normal + tangent1 * p.tangent1 + tangent2 * p.tangent2;
  const Vec3 angular_a = normal * p.in_a + tangent1 * p.it1_a + tangent2 * p.it2_a;
  const Vec3 angular_b = normal * p.in_b + tangent1 * p.it1_b + tangent2 * p.it2_b;
  a.velocity += p.inv_mass_a * linear;
  a.angular_velocity += angular_a;
  b.velocity -= p.inv_mass_b * linear;
  b.angular_velocity -= angular_b;
}

void PenaltySolver::begin_substep(std::span<BodyState> bodies) {
  for (Point& p : points_)
    p.substep_separation = separation(p, bodies);
  for (const Point& p : points_)
    apply(p, p.normal_impulse, p.tangent_impulse1, p.tangent_impulse2, bodies);
}

// Row updates of projected Gauss-Seidel on the implicit substep. With the accumulated impulse
// lambda and the current approach velocity v_n (which already includes lambda), the new
// impulse satisfies lambda' = h (-k phi - (h k + c) (v_n + (lambda' - lambda) / m_eff)), so
//   lambda' = (h (-k phi - (h k + c) v_n) + g lambda) / (1 + g),   g = h (h k + c) / m_eff,
// clamped at 0 (a spring pushes, never pulls). phi is the separation at the substep's start.
Real PenaltySolver::solve(std::span<BodyState> bodies) {
  const Real h = settings_.substep;
  Real largest_change = 0;
  const Real v_reg = settings_.friction_regularisation_speed;
  for (const PairInfo& pair : pairs_) {
    const std::span<Point> points = std::span(points_).subspan(pair.first_point, pair.count);
    for (Point& p : points) {
      const Real phi = p.substep_separation;
      const BodyState& a = bodies[p.a];
      const BodyState& b = bodies[p.b];
      const Real vn = p.normal.dot(a.velocity - b.velocity) + p.rn_a.dot(a.angular_velocity) -
                      p.rn_b.dot(b.angular_velocity);
      // The spring sees the separation at the end of the substep, phi + h v_n', also when the
      // surfaces are still apart at its start: a spring that switched on only at the next
      // substep would let a body sink into it without doing work against it, and then push
      // it out with energy k phi^2 / 2 that nothing paid for (measured: +0.06 J in the first
      // steps of a 12-row wall pyramid, +1.5 J and a launched top box at 40 rows). The
      // damper acts only while the surfaces overlap.
      const Real damping = phi < 0 ? p.damping : Real(0);
      const Real rate = h * p.stiffness + damping;
      const Real g = p.normal_mass > 0 ? h * rate / p.normal_mass : Real(0);
      const Real target = (h * (-p.stiffness * phi - rate * vn) + g * p.normal_impulse) / (1 + g);
      const Real new_impulse = std::max(target, Real(0));
      const Real applied = new_impulse - p.normal_impulse;
      p.normal_impulse = new_impulse;
      if (p.normal_mass > 0)
        largest_change = std::max(largest_change, std::abs(applied) / p.normal_mass);
      apply(p, applied, 0, 0, bodies);
    }
    // Regularised Coulomb friction, implicit as well: the viscous coefficient mu lambda_n /
    // v_reg acts on the end-of-substep sliding velocity, then the impulse is clamped to the
    // disc mu lambda_n.
    for (Point& p : points) {
      const BodyState& a = bodies[p.a];
      const BodyState& b = bodies[p.b];
      const Vec3 dv = a.velocity - b.velocity;
      const Real slip1 =
          p.tangent1.dot(dv) + p.rt1_a.dot(a.angular_velocity) - p.rt1_b.dot(b.angular_velocity);
      const Real slip2 =
          p.tangent2.dot(dv) + p.rt2_a.dot(a.angular_velocity) - p.rt2_b.dot(b.angular_velocity);
      const Real bound = p.friction * p.normal_impulse;
      const Real viscosity = bound / v_reg;
      auto row = [&](Real impulse, Real slip, Real mass) {
        const Real g = mass > 0 ? viscosity / mass : Real(0);
        return (-viscosity * slip + g * impulse) / (1 + g);
      };
      Real new1 = row(p.tangent_impulse1, slip1, p.tangent_mass1);
      Real new2 = row(p.tangent_impulse2, slip2, p.tangent_mass2);
      const Real magnitude = std::sqrt(new1 * new1 + new2 * new2);
      if (magnitude > bound) {
        const Real scale = magnitude > 0 ? bound / magnitude : Real(0);
        new1 *= scale;
        new2 *= scale;
      }
      apply(p, 0, new1 - p.tangent_impulse1, new2 - p.tangent_impulse2, bodies);
      p.tangent_impulse1 = new1;
      p.tangent_impulse2 = new2;
    }
  }
  return largest_change;
}

void PenaltySolver::store(std::vector<CachedManifold>& cache) const {
  detail::store_manifolds(pairs_, pair_bodies_, points_, cache);
}

}  // namespace tumble
