// Contact solver: sequential impulses with soft contacts and substepping ("soft step").
//
// Sources: Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005 (accumulated, clamped
// impulses and warm starting); Catto, "Solver2D" (2024) and Box2D v3's solver design (soft
// step: substeps with a soft, mass-independent contact spring, then a relax pass that removes
// the spring's bias velocity so that pushing out penetration adds no energy).
//
// Per contact point: a non-penetration constraint whose bias is speculative when the points are
// apart (a gap may close within the substep but not be overshot) and a critically over-damped
// spring of `contact_hertz` when they penetrate beyond the slop; Coulomb friction clamped to the
// disc mu * lambda_n (two tangent directions clamped together, so sliding is isotropic);
// restitution applied once per step, in the substep of impact, to points that met an approach
// faster than the threshold. Impulses are warm-started by feature id (nearest point as
// fallback) from the previous step. Separation is tracked through the substeps from the bodies'
// motion, without running collision again.
#pragma once

#include <span>
#include <vector>

#include "collision/contact.hpp"
#include "dynamics/contact_cache.hpp"
#include "dynamics/rigid_body.hpp"
#include "dynamics/solver_point.hpp"

namespace tumble {

struct ContactSolverSettings {
  Real substep = Real(1) / 240;            // h, one substep [s]
  Real penetration_slop = Real(0.0005);    // penetration left alone [m]
  Real contact_hertz = 30;                 // stiffness of the push-out spring [Hz]
  Real contact_damping_ratio = 10;         // its damping ratio [1]
  Real max_push_velocity = 3;              // fastest push-out [m/s]
  Real restitution_threshold = Real(0.2);  // slower approaches do not bounce [m/s]
};

// A manifold between two bodies with its combined material.
struct PairContact {
  std::int32_t body_a = 0;  // body_a < body_b
  std::int32_t body_b = 0;
  Real friction = 0;
  Real restitution = 0;
  // A new point without a feature match takes the impulses of the nearest unmatched cached
  // point within this distance [m] (in A's frame). Feature ids of a box resting squarely on
  // another switch between vertex and clipped-edge points under tiny motions; without this
  // fallback each switch would restart that point's impulse from zero.
  Real match_distance = 0;
  Manifold manifold;
};

class ContactSolver {
 public:
  // Builds the constraints for `contacts` (sorted by pair) from the bodies' poses at the start
  // of the step, and takes warm-start impulses from `previous` (sorted by pair).
  void prepare(std::span<const PairContact> contacts, std::span<const CachedManifold> previous,
               std::span<const BodyState> bodies, std::span<const BodyMass> masses,
               const ContactSolverSettings& settings);
  // Applies the accumulated impulses (start of every substep).
  void warm_start(std::span<BodyState> bodies) const;
  // One Gauss-Seidel pass. With `use_bias`, penetration is pushed out by the soft spring;
  // without (the relax pass), the constraint is rigid and removes the push-out velocity.
  void solve(std::span<BodyState> bodies, bool use_bias);
  // Before each substep's soft passes: points that approach faster than the restitution
  // threshold and whose gap closes within the substep bounce now, one pair at a time, in
  // sweeps until no such point is left (each point at most once per step). Resolving impacts
  // pairwise and in sequence, before the inelastic passes can spread the impact over every
  // touching body, is what lets momentum pass down a row of touching bodies (Newton's cradle);
  // each pairwise bounce with e <= 1 can only remove energy. Returns the bounces made.
  int resolve_impacts(std::span<BodyState> bodies);
  // After each substep's relax pass: points that met an approach faster than the threshold in
  // the passes (not caught by resolve_impacts) leave with -e times it.
  void apply_restitution(std::span<BodyState> bodies);
  // Writes the accumulated impulses, for the next step's warm start.
  void store(std::vector<CachedManifold>& cache) const;

  int point_count() const { return static_cast<int>(points_.size()); }

 private:
  struct Point : detail::SolverPoint {
    Real restitution = 0;
    Real impact_velocity = 0;  // normal velocity just before the step's first push
    bool touched = false;      // pushed at least once this step
    bool bounced = false;      // restitution applied this step
  };

  struct PairInfo {
    std::int32_t first_point = 0;
    std::int32_t count = 0;
  };

  static void warm_start_from(const CachedManifold& cached, Real match_distance,
                              std::span<Point> points);
  Real separation(const Point& p, std::span<const BodyState> bodies) const;
  // Velocity along the normal / a tangent, and an impulse along them, from the precomputed rows.
  static Real normal_velocity(const Point& p, std::span<const BodyState> bodies);
  static void apply_normal(const Point& p, Real impulse, std::span<BodyState> bodies);
  static void apply_tangent(const Point& p, Real impulse1, Real impulse2,
                            std::span<BodyState> bodies);

  ContactSolverSettings settings_;
  // Soft-constraint coefficients for the substep (Catto, Solver2D: bias rate, mass scale,
  // impulse scale).
  Real bias_rate_ = 0;
  Real mass_scale_ = 1;
  Real impulse_scale_ = 0;
  std::vector<Point> points_;
  std::vector<PairInfo> pairs_;
  std::vector<std::int32_t> pair_bodies_;  // a, b per pair, for store()
  std::vector<Real> inverse_mass_;
  std::vector<Mat3> inverse_inertia_world_;
};

}  // namespace tumble
