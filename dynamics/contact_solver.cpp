#include "dynamics/contact_solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "dynamics/contact_rows.hpp"

namespace tumble {
using detail::find_cached;

void ContactSolver::prepare(std::span<const PairContact> contacts,
                            std::span<const CachedManifold> previous,
                            std::span<const BodyState> bodies, std::span<const BodyMass> masses,
                            const ContactSolverSettings& settings) {
  settings_ = settings;
  points_.clear();
  pairs_.clear();
  pair_bodies_.clear();
  detail::world_inverse_masses(bodies, masses, inverse_mass_, inverse_inertia_world_);

  // Soft spring of angular frequency w and damping ratio z, discretised implicitly over the
  // substep h: a1 = 2 z + h w, a2 = h w a1, a3 = 1 / (1 + a2). The bias velocity is
  // (w / a1) * separation, and the impulse is scaled so the response does not depend on mass.
  const Real h = settings.substep;
  const Real omega = 2 * std::numbers::pi_v<Real> * settings.contact_hertz;
  const Real a1 = 2 * settings.contact_damping_ratio + h * omega;
  const Real a2 = h * omega * a1;
  const Real a3 = Real(1) / (1 + a2);
  bias_rate_ = a1 > 0 ? omega / a1 : Real(0);
  mass_scale_ = a2 * a3;
  impulse_scale_ = a3;

  for (const PairContact& pc : contacts) {
    const std::int32_t a = pc.body_a;
    const std::int32_t b = pc.body_b;
    PairInfo info{static_cast<std::int32_t>(points_.size()), pc.manifold.count};
    const Vec3 normal = pc.manifold.normal;
    Vec3 t1, t2;
    orthonormal_basis(normal, t1, t2);
    for (int k = 0; k < pc.manifold.count; ++k) {
      const ContactPoint& cp = pc.manifold.points[k];
      Point p;
      detail::fill_contact_point(p, pc, cp, t1, t2, bodies, inverse_mass_, inverse_inertia_world_);
      p.restitution = pc.restitution;
      points_.push_back(p);
    }
    if (const CachedManifold* cached = find_cached(previous, a, b)) {
      warm_start_from(*cached, pc.match_distance,
                      std::span(points_).subspan(info.first_point, info.count));
    }
    pairs_.push_back(info);
    pair_bodies_.push_back(a);
    pair_bodies_.push_back(b);
  }
}

// Each cached point lends its impulses to at most one new point: first to the point with the
// same feature id, then, for points still unmatched, to the nearest within `match_distance`.
void ContactSolver::warm_start_from(const CachedManifold& cached, Real match_distance,
                                    std::span<Point> points) {
  std::array<bool, kMaxManifoldPoints> used{};
  std::array<int, kMaxManifoldPoints> source;
  source.fill(-1);
  for (std::size_t k = 0; k < points.size(); ++k) {
    for (int c = 0; c < cached.count; ++c) {
      if (!used[c] && cached.points[c].feature == points[k].feature) {
        used[c] = true;
        source[k] = c;
        break;
      }
    }
  }
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (source[k] >= 0)
      continue;
    Real best = match_distance;
    for (int c = 0; c < cached.count; ++c) {
      const Real distance = (cached.points[c].local_point - points[k].local_a).norm();
      if (!used[c] && distance < best) {
        best = distance;
        source[k] = c;
      }
    }
    if (source[k] >= 0)
      used[source[k]] = true;
  }
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (source[k] < 0)
      continue;
    const CachedContactPoint& match = cached.points[source[k]];
    Point& p = points[k];
    p.normal_impulse = match.normal_impulse;
    p.tangent_impulse1 = match.friction_impulse.dot(p.tangent1);
    p.tangent_impulse2 = match.friction_impulse.dot(p.tangent2);
  }
}

Real ContactSolver::separation(const Point& p, std::span<const BodyState> bodies) const {
  const BodyState& a = bodies[p.a];
  const BodyState& b = bodies[p.b];
  const Vec3 anchor_a = a.position + a.orientation * p.local_a;
  const Vec3 anchor_b = b.position + b.orientation * p.local_b;
  return p.base_separation + (anchor_a - anchor_b).dot(p.normal);
}

Real ContactSolver::normal_velocity(const Point& p, std::span<const BodyState> bodies) {
  const BodyState& a = bodies[p.a];
  const BodyState& b = bodies[p.b];
  return p.normal.dot(a.velocity - b.velocity) + p.rn_a.dot(a.angular_velocity) -
         p.rn_b.dot(b.angular_velocity);
}

void ContactSolver::apply_normal(const Point& p, Real impulse, std::span<BodyState> bodies) {
  BodyState& a = bodies[p.a];
  BodyState& b = bodies[p.b];
  a.velocity += (p.inv_mass_a * impulse) * p.normal;
  a.angular_velocity += impulse * p.in_a;
  b.velocity -= (p.inv_mass_b * impulse) * p.normal;
  b.angular_velocity -= impulse * p.in_b;
}

void ContactSolver::apply_tangent(const Point& p, Real impulse1, Real impulse2,
                                  std::span<BodyState> bodies) {
  BodyState& a = bodies[p.a];
  BodyState& b = bodies[p.b];
  const Vec3 linear = impulse1 * p.tangent1 + impulse2 * p.tangent2;
  a.velocity += p.inv_mass_a * linear;
  a.angular_velocity += impulse1 * p.it1_a + impulse2 * p.it2_a;
  b.velocity -= p.inv_mass_b * linear;
  b.angular_velocity -= impulse1 * p.it1_b + impulse2 * p.it2_b;
}

void ContactSolver::warm_start(std::span<BodyState> bodies) const {
  for (const Point& p : points_) {
    apply_normal(p, p.normal_impulse, bodies);
    apply_tangent(p, p.tangent_impulse1, p.tangent_impulse2, bodies);
  }
}

void ContactSolver::solve(std::span<BodyState> bodies, bool use_bias) {
  const Real inv_h = Real(1) / settings_.substep;
  for (const PairInfo& pair : pairs_) {
    const std::span<Point> points = std::span(points_).subspan(pair.first_point, pair.count);
    // Normal constraints first, so friction works with this pass's normal impulses.
    for (Point& p : points) {
      const Real s = separation(p, bodies);
      Real bias = 0;
      Real mass_scale = 1;
      Real impulse_scale = 0;
      if (s > 0) {
        bias = s * inv_h;  // speculative: close the gap within the substep, no further
      } else if (use_bias) {
        const Real excess = std::min(s + settings_.penetration_slop, Real(0));
        bias = std::max(bias_rate_ * excess, -settings_.max_push_velocity);
        mass_scale = mass_scale_;
        impulse_scale = impulse_scale_;
      }
      const Real vn = normal_velocity(p, bodies);
      const Real delta =
          -p.normal_mass * mass_scale * (vn + bias) - impulse_scale * p.normal_impulse;
      const Real new_impulse = std::max(p.normal_impulse + delta, Real(0));
      const Real applied = new_impulse - p.normal_impulse;
      p.normal_impulse = new_impulse;
      if (!p.touched && new_impulse > 0) {
        // The first push of this step: the normal velocity just before it is the impact
        // velocity that restitution reflects.
        p.touched = true;
        p.impact_velocity = vn;
      }
      apply_normal(p, applied, bodies);
    }
    for (Point& p : points) {
      const BodyState& a = bodies[p.a];
      const BodyState& b = bodies[p.b];
      const Vec3 dv = a.velocity - b.velocity;
      const Real v1 =
          p.tangent1.dot(dv) + p.rt1_a.dot(a.angular_velocity) - p.rt1_b.dot(b.angular_velocity);
      const Real v2 =
          p.tangent2.dot(dv) + p.rt2_a.dot(a.angular_velocity) - p.rt2_b.dot(b.angular_velocity);
      const Real max_friction = p.friction * p.normal_impulse;
      Real new1 = p.tangent_impulse1 - v1 * p.tangent_mass1;
      Real new2 = p.tangent_impulse2 - v2 * p.tangent_mass2;
      const Real magnitude = std::sqrt(new1 * new1 + new2 * new2);
      if (magnitude > max_friction) {
        // Clamp to the friction disc, not a box, so sliding friction is isotropic.
        const Real scale = magnitude > 0 ? max_friction / magnitude : Real(0);
        new1 *= scale;
        new2 *= scale;
      }
      apply_tangent(p, new1 - p.tangent_impulse1, new2 - p.tangent_impulse2, bodies);
      p.tangent_impulse1 = new1;
      p.tangent_impulse2 = new2;
    }
  }
}

int ContactSolver::resolve_impacts(std::span<BodyState> bodies) {
  const Real h = settings_.substep;
  int bounces = 0;
  // Each sweep can pass the impact one pair further along a chain whose pairs are listed in
  // the opposite order; a point bounces at most once, so the number of points bounds the sweeps.
  const std::size_t max_sweeps = points_.size() + 1;
  for (std::size_t sweep = 0; sweep < max_sweeps; ++sweep) {
    bool any = false;
    for (Point& p : points_) {
      if (p.restitution == 0 || p.bounced)
        continue;
      const Real vn = normal_velocity(p, bodies);
      if (vn > -settings_.restitution_threshold || separation(p, bodies) + vn * h > 0)
        continue;
      p.bounced = true;
      p.touched = true;
      p.impact_velocity = vn;
      apply_normal(p, -p.normal_mass * (1 + p.restitution) * vn, bodies);
      any = true;
      ++bounces;
    }
    if (!any)
      break;
  }
  return bounces;
}

// Called after each substep's relax pass. A point whose first push in this step met an
// approach faster than the threshold leaves with -e times that impact velocity, once per step.
// Bouncing in the substep of impact, not at the end of the step, keeps the bounce's timing
// error to one substep. The bounce impulse is not added to the accumulated impulse: that one is
// re-applied by every substep's warm start, and the bounce must happen once.
void ContactSolver::apply_restitution(std::span<BodyState> bodies) {
  for (Point& p : points_) {
    if (p.restitution == 0 || !p.touched || p.bounced ||
        p.impact_velocity > -settings_.restitution_threshold) {
      continue;
    }
    p.bounced = true;
    const Real vn = normal_velocity(p, bodies);
    const Real impulse = -p.normal_mass * (vn + p.restitution * p.impact_velocity);
    if (impulse > 0)
      apply_normal(p, impulse, bodies);
  }
}

void ContactSolver::store(std::vector<CachedManifold>& cache) const {
  detail::store_manifolds(pairs_, pair_bodies_, points_, cache);
}

}  // namespace tumble
