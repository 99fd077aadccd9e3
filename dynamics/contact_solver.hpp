// Contact solver: sequential impulses with soft contacts and substepping ("soft step"), solved a
// manifold at a time, several manifolds side by side in vector lanes.
//
// Sources: Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005 (accumulated, clamped
// impulses and warm starting); Catto, "Solver2D" (2024) and Box2D v3's solver (soft step:
// substeps with a soft, mass-independent contact spring, then a relax pass that removes the
// spring's bias velocity so that pushing out penetration adds no energy); Catto, "SIMD Matters"
// (2024) and Box2D v3's wide contact solver (graph colouring, constraints in structure of arrays
// solved a colour at a time, a compact body-velocity array); Box2D v2's block solver (Catto,
// b2ContactSolver::SolveVelocityConstraints) for solving a manifold's normal rows together.
//
// Per manifold: the normal rows of all its points are solved together, as one small linear
// complementarity problem (all points pushing; when one would pull, again without it), so that a
// box on a face feels one push spread by the geometry instead of four in a fixed order, which
// tips it; then Coulomb friction point by point, clamped to the disc mu * lambda_n. A point apart
// may close its gap within the substep (speculative); a point penetrating deeper than the slop is
// pushed out by a spring of `contact_hertz` and `contact_damping_ratio`, at most
// `max_push_velocity`. Restitution is applied once per step, in the substep of impact, to points
// that met an approach faster than the threshold. Impulses are warm-started by feature id (nearest
// point as fallback) from the previous step. Separation is tracked through the substeps from the
// bodies' motion, without running collision again. docs/architecture.md tells the whole step.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "collision/contact.hpp"
#include "dynamics/contact_cache.hpp"
#include "dynamics/contact_graph.hpp"
#include "dynamics/parallel_runner.hpp"
#include "dynamics/rigid_body.hpp"

namespace tumble {

// The settings of one group of contacts for one step (every island of a group shares its
// substep count: docs/architecture.md, "Substeps per island").
struct ContactSolverSettings {
  Real substep = Real(1) / 240;            // h, one substep [s]
  int substeps = 4;                        // substeps per step (the cache holds step impulses)
  Real penetration_slop = Real(0.0001);    // penetration left alone [m]
  Real contact_hertz = 30;                 // stiffness of the push-out spring [Hz]
  Real static_contact_hertz = 60;          // the same against a static body [Hz]
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

// What loads a contact's points, per unit effective mass (force times the point's J M^-1 J^T).
struct ContactLoad {
  Real warm = 0;    // the largest warm-start impulse over dt [m/s^2]
  Real weight = 0;  // the upper body's weight shared by the points [m/s^2]
  // The largest J M^-1 J^T of the points [1/kg]: a force F on the point loads it F times this.
  Real inverse_effective_mass = 0;
};

namespace detail {
struct WideKernels;
}

class ContactSolver {
 public:
  ContactSolver();
  // With the given vector kernels (detail::available_wide_kernels), for tests that compare them.
  explicit ContactSolver(const detail::WideKernels& kernels);
  ~ContactSolver();
  ContactSolver(ContactSolver&&) noexcept;
  ContactSolver& operator=(ContactSolver&&) noexcept;

  // First half of the preparation: the constraints for `contacts` (sorted by pair) from the
  // bodies' poses at the start of the step, with warm-start impulses from `previous` (sorted by
  // pair), a step of `dt` long under `gravity` [m/s^2].
  void build(std::span<const PairContact> contacts, std::span<const CachedManifold> previous,
             std::span<const BodyState> bodies, std::span<const BodyMass> masses, Real dt,
             const Vec3& gravity);
  // For each contact of the last build (in its order), the forces that load its points per unit
  // effective mass [m/s^2]. A soft contact of angular frequency omega settles load / omega^2
  // deep, so the world picks an island's substeps from them (docs/architecture.md, "Substeps
  // per island").
  std::span<const ContactLoad> contact_loads() const { return loads_; }
  // Second half: contact c is solved in group group_of_contact[c], with the substeps and
  // stiffness of group_settings[that group]; each group's pairs are coloured and packed into
  // vector lanes. Groups must not share a moving body, except bodies of infinite mass that move
  // (`kinematic`, one flag per body, may be empty): each group gives them a slot of their own.
  void pack(std::span<const std::int32_t> group_of_contact,
            std::span<const ContactSolverSettings> group_settings,
            std::span<const std::uint8_t> kinematic = {});
  // Both halves, every contact in one group.
  void prepare(std::span<const PairContact> contacts, std::span<const CachedManifold> previous,
               std::span<const BodyState> bodies, std::span<const BodyMass> masses,
               const ContactSolverSettings& settings);

  // Threads for the passes over a colour, the separations and the build (null: this thread).
  // Results do not depend on the runner's thread count.
  void set_runner(const ParallelRunner* runner) { runner_ = runner; }

  int group_count() const { return static_cast<int>(groups_.size()); }
  int group_point_count(int group) const { return groups_[std::size_t(group)].point_count; }

  // The solver works on its own compact copy of the velocities of the bodies a group's contacts
  // touch: load before the passes, store after them.
  void load_velocities(int group, std::span<const BodyState> bodies);
  void store_velocities(int group, std::span<BodyState> bodies) const;
  // Each point's separation now, from how far its bodies moved since the start of the step
  // (call after the positions moved). The bodies' motions are taken now; the bundles get them in
  // the next pass over them (solve) or before whatever else reads a separation first.
  void update_separations(int group, std::span<const BodyState> bodies);

  // Applies the accumulated impulses (start of every substep).
  void warm_start(int group);
  // One pass over the group's manifolds, a colour at a time. With `use_bias`, penetration is
  // pushed out by the soft spring; without (the relax pass), the constraint is rigid and removes
  // the push-out velocity.
  void solve(int group, bool use_bias);
  // Before each substep's warm start and soft passes: points that approach faster than the
  // restitution threshold and whose gap closes within the substep bounce now, one pair at a
  // time, in sweeps until no such point is left (each point at most once per step; a point that
  // bounces drops its accumulated normal impulse, so the warm start adds nothing to the
  // bounce). Before the warm start, because the bounce reflects the approach it sees, and the
  // cached impulses of other contacts may add approach the passes then take back. Resolving impacts
  // pairwise and in sequence, before the passes can spread the impact over every touching
  // body, is what lets momentum pass down a row of touching bodies (Newton's cradle); each
  // pairwise bounce with e <= 1 can only remove energy. Returns the bounces made.
  int resolve_impacts(int group);
  // After each substep's relax pass: points that met an approach faster than the threshold in
  // the passes (not caught by resolve_impacts) leave with -e times it.
  void apply_restitution(int group);
  // Writes the accumulated impulses (over the whole step), for the next step's warm start, into
  // `cache` in pair order.
  void store(std::vector<CachedManifold>& cache);

  // The same passes on BodyState directly for a solver prepared with one group (load, act,
  // store): for tests and single calls.
  void warm_start(std::span<BodyState> bodies);
  void solve(std::span<BodyState> bodies, bool use_bias);
  int resolve_impacts(std::span<BodyState> bodies);
  void apply_restitution(std::span<BodyState> bodies);

  int point_count() const { return point_count_; }
  int manifold_count() const { return static_cast<int>(records_.size()); }
  // Colours used over all groups, and pairs that found no colour, in the last pack.
  int color_count() const { return color_count_; }
  int overflow_count() const { return overflow_count_; }
  // Bytes held for constraints and bodies (capacity), for the benchmark's memory figures.
  std::size_t bytes_reserved() const;

 private:
  struct PointRecord {
    Vec3 r_a = Vec3::Zero();  // lever arms at the start of the step (world)
    Vec3 r_b = Vec3::Zero();
    Real normal_diagonal = 0;  // J M^-1 J^T of the normal row (the substep choice needs it)
    Real base_separation = 0;  // -depth: both anchors start at the contact point
    // Accumulated impulses: over the step after build(), per substep once packed.
    Real normal_impulse = 0;
    Real tangent_impulse1 = 0, tangent_impulse2 = 0;
    std::uint32_t feature = 0;
    Vec3 local_a = Vec3::Zero();  // the contact point in A's frame, for the cache
  };

 public:
  // The width-independent record of one manifold, made by build() and packed into lanes. The
  // rest of the rows (the tangents' effective masses, the normal rows' coupling terms) are
  // computed by the pack, several manifolds at a time in vector lanes.
  struct ManifoldRecord {
    std::int32_t body_a = 0, body_b = 0;
    std::int32_t slot_a = 0, slot_b = 0;  // in the compact velocity array; 0 = static
    std::int32_t count = 0;
    Vec3 normal = Vec3::UnitZ();
    Vec3 tangent1 = Vec3::UnitX();
    Vec3 tangent2 = Vec3::UnitY();
    Real inv_mass_a = 0, inv_mass_b = 0;
    Real friction = 0, restitution = 0;
    // The separation's second derivative along the pair's sliding direction at the start of the
    // step [1/m]; 0 for a flat contact (the manifold's separation_curvature, "Curved contacts").
    Real curvature = 0;
    std::array<PointRecord, kMaxManifoldPoints> points{};
  };

  // The solver's velocity of one body, padded to a cache line so lanes load it whole.
  struct alignas(64) Velocity {
    Real v[3];
    Real w[3];
    Real pad[2];
  };
  // How far a body moved since the start of the step: displacement and rotation less identity.
  struct alignas(32) Motion {
    Real dp[3];
    Real rotation_less_identity[9];  // row-major
  };
  // Soft-constraint coefficients of the substep (Catto, Solver2D).
  struct Coefficients {
    Real h = 0;
    Real inv_h = 0;
    // [0] pairs of two moving bodies, [1] pairs with a static body.
    Real bias_rate[2] = {0, 0};        // omega / (2 zeta + h omega) [1/s]
    Real soft_compliance[2] = {0, 0};  // 1 / (h omega (2 zeta + h omega)): c = A_ii * this
    Real slop = 0;
    Real max_push = 0;
    Real restitution_threshold = 0;
  };

 private:
  static void warm_start_from(const CachedManifold& cached, Real match_distance, ManifoldRecord& m);
  // Gravity as build_record reads it, worked out once per build (a square root and a division
  // each, which every record waited on).
  struct Gravity {
    Real magnitude = 0;        // |g|
    Vec3 down = Vec3::Zero();  // g / |g|
    bool present = false;      // |g|^2 > 0
  };
  // build()'s work for one contact.
  static void build_record(const PairContact& pc, const CachedManifold* cached,
                           std::span<const BodyState> bodies, std::span<const BodyMass> masses,
                           std::span<const Mat3> inverse_inertia_world, Real dt,
                           const Gravity& gravity, ManifoldRecord& m, ContactLoad& load);

  struct Run {
    std::int32_t begin, end;  // bundles of one colour, or of the overflow (one pair each)
    bool sequential;          // the overflow: its bundles share bodies
  };
  struct Group {
    ContactSolverSettings settings;
    Coefficients coefficients;
    std::int32_t slot_begin = 1, slot_end = 1;  // its moving bodies
    std::int32_t bundle_begin = 0, bundle_end = 0;
    std::int32_t run_begin = 0, run_end = 0;
    int point_count = 0;
    bool has_restitution = false;
  };

  // Calls body(begin, end) over [0, count) in chunks of `grain` on the runner's threads.
  template <class Body>
  void for_chunks(std::int32_t count, std::int32_t grain, Body&& body) const;

  template <class Kernel>
  void for_each_colour(const Group& g, const Kernel& kernel);
  // store()'s work for records [begin, end).
  void store_records(std::int32_t begin, std::int32_t end,
                     std::vector<CachedManifold>& cache) const;

  void apply_pending_separations(int group);
  // update_separations' work for slots [begin, end): each body's motion since the step began.
  void update_motions(std::int32_t begin, std::int32_t end, std::span<const BodyState> bodies);

  const detail::WideKernels* kernels_;
  const ParallelRunner* runner_ = nullptr;
  int pending_separations_group_ = -1;   // whose bundles wait for update_separations' motions
  std::vector<ManifoldRecord> records_;  // in contact (pair) order
  std::vector<ContactLoad> loads_;
  std::vector<std::int32_t> group_of_record_;
  std::vector<Group> groups_;
  std::vector<Run> runs_;
  int bundle_count_ = 0;
  int point_count_ = 0;
  int color_count_ = 0;
  int overflow_count_ = 0;

  // Lanes: bundles of kernels_->lanes manifolds, group by group and colour by colour, in an
  // aligned buffer.
  struct AlignedFree {
    void operator()(std::byte* p) const;
  };
  std::unique_ptr<std::byte[], AlignedFree> bundles_;
  std::size_t bundle_capacity_ = 0;         // bytes
  std::vector<std::int32_t> lane_records_;  // bundle b, lane l: record index, or -1

  // Slots: 0 is every static body; then each moving body the contacts touch, group by group, in
  // order of first appearance in the pairs.
  std::vector<std::int32_t> slot_of_body_;
  std::vector<std::int32_t> body_of_slot_;  // [0] unused
  std::vector<Velocity> velocities_;
  std::vector<Motion> motions_;
  std::vector<Vec3> start_position_;  // per body of the last build
  std::vector<Quat> start_orientation_;
  std::vector<Mat3> inverse_inertia_world_;               // per body of the last build
  std::vector<const CachedManifold*> cached_of_contact_;  // its last-step manifold, or null
  ContactGraph graph_;
  std::vector<std::int32_t> group_records_;  // scratch: one group's records in pair order
  std::vector<std::int32_t> single_group_;   // prepare(): every contact in group 0
  std::vector<std::int32_t> pair_slot_a_, pair_slot_b_;
};

}  // namespace tumble
