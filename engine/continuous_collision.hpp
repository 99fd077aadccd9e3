// The continuous-collision stage of the step (design.md step 5; seed 4.3 and pitfall 2): bodies
// that move far in a step are swept from their pose at the start of the step to their pose at
// the end, against their broad-phase candidates, and a body that would meet one is stopped at
// the first time of impact.
//
// Which bodies are swept (the scene's `ccd`): `off` none; `on` every dynamic body; `auto` the
// bodies marked `fast: true` and those whose surface moves more than kAutoSweepFraction of
// their thickness in the step (thickness: sphere and capsule radius, smallest box half extent).
//
// How the rest of the step is kept: time stealing. The body is put at its pose at the time of
// impact (a small gap before contact) and keeps its velocity; the rest of its motion in this
// step is given up, and the next step's narrow phase finds the pair within the speculative
// margin, so the solver meets the impact with the velocity the body had. Other bodies keep
// their whole step. Sub-stepping the fast body through the rest of the step would keep the
// time but needs the solver inside this stage; time stealing loses at most one step of a fast
// body's motion at each impact, which is invisible at the speeds where it applies.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/broad_phase.hpp"
#include "dynamics/rigid_body.hpp"
#include "engine/scene.hpp"

namespace tumble {

// `auto` sweeps a body whose surface moves more than this fraction of its thickness in a step.
inline constexpr Real kAutoSweepFraction = Real(0.5);

struct ContinuousCollisionCounts {
  std::int64_t swept_bodies = 0;    // bodies swept this step
  std::int64_t toi_queries = 0;     // time-of-impact queries run
  std::int64_t stopped_bodies = 0;  // bodies moved back to a time of impact
};

class ContinuousCollision {
 public:
  explicit ContinuousCollision(const Scene& scene);

  // True when the scene can ever need the stage (`ccd` not off and some dynamic body).
  bool enabled() const { return enabled_; }

  // `start` holds each body's pose at the start of the step, `bodies` the state after the
  // position integration (changed in place for stopped bodies), `candidates` the step's
  // broad-phase pairs (from bounds swept over the step). Allocates nothing once warmed up.
  ContinuousCollisionCounts run(const Scene& scene, const std::vector<Transform>& start,
                                const std::vector<ProxyPair>& candidates,
                                std::vector<BodyState>& bodies);

 private:
  bool enabled_ = false;
  std::vector<Real> thickness_;
  std::vector<Real> radius_;
  std::vector<std::uint8_t> swept_;
  std::vector<Real> earliest_;
};

}  // namespace tumble
