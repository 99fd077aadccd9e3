// Penalty contact solver (Moore and Wilhelms, "Collision Detection and Response for Computer
// Animation", SIGGRAPH 1988): each contact point is a spring-damper along the normal,
//   f_n = max(0, -k phi - c v_n),
// with phi the signed separation (negative when penetrating) and v_n the normal approach
// velocity, and regularised Coulomb friction: a viscous force -mu f_n v_t / v_reg, clamped to
// the disc |f_t| <= mu f_n, so that friction is a smooth function of the sliding velocity.
//
// Stiff springs (k up to 1e9 N/m at dt = 1/60) are integrated implicitly: over a substep h the
// spring and damper see the velocity at the end of the substep (linearised backward Euler,
// Hairer & Wanner, "Solving ODEs II", IV.3, applied to the contact as a 1D spring-damper with
// the point's effective mass). For one contact the update is
//   lambda = h (-k phi - (h k + c) v_n') ,   v_n' = v_n + lambda / m_eff,
// which is unconditionally stable: its amplification factor is below 1 for every k h^2 / m.
// Coupled contacts form the linear system (M + h C + h^2 K) dv = ..., which is symmetric positive
// definite, so projected Gauss-Seidel on it (the `iterations` passes) converges to the implicit
// step of the whole contact network. Impulses persist across substeps and steps (warm start),
// which only speeds that convergence: the fixed point does not depend on the starting guess.
//
// Limits (docs/stability.md): backward Euler dissipates energy at every contact (more the
// larger omega h), so a penalty contact with c = 0 still loses energy and the bounce of an
// elastic collision is below 1; bodies at rest sink by m g / k; with k h^2 / m_eff >> 1 the
// spring acts as a rigid constraint with a full Baumgarte correction phi / h.
#pragma once

#include <span>
#include <vector>

#include "collision/contact.hpp"
#include "dynamics/contact_cache.hpp"
#include "dynamics/contact_solver.hpp"
#include "dynamics/rigid_body.hpp"
#include "dynamics/solver_point.hpp"

namespace tumble {

struct PenaltySolverSettings {
  Real substep = Real(1) / 240;  // h [s]
  // Sliding speed at which friction reaches its Coulomb bound; slower sliding sees a viscous
  // force proportional to speed. Small: it is the creep speed scale of a loaded contact. [m/s]
  Real friction_regularisation_speed = Real(1e-3);
  // Passes per substep: at least `min_iterations`, then until a pass changes no point's normal
  // velocity by more than `tolerance` (its impulse change over its effective mass), at most
  // `max_iterations`. An unconverged pass is not the implicit step: one Gauss-Seidel pass per
  // substep on a 20-box tower at k h^2 / m ~ 1 gains energy and topples it, and a tolerance
  // relative to the largest impulse leaves the light box of a 1:1000 stack unconverged and
  // tilting (docs/stability.md). A velocity is comparable across mass ratios. [m/s]
  int min_iterations = 1;
  int max_iterations = 64;
  Real tolerance = Real(1e-5);
};

// Spring and damper of a contact pair, combined from the two materials.
struct PenaltyPair {
  Real stiffness = 0;  // k [N/m]
  Real damping = 0;    // c [N s/m]
};

class PenaltySolver {
 public:
  // `springs[i]` belongs to `contacts[i]`.
  void prepare(std::span<const PairContact> contacts, std::span<const PenaltyPair> springs,
               std::span<const CachedManifold> previous, std::span<const BodyState> bodies,
               std::span<const BodyMass> masses, const PenaltySolverSettings& settings);
  // Start of every substep: measures each point's separation (the poses do not change during
  // the substep's passes) and applies the accumulated impulses.
  void begin_substep(std::span<BodyState> bodies);
  // One Gauss-Seidel pass on the implicit spring-damper system of this substep. Returns the
  // largest change of a point's normal velocity that the pass made [m/s], the measure of
  // convergence the stepper iterates on.
  Real solve(std::span<BodyState> bodies);
  void store(std::vector<CachedManifold>& cache) const;

  int point_count() const { return static_cast<int>(points_.size()); }
  const PenaltySolverSettings& settings() const { return settings_; }

 private:
  struct Point : detail::SolverPoint {
    Real substep_separation = 0;  // phi at the start of the current substep [m]
    Real stiffness = 0;
    Real damping = 0;
  };
  struct PairInfo {
    std::int32_t first_point = 0;
    std::int32_t count = 0;
  };

  Real separation(const Point& p, std::span<const BodyState> bodies) const;
  static void apply(const Point& p, Real normal, Real tangent1, Real tangent2,
                    std::span<BodyState> bodies);

  PenaltySolverSettings settings_;
  std::vector<Point> points_;
  std::vector<PairInfo> pairs_;
  std::vector<std::int32_t> pair_bodies_;
  std::vector<Real> inverse_mass_;
  std::vector<Mat3> inverse_inertia_world_;
};

}  // namespace tumble
