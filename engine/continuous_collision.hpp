// The continuous-collision stage of the step (docs/ccd.md, "In the stepper"). Discrete collision
// looks at the world once per step, so a body that moves farther than its thickness in a step
// can pass through a thin one (tunnelling). Bodies that move far in a step are therefore swept
// from their pose at the start of the step to their pose at the end, and a body that would meet
// another is stopped at the first time of impact.
//
// Which pairs are tested: only swept bodies pay for sweeps. The discrete broad phase holds every
// body's box at the start of the step, grown by at most the sweep threshold below (Simulation's
// bounds stage caps the speculative growth there, so a fast body does not pair with everything
// along its path). The sweep finds its pairs from boxes over each body's actual motion (start
// to end of the step): with many swept bodies one sort and sweep of all bodies' motion boxes;
// with few, each swept body's motion box queries the broad phase for static and unswept bodies,
// and the swept bodies are sorted and swept among themselves (both move). docs/ccd.md.
//
// Which bodies are swept (the scene's `ccd`): `off` none; `on` every dynamic body; `auto` the
// bodies marked `fast: true` and those whose surface moves more than kAutoSweepFraction of
// their thickness in the step (thickness: sphere and capsule radius, smallest box half extent;
// a sphere's spin, and a capsule's or cylinder's about its own axis, moves no part of the space
// it fills, so that part of the turn does not count).
//
// How the rest of the step is kept: by rounds of impacts. The body is put at its pose at the
// time of impact (a small gap before contact), and the impact is resolved there and then, along
// the normal at the time of impact: the centres' approach speed is reflected by the pair's
// restitution (zero below the restitution threshold), by an impulse shared by the inverse
// masses. Leaving the approach to the next step's solver relies on the narrow phase finding that
// contact, and it keeps one manifold per pair, without the points whose normal is more than 60
// degrees from the deepest one's (contact_collector.hpp): a body wedged between two such mesh
// faces, stopped there step after step, would keep every m/s gravity gave it until a knock set
// it free. Then both bodies of each impact move on from there through the rest of the step with
// their new velocities, swept again against everything (another round), so that a chain of
// impacts (a row of balls struck at speed, a ball into a corner) loses no time and tunnels
// nowhere. In a round each group of bodies that may meet takes only its first hit (what that
// impact changes may bring a member to an earlier meeting than the group's later hits); the
// rest are found again in the next round, against the changed motions. After kMaxImpactRounds
// a body still being hit stays where its last impact left it (the rest of its step given up).
// docs/ccd.md, "Rounds of impacts".
#pragma once

#include <cstdint>
#include <span>
#include <vector>
#include "dynamics/parallel_runner.hpp"

#include "collision/broad_phase/broad_phase.hpp"
#include "collision/cache_prefetch.hpp"
#include "collision/ccd/rigid_motion.hpp"
#include "dynamics/rigid_body.hpp"
#include "engine/model.hpp"
#include "tumble/scene.hpp"

namespace tumble {

// `auto` sweeps a body whose surface moves more than this fraction of its thickness in a step.
inline constexpr Real kAutoSweepFraction = Real(0.5);

// Pairs with a swept body are found by sorting every body's motion box once one body in this
// many is swept, else by a broad-phase query per swept body.
inline constexpr std::int64_t kSortAllFraction = 8;

// After the first impacts, the bodies whose velocity an impact changed are swept again through
// the rest of the step, up to this many rounds; a body still in a chain of impacts after them
// gives up the rest of its step where it stands.
inline constexpr int kMaxImpactRounds = 16;

struct ContinuousCollisionCounts {
  std::int64_t swept_bodies = 0;     // bodies swept this step
  std::int64_t candidate_pairs = 0;  // pairs with a swept body whose boxes overlap
  std::int64_t toi_queries = 0;      // time-of-impact queries run
  std::int64_t stopped_bodies = 0;   // bodies moved back to a time of impact
  std::int64_t impact_rounds = 0;    // rounds that swept bodies on after an impact
};

class ContinuousCollision {
 public:
  explicit ContinuousCollision(const Scene& scene);
  // For another scene (a world's reset), keeping the tables' storage.
  void rebuild(const Scene& scene);

  // True when the scene can ever need the stage (`ccd` not off and some dynamic body).
  bool enabled() const { return enabled_; }

  // How far the surface of `body` may move in a step before `auto` sweeps it [m]. A body that
  // moves less is not swept, so the discrete stages must cover that much motion themselves;
  // beyond it the sweep does, and the bounds stage needs to grow the body's box no further.
  Real sweep_threshold(std::size_t body) const { return kAutoSweepFraction * thickness_[body]; }

  // Records the tables the gate of run() reads, to be asked for ahead
  // (collision/cache_prefetch.hpp).
  void prefetch(CachePrefetch& requests) const {
    requests.record_each(gate_, thickness_, turning_radius_);
  }

  // `start` holds each body's pose at the start of the step, `bodies` the state after the
  // position integration (changed in place for stopped bodies), `broad_phase` every body's box
  // at the start of the step (grown by the bounds stage), `masses` each body's (for the impact
  // at a stop). Allocates nothing once warmed up.
  // The time-of-impact queries run on `runner`'s threads (the same results on any count).
  ContinuousCollisionCounts run(const Model& model, const std::vector<Transform>& start,
                                const BroadPhase& broad_phase, std::vector<BodyState>& bodies,
                                std::span<const BodyMass> masses, const ParallelRunner& runner);

  // How the pairs with a swept body are found. Every way gives bit-identical results (a pair
  // whose boxes are apart can never come within the stop distance); tests compare them.
  enum class PairSearch : std::uint8_t {
    automatic,    // sort_all when one body in kSortAllFraction or more is swept, else broad_phase
    broad_phase,  // each swept body queries the broad phase; swept bodies sorted among themselves
    sort_all,     // the motion boxes of all bodies sorted and swept on one axis at once
    every_pair,   // no pruning: every pair with a swept body is tested
  };
  void set_pair_search(PairSearch search) { pair_search_ = search; }
  // Whether a round after an impact takes again a pair's earlier answer for the same motions
  // (tested_pairs_). Either way gives bit-identical results; tests compare them.
  void set_reuse_tests(bool reuse) { reuse_tests_ = reuse; }

 private:
  // The step's pairs to test, in the order found, and what each test found: they run on the
  // runner's threads, each writing its own result, and the hits are recorded in pair order after.
  struct PairTest {
    std::int32_t a = 0, b = 0;
    Real time = 1;
    Vec3 normal = Vec3::Zero();
    std::int8_t queries = 0;
    bool hit = false;
  };
  bool may_sweep(const Scene& scene, const std::vector<Transform>& start,
                 const std::vector<BodyState>& bodies) const;
  void add_pair(std::int32_t ia, std::int32_t ib, ContinuousCollisionCounts& counts);
  void test_pair(const Scene& scene, PairTest& test) const;
  // `closing_is_an_impact`: a pair that starts in touch and closes is hit at once (in the
  // rounds after an impact; in the first, the contacts take such pairs).
  void test_motions(const Scene& scene, const RigidMotion& ma, const RigidMotion& mb,
                    bool closing_is_an_impact, PairTest& test) const;
  // Sorts entries_ on x and calls `pair(e, f)` for each two whose boxes overlap, one swept.
  template <class Pair>
  void sort_and_sweep(Pair&& pair);
  void sort_and_sweep(ContinuousCollisionCounts& counts);
  void stop_at_earliest_times(const Model& model, std::vector<BodyState>& bodies,
                              std::span<const BodyMass> masses, ContinuousCollisionCounts& counts);
  void record_hit(std::int32_t body, std::int32_t partner, Real time, const Vec3& normal);
  // The impulse of an impact between i and j along n (towards i); false when they do not
  // approach (or both are immovable).
  bool resolve_impact(const Model& model, std::size_t i, std::size_t j, const Vec3& n,
                      std::vector<BodyState>& bodies, std::span<const BodyMass> masses) const;
  // A body whose velocity an impact changed moves on from its pose at move_time_ with it.
  void move_on(std::size_t body, std::vector<BodyState>& bodies, Real dt);
  // Body b's motion from step time `from` to the end of the step.
  RigidMotion rest_of_motion(std::size_t b, Real from) const;
  std::int32_t group_root(std::int32_t body);
  // The box of a body's motion in this round (where it stands, for a static body).
  Aabb round_box(const Scene& scene, std::int32_t body) const;
  void sweep_on_after_impacts(const Model& model, const BroadPhase& broad_phase,
                              Real unswept_travel, std::vector<BodyState>& bodies,
                              std::span<const BodyMass> masses, const ParallelRunner& runner,
                              ContinuousCollisionCounts& counts);

  bool enabled_ = false;
  // Whether the last run finished (a run that threw may leave its scratch tables dirty).
  bool settled_ = false;
  PairSearch pair_search_ = PairSearch::automatic;
  bool reuse_tests_ = true;
  std::vector<Real> thickness_;
  std::vector<Real> radius_;
  std::vector<Real> turning_radius_;  // how far a turn of one radian moves the space a body fills
  std::vector<std::uint8_t> about_own_axis_;  // 1: turning about local z moves none of it
  // may_sweep's view of each body: never swept (static or kinematic), always (`ccd: on`, or
  // `fast`), or when its travel bound exceeds half its sweep threshold.
  static constexpr std::uint8_t kNeverSwept = 0;
  static constexpr std::uint8_t kAlwaysSwept = 1;
  static constexpr std::uint8_t kSweptIfFar = 2;
  std::vector<std::uint8_t> gate_;
  std::vector<std::uint8_t> swept_;
  std::vector<Real> earliest_;
  // Of each swept body's earliest hit: the other body (the lower index among hits at the same
  // time, so the choice does not depend on the order pairs are tested in; -1 for none) and the
  // normal at that time, towards the body (zero when the search stopped at its iteration cap).
  std::vector<std::int32_t> hit_partner_;
  std::vector<Vec3> hit_normal_;
  // Each body's motion over the step: from plan_from_ (a time in the step, 0 but after an
  // impact) to the end, over its parameter 0 to 1.
  std::vector<RigidMotion> motions_;
  std::vector<Real> plan_from_;
  std::vector<Real> move_time_;  // when an impact set the body moving on
  // The bodies to sweep on in the next round, and in this one; 1 in moving_on_ while listed.
  std::vector<std::int32_t> moving_on_list_, next_moving_on_;
  std::vector<std::uint8_t> moving_on_;
  std::vector<std::uint8_t> hit_this_round_;  // took a hit this round
  // The groups of bodies that may meet in a round (union-find; -1 outside every pair), each
  // root's box of its members' motions and whether its first hit has been seen.
  std::vector<std::int32_t> group_of_;
  std::vector<Aabb> group_box_;
  std::vector<std::uint8_t> group_hit_;
  std::vector<std::int32_t> grouped_;
  std::vector<Aabb> changed_boxes_;     // the motions this round's impacts changed
  std::vector<std::uint8_t> moved_on_;  // an impact set it moving this step
  std::vector<std::int32_t> moved_on_list_;
  struct RoundPair {
    std::int32_t a = 0, b = 0;       // a is moving on; b may be too (then a < b)
    Real from = 0;                   // the step time both motions are tested from
    RigidMotion motion_a, motion_b;  // what is left of each motion from `from` on
    bool known = false;              // tested before with these motions (tested_pairs_)
  };
  std::vector<RoundPair> round_pairs_;
  // Each pair's last test in this step's rounds, by (a, b), with the motions it was made for. A
  // body waiting while its group's first hit is resolved keeps its motion, so round after round
  // asks the same queries of it; a test is a function of the two motions, so its answer is
  // taken again. (A fuzzed scene of overlapping fields asked 59% of its advancement iterations
  // again.)
  struct TestedPair {
    std::int32_t a = 0, b = 0;
    Real from = 0;
    RigidMotion motion_a, motion_b;
    PairTest test;
  };
  std::vector<TestedPair> tested_pairs_;  // sorted by (a, b)
  // The entry of (a, b) among the first `sorted` of tested_pairs_ (those sorted), or its end.
  std::vector<TestedPair>::iterator find_tested(std::int32_t a, std::int32_t b, std::size_t sorted);
  std::vector<std::uint32_t> round_order_;
  std::vector<Aabb> swept_boxes_;         // of swept bodies: the box of the whole motion
  std::vector<std::int32_t> swept_list_;  // swept bodies, ascending
  std::vector<std::int32_t> found_;       // broad-phase query output
  struct SweepEntry {
    Aabb box;
    std::int32_t id = 0;
    std::uint8_t swept = 0;
  };
  std::vector<SweepEntry> entries_;  // boxes to sort and sweep
  std::vector<PairTest> tests_;
};

}  // namespace tumble
