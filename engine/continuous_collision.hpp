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
// How the rest of the step is kept: time stealing. The body is put at its pose at the time of
// impact (a small gap before contact); the rest of its motion in this step is given up. The
// impact itself is resolved there and then, along the normal at the time of impact: the
// centres' approach speed is reflected by the pair's restitution (zero below the restitution
// threshold), by an impulse shared by the inverse masses. Leaving the approach to the next
// step's solver relies on the narrow phase finding that contact, and it keeps one manifold per
// pair, without the points whose normal is more than 60 degrees from the deepest one's
// (contact_collector.hpp): a body wedged between two such mesh faces, stopped there step after
// step, would keep every m/s gravity gave it until a knock set it free. Other bodies keep their
// whole step. Sub-stepping the fast body through the rest of the step would keep the time but
// needs the solver inside this stage; time stealing loses at most one step of a fast body's
// motion at each impact, which is invisible at the speeds where it applies.
#pragma once

#include <cstdint>
#include <span>
#include <vector>
#include "dynamics/parallel_runner.hpp"

#include "collision/broad_phase/broad_phase.hpp"
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

struct ContinuousCollisionCounts {
  std::int64_t swept_bodies = 0;     // bodies swept this step
  std::int64_t candidate_pairs = 0;  // pairs with a swept body whose boxes overlap
  std::int64_t toi_queries = 0;      // time-of-impact queries run
  std::int64_t stopped_bodies = 0;   // bodies moved back to a time of impact
};

class ContinuousCollision {
 public:
  explicit ContinuousCollision(const Scene& scene);

  // True when the scene can ever need the stage (`ccd` not off and some dynamic body).
  bool enabled() const { return enabled_; }

  // How far the surface of `body` may move in a step before `auto` sweeps it [m]. A body that
  // moves less is not swept, so the discrete stages must cover that much motion themselves;
  // beyond it the sweep does, and the bounds stage needs to grow the body's box no further.
  Real sweep_threshold(std::size_t body) const { return kAutoSweepFraction * thickness_[body]; }

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
  void add_pair(std::int32_t ia, std::int32_t ib, ContinuousCollisionCounts& counts);
  void test_pair(const Scene& scene, PairTest& test) const;
  void sort_and_sweep(ContinuousCollisionCounts& counts);
  void stop_at_earliest_times(const Model& model, std::vector<BodyState>& bodies,
                              std::span<const BodyMass> masses,
                              ContinuousCollisionCounts& counts) const;
  void record_hit(std::int32_t body, std::int32_t partner, Real time, const Vec3& normal);

  bool enabled_ = false;
  PairSearch pair_search_ = PairSearch::automatic;
  std::vector<Real> thickness_;
  std::vector<Real> radius_;
  std::vector<Real> turning_radius_;  // how far a turn of one radian moves the space a body fills
  std::vector<std::uint8_t> about_own_axis_;  // 1: turning about local z moves none of it
  std::vector<std::uint8_t> swept_;
  std::vector<Real> earliest_;
  // Of each swept body's earliest hit: the other body (the lower index among hits at the same
  // time, so the choice does not depend on the order pairs are tested in; -1 for none) and the
  // normal at that time, towards the body (zero when the search stopped at its iteration cap).
  std::vector<std::int32_t> hit_partner_;
  std::vector<Vec3> hit_normal_;
  std::vector<RigidMotion> motions_;      // each body's motion over the step
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
