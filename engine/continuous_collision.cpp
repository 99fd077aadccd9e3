#include "engine/continuous_collision.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "collision/ccd/conservative_advancement.hpp"
#include "collision/shapes/shape.hpp"

namespace tumble {
namespace {

// The body's motion over the step, from its start pose to its pose now. The turn between two
// orientations is only known modulo a full turn, and a body spinning fast turns by more than
// half a turn in a step (each substep of the integrator may turn it by almost half a turn), so
// the turn is taken as the rotation vector that reaches the end orientation and lies closest to
// angular velocity times dt.
RigidMotion step_motion(const Transform& start, const BodyState& end, Real dt) {
  const Vec3 shortest =
      rotation_vector_from_quaternion(end.orientation * start.rotation.conjugate());
  const Vec3 guide = end.angular_velocity * dt;
  const Real angle = shortest.norm();
  Vec3 turn = shortest;
  if (angle > 0) {
    const Vec3 axis = shortest / angle;
    Real best = (shortest - guide).norm();
    for (int m = -3; m <= 3; ++m) {
      const Vec3 candidate = axis * (angle + 2 * Real(M_PI) * m);
      const Real error = (candidate - guide).norm();
      if (error < best) {
        best = error;
        turn = candidate;
      }
    }
  }
  return RigidMotion::from_velocity(start, end.position - start.translation, turn);
}

// A box holding the shape at every time of the motion. Without turning the shape only
// translates, and every translate lies in the box of the two end poses' boxes; a turning shape
// stays within its bounding radius of its centre, which moves on a line (the linear kind).
Aabb motion_box(const Shape& shape, const RigidMotion& m, Real radius) {
  if (m.angular_velocity().squaredNorm() == 0) {
    Aabb box = world_aabb(shape, m.start());
    box.grow(world_aabb(shape, m.end()));
    return box;
  }
  Aabb box;
  box.grow(m.start().translation);
  box.grow(m.end().translation);
  return box.inflated(radius);
}

// Equal to the bit (NaN never equals, so a motion with NaN is always tested again).
bool same_bits(Real x, Real y) {
  return x == y && std::signbit(x) == std::signbit(y);
}

bool same_pose(const Transform& x, const Transform& y) {
  for (int i = 0; i < 3; ++i) {
    if (!same_bits(x.translation[i], y.translation[i]))
      return false;
  }
  for (int i = 0; i < 4; ++i) {
    if (!same_bits(x.rotation.coeffs()[i], y.rotation.coeffs()[i]))
      return false;
  }
  return true;
}

// The same motion to the bit: its kind, poses and turn (the rest of a RigidMotion, its screw
// velocity and centre speed, is computed from these).
bool same_motion(const RigidMotion& x, const RigidMotion& y) {
  return x.kind() == y.kind() && same_pose(x.start(), y.start()) && same_pose(x.end(), y.end()) &&
         same_bits(x.angular_velocity().x(), y.angular_velocity().x()) &&
         same_bits(x.angular_velocity().y(), y.angular_velocity().y()) &&
         same_bits(x.angular_velocity().z(), y.angular_velocity().z());
}

}  // namespace

ContinuousCollision::ContinuousCollision(const Scene& scene) {
  rebuild(scene);
}

void ContinuousCollision::rebuild(const Scene& scene) {
  enabled_ = false;
  const std::size_t n = scene.bodies.size();
  // A run writes each per-run table before it reads it, except the grouping's, which it leaves
  // as a new table has them when it finishes: after a finished run over as many bodies, only the
  // shapes' tables change (a reset in a batch of worlds then touches the five per-body shape and
  // gate tables, not all of them).
  if (!settled_ || thickness_.size() != n) {
    // Each table cleared then sized: the same elements as a new one's, in the storage it has.
    const auto fresh = [n](auto&... tables) { (..., (tables.clear(), tables.resize(n))); };
    fresh(thickness_, radius_, turning_radius_, about_own_axis_, gate_, swept_, earliest_,
          hit_partner_, hit_normal_, motions_, plan_from_, move_time_, moving_on_, hit_this_round_,
          group_box_, group_hit_, moved_on_, swept_boxes_);
    group_of_.assign(n, -1);
    // The per-run lists are empty after a run that finished; one that threw may have left some.
    // The pair search chosen by set_pair_search is a setting, and stays.
    grouped_.clear();
    moving_on_list_.clear();
    next_moving_on_.clear();
    swept_list_.clear();
    found_.clear();
    entries_.clear();
    swept_list_.reserve(n);
    found_.reserve(n);
    entries_.reserve(n);
    settled_ = true;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const BodyDesc& d = scene.bodies[i];
    thickness_[i] = inner_radius(d.shape);
    radius_[i] = d.shape.is_bounded() ? bounding_radius(d.shape) : Real(0);
    // A sphere turning about its centre fills the same space, and so does a capsule or a
    // cylinder turning about its own axis: that part of a turn cannot carry the body through
    // anything (a ball or a log rolling down a slope is not swept for its roll).
    turning_radius_[i] = d.shape.type == ShapeType::sphere ? Real(0) : radius_[i];
    about_own_axis_[i] =
        d.shape.type == ShapeType::capsule || d.shape.type == ShapeType::cylinder ? 1 : 0;
    if (!d.is_static && scene.world.ccd != CcdMode::off)
      enabled_ = true;
    gate_[i] = d.is_static || d.kinematic                 ? kNeverSwept
               : scene.world.ccd == CcdMode::on || d.fast ? kAlwaysSwept
                                                          : kSweptIfFar;
  }
}

// Whether any body may need a sweep this step, from a bound on its travel that costs a quaternion
// product where the exact travel (run) costs a rotation vector and a screw motion per body: most
// steps of most scenes sweep nothing, and then the exact motions are not needed. The bound: the
// shortest turn between the poses has angle 2 asin(|v|) <= pi |v| (v the vector part of the
// relative quaternion), and the turn the step takes is the one nearest the angular velocity's
// guide g, so its length is at most |g| + |shortest - g| <= 2 |g| + pi |v|; the part about a
// body's own axis is not more than the whole. Half the threshold leaves room for rounding.
bool ContinuousCollision::may_sweep(const Scene& scene, const std::vector<Transform>& start,
                                    const std::vector<BodyState>& bodies) const {
  const Real dt = scene.world.dt;
  // The bodies' kinds come from a table of their own (rebuild): the scene's descriptions are large,
  // and reading a flag of each missed the cache once per body.
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (gate_[i] == kNeverSwept)
      continue;
    if (gate_[i] == kAlwaysSwept)
      return true;
    const BodyState& b = bodies[i];
    const Real relative_turn = (b.orientation * start[i].rotation.conjugate()).vec().norm();
    const Real turn_bound =
        2 * b.angular_velocity.norm() * dt + Real(M_PI) * std::min<Real>(relative_turn, 1);
    const Real travel_bound =
        (b.position - start[i].translation).norm() + turn_bound * turning_radius_[i];
    if (!(travel_bound <= Real(0.5) * kAutoSweepFraction * thickness_[i]))
      return true;
  }
  return false;
}

ContinuousCollisionCounts ContinuousCollision::run(const Model& model,
                                                   const std::vector<Transform>& start,
                                                   const BroadPhase& broad_phase,
                                                   std::vector<BodyState>& bodies,
                                                   std::span<const BodyMass> masses,
                                                   const ParallelRunner& runner) {
  const Scene& scene = model.scene();
  ContinuousCollisionCounts counts;
  const std::size_t n = bodies.size();
  const CcdMode mode = scene.world.ccd;
  const Real skin = std::max(scene.world.contact_margin, Real(1e-6));
  swept_list_.clear();
  moved_on_list_.clear();
  // Only the stage below reads these tables, so a step that needs no sweep leaves them alone
  // (clearing them cost a batch of small worlds more than the gate itself: a cache miss per table
  // per world).
  if (mode == CcdMode::off || !may_sweep(scene, start, bodies))
    return counts;
  for (std::size_t i = 0; i < n; ++i) {
    swept_[i] = 0;
    earliest_[i] = 1;
    hit_partner_[i] = -1;
    plan_from_[i] = 0;
    moving_on_[i] = 0;
    moved_on_[i] = 0;
  }
  // The farthest any point of an unswept dynamic body moves in this step: its box in the broad
  // phase covers its start pose, so that box grown by this covers its whole motion.
  Real unswept_travel = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const BodyDesc& d = scene.bodies[i];
    if (d.is_static) {
      motions_[i] = RigidMotion::stationary(start[i]);
      continue;
    }
    motions_[i] = step_motion(start[i], bodies[i], scene.world.dt);
    const RigidMotion& m = motions_[i];
    Vec3 turn = m.angular_velocity();
    if (about_own_axis_[i] != 0) {
      const Vec3 axis = start[i].rotation * Vec3::UnitZ();
      turn -= axis * turn.dot(axis);
    }
    const Real travel = m.centre_speed() + turn.norm() * turning_radius_[i];
    // A kinematic body moves where it is told: it is an obstacle to the swept bodies, never
    // stopped itself.
    if (mode != CcdMode::off && !d.kinematic &&
        (mode == CcdMode::on || d.fast || travel > kAutoSweepFraction * thickness_[i])) {
      swept_[i] = 1;
      swept_list_.push_back(static_cast<std::int32_t>(i));
      swept_boxes_[i] = motion_box(d.shape, m, radius_[i]).inflated(skin);
      ++counts.swept_bodies;
    } else {
      unswept_travel = std::max(unswept_travel, travel);
    }
  }
  if (counts.swept_bodies == 0)
    return counts;
  settled_ = false;
  PairSearch search = pair_search_;
  if (search == PairSearch::automatic) {
    // A broad-phase query costs about as much as sorting a few dozen boxes (a tree descent per
    // swept body); once one body in kSortAllFraction is swept, one sort of every body's motion
    // box is the cheaper way (measured on scenes/high_speed.yaml, docs/ccd.md).
    search = counts.swept_bodies * kSortAllFraction >= static_cast<std::int64_t>(n)
                 ? PairSearch::sort_all
                 : PairSearch::broad_phase;
  }
  entries_.clear();
  tests_.clear();
  if (search == PairSearch::every_pair) {
    for (const std::int32_t s : swept_list_) {
      for (std::int32_t other = 0; other < static_cast<std::int32_t>(n); ++other) {
        // A pair of swept bodies once; an empty slot (a removed body) never.
        if (other == s || (swept_[other] && other < s) || model.is_removed(std::size_t(other)))
          continue;
        add_pair(std::min(s, other), std::max(s, other), counts);
      }
    }
  } else if (search == PairSearch::broad_phase) {
    // Swept against static and unswept bodies, through the broad phase. A swept body's own box
    // and other swept bodies' boxes are there too (at their start poses): skipped, the sort
    // below pairs swept bodies by their whole motion.
    for (const std::int32_t s : swept_list_) {
      broad_phase.query(swept_boxes_[s].inflated(unswept_travel), found_);
      for (const std::int32_t other : found_) {
        if (swept_[other])
          continue;
        add_pair(std::min(s, other), std::max(s, other), counts);
      }
      entries_.push_back({swept_boxes_[s], s, 1});
    }
    sort_and_sweep(counts);
  } else {
    // Every bounded body's box over its own motion (a static body's box where it stands), so
    // unswept bodies need no allowance for having moved; unbounded static shapes (planes) are
    // tested against each swept body's box.
    for (std::size_t i = 0; i < n; ++i) {
      const BodyDesc& d = scene.bodies[i];
      const std::int32_t id = static_cast<std::int32_t>(i);
      if (model.is_removed(i))
        continue;  // an empty slot (a removed body) is nothing to hit
      if (swept_[i]) {
        entries_.push_back({swept_boxes_[i], id, 1});
      } else if (d.shape.is_bounded()) {
        entries_.push_back({d.is_static ? world_aabb(d.shape, start[i])
                                        : motion_box(d.shape, motions_[i], radius_[i]),
                            id, 0});
      } else {
        const Aabb box = world_aabb(d.shape, start[i]);
        for (const std::int32_t s : swept_list_) {
          if (!box.overlaps(swept_boxes_[s]))
            continue;
          add_pair(std::min(s, id), std::max(s, id), counts);
        }
      }
    }
    sort_and_sweep(counts);
  }
  // Each pair's queries on the threads; the hits then in the order the pairs were found (each
  // body keeps its earliest, ties to the lower partner, so the order would not matter anyway).
  constexpr std::int32_t kPairsPerChunk = 16;
  runner.for_chunks(static_cast<std::int32_t>(tests_.size()), kPairsPerChunk,
                    [&](std::int32_t begin, std::int32_t end) {
                      for (std::int32_t k = begin; k < end; ++k)
                        test_pair(scene, tests_[std::size_t(k)]);
                    });
  for (const PairTest& t : tests_) {
    counts.toi_queries += t.queries;
    if (!t.hit)
      continue;
    if (swept_[std::size_t(t.a)])
      record_hit(t.a, t.b, t.time, t.normal);
    if (swept_[std::size_t(t.b)])
      record_hit(t.b, t.a, t.time, -t.normal);
  }
  stop_at_earliest_times(model, bodies, masses, counts);
  sweep_on_after_impacts(model, broad_phase, unswept_travel, bodies, masses, runner, counts);
  settled_ = true;
  return counts;
}

// Sort and sweep on x (Baraff 1992; Cohen et al., I-COLLIDE 1995) over entries_, testing the
// overlapping pairs with a swept body. Ties sort by body index so the order is fixed; the times
// found do not depend on the order anyway (each body keeps its earliest).
template <class Pair>
void ContinuousCollision::sort_and_sweep(Pair&& pair) {
  std::sort(entries_.begin(), entries_.end(), [](const SweepEntry& p, const SweepEntry& q) {
    return p.box.min.x() < q.box.min.x() || (p.box.min.x() == q.box.min.x() && p.id < q.id);
  });
  const std::size_t count = entries_.size();
  for (std::size_t k = 0; k < count; ++k) {
    const SweepEntry& e = entries_[k];
    const Real end = e.box.max.x();
    for (std::size_t j = k + 1; j < count; ++j) {
      const SweepEntry& f = entries_[j];
      if (f.box.min.x() > end)
        break;
      if ((e.swept | f.swept) == 0 || !e.box.overlaps(f.box))
        continue;
      pair(e, f);
    }
  }
}

void ContinuousCollision::sort_and_sweep(ContinuousCollisionCounts& counts) {
  sort_and_sweep([&](const SweepEntry& e, const SweepEntry& f) {
    add_pair(std::min(e.id, f.id), std::max(e.id, f.id), counts);
  });
}

void ContinuousCollision::record_hit(std::int32_t body, std::int32_t partner, Real time,
                                     const Vec3& normal) {
  const std::size_t i = static_cast<std::size_t>(body);
  if (time < earliest_[i] ||
      (time == earliest_[i] && (hit_partner_[i] < 0 || partner < hit_partner_[i]))) {
    earliest_[i] = time;
    hit_partner_[i] = partner;
    hit_normal_[i] = normal;
  }
}

void ContinuousCollision::stop_at_earliest_times(const Model& model, std::vector<BodyState>& bodies,
                                                 std::span<const BodyMass> masses,
                                                 ContinuousCollisionCounts& counts) {
  next_moving_on_.clear();
  // Each body an impact set moving, and the time it moves on from: a stopped body from its
  // stop, its partner from the impact (the first, when several bodies hit it).
  const auto moves_on = [&](std::size_t b, Real time) {
    if (masses[b].inverse_mass == 0)
      return;
    const bool stopped = swept_[b] && earliest_[b] < 1;
    if (!moving_on_[b]) {
      moving_on_[b] = 1;
      move_time_[b] = stopped ? earliest_[b] : time;
      next_moving_on_.push_back(static_cast<std::int32_t>(b));
    } else if (!stopped) {
      move_time_[b] = std::min(move_time_[b], time);
    }
  };
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (!swept_[i] || earliest_[i] >= 1)
      continue;
    const Transform at = motions_[i].at(earliest_[i]);
    bodies[i].position = at.translation;
    bodies[i].orientation = at.rotation;
    ++counts.stopped_bodies;
    if (hit_partner_[i] < 0)
      continue;
    const std::size_t j = static_cast<std::size_t>(hit_partner_[i]);
    if (!resolve_impact(model, i, j, hit_normal_[i], bodies, masses))
      continue;
    moves_on(i, earliest_[i]);
    moves_on(j, earliest_[i]);
  }
  // A body stopped without an impact stays where it stopped.
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (swept_[i] && earliest_[i] < 1 && !moving_on_[i]) {
      motions_[i] = RigidMotion::stationary(motions_[i].at(earliest_[i]));
      plan_from_[i] = earliest_[i];
    }
  }
  std::sort(next_moving_on_.begin(), next_moving_on_.end());
  for (const std::int32_t b : next_moving_on_)
    move_on(static_cast<std::size_t>(b), bodies, model.scene().world.dt);
}

bool ContinuousCollision::resolve_impact(const Model& model, std::size_t i, std::size_t j,
                                         const Vec3& n, std::vector<BodyState>& bodies,
                                         std::span<const BodyMass> masses) const {
  // The approach of the centres along the normal, reflected by the restitution, by an impulse
  // shared as the inverse masses share it.
  const Real approach = (bodies[i].velocity - bodies[j].velocity).dot(n);
  const Real im_i = masses[i].inverse_mass;
  const Real im_j = masses[j].inverse_mass;
  if (!(approach < 0) || im_i + im_j == 0)
    return false;
  const Real restitution =
      -approach > model.scene().world.restitution_threshold
          ? model.restitution(model.scene().bodies[i].material, model.scene().bodies[j].material)
          : Real(0);
  const Real impulse = -(1 + restitution) * approach / (im_i + im_j);
  bodies[i].velocity += n * (impulse * im_i);
  bodies[j].velocity -= n * (impulse * im_j);
  return true;
}

void ContinuousCollision::move_on(std::size_t b, std::vector<BodyState>& bodies, Real dt) {
  const Real time = move_time_[b];
  const Transform pose = rest_of_motion(b, time).start();
  bodies[b].position = pose.translation;
  bodies[b].orientation = pose.rotation;
  const Real rest = (1 - time) * dt;
  motions_[b] = RigidMotion::from_velocity(pose, bodies[b].velocity * rest,
                                           bodies[b].angular_velocity * rest);
  plan_from_[b] = time;
}

std::vector<ContinuousCollision::TestedPair>::iterator ContinuousCollision::find_tested(
    std::int32_t a, std::int32_t b, std::size_t sorted) {
  const auto end = tested_pairs_.begin() + std::ptrdiff_t(sorted);
  const auto it =
      std::lower_bound(tested_pairs_.begin(), end, std::pair{a, b},
                       [](const TestedPair& x, const std::pair<std::int32_t, std::int32_t>& key) {
                         return x.a < key.first || (x.a == key.first && x.b < key.second);
                       });
  return it != end && it->a == a && it->b == b ? it : tested_pairs_.end();
}

std::int32_t ContinuousCollision::group_root(std::int32_t c) {
  while (group_of_[std::size_t(c)] != c) {
    group_of_[std::size_t(c)] = group_of_[std::size_t(group_of_[std::size_t(c)])];
    c = group_of_[std::size_t(c)];
  }
  return c;
}

Aabb ContinuousCollision::round_box(const Scene& scene, std::int32_t c) const {
  const std::size_t i = std::size_t(c);
  const BodyDesc& d = scene.bodies[i];
  if (d.is_static)
    return world_aabb(d.shape, motions_[i].start());
  if (swept_[i] || moving_on_[i])
    return swept_boxes_[i];
  return motion_box(d.shape, motions_[i], radius_[i]);
}

RigidMotion ContinuousCollision::rest_of_motion(std::size_t b, Real from) const {
  const RigidMotion& m = motions_[b];
  const Real begin = plan_from_[b];
  if (from <= begin)
    return m;
  const Real s = (from - begin) / (1 - begin);
  // The same straight line and turn about a fixed axis, from its pose at `from` on.
  return RigidMotion::from_velocity(m.at(s), m.linear_velocity() * (1 - s),
                                    m.angular_velocity() * (1 - s));
}

void ContinuousCollision::sweep_on_after_impacts(const Model& model, const BroadPhase& broad_phase,
                                                 Real unswept_travel,
                                                 std::vector<BodyState>& bodies,
                                                 std::span<const BodyMass> masses,
                                                 const ParallelRunner& runner,
                                                 ContinuousCollisionCounts& counts) {
  const Scene& scene = model.scene();
  const Real skin = std::max(scene.world.contact_margin, Real(1e-6));
  const Real dt = scene.world.dt;
  tested_pairs_.clear();
  for (int round = 0; round < kMaxImpactRounds && !next_moving_on_.empty(); ++round) {
    ++counts.impact_rounds;
    moving_on_list_.swap(next_moving_on_);
    next_moving_on_.clear();
    for (const std::int32_t a : moving_on_list_) {
      if (!moved_on_[std::size_t(a)]) {
        moved_on_[std::size_t(a)] = 1;
        moved_on_list_.push_back(a);
      }
    }
    // The pairs: each body moving on against the static and slow bodies near its path (the
    // broad phase: boxes at the start of the step, grown by the farthest a slow body moves),
    // every swept body, and every other body moving on; from the later of the two motions'
    // starts.
    round_pairs_.clear();
    const auto add_round_pair = [&](std::int32_t a, std::int32_t b) {
      RoundPair& p = round_pairs_.emplace_back();
      p.a = a;
      p.b = b;
      p.from = std::max(plan_from_[std::size_t(a)], plan_from_[std::size_t(b)]);
    };
    entries_.clear();
    for (const std::int32_t a : moving_on_list_) {
      const std::size_t i = std::size_t(a);
      swept_boxes_[i] = motion_box(scene.bodies[i].shape, motions_[i], radius_[i]).inflated(skin);
      entries_.push_back({swept_boxes_[i], a, 1});
      broad_phase.query(swept_boxes_[i].inflated(unswept_travel), found_);
      std::sort(found_.begin(), found_.end());
      for (const std::int32_t b : found_) {
        const std::size_t j = std::size_t(b);
        if (b == a || swept_[j] || moved_on_[j] || model.is_removed(j))
          continue;
        if (scene.bodies[j].shape.is_bounded() && !swept_boxes_[i].overlaps(round_box(scene, b)))
          continue;
        add_round_pair(a, b);
      }
    }
    // Swept bodies (their boxes over the whole step hold what is left of their motion) and the
    // bodies moving on, sorted and swept on x, for the pairs with one moving on.
    for (const std::int32_t b : swept_list_) {
      if (!moving_on_[std::size_t(b)])
        entries_.push_back({swept_boxes_[std::size_t(b)], b, 0});
    }
    // Bodies an impact set moving earlier in the step: the box of their last motion.
    for (const std::int32_t b : moved_on_list_) {
      if (!moving_on_[std::size_t(b)] && !swept_[std::size_t(b)])
        entries_.push_back({swept_boxes_[std::size_t(b)], b, 0});
    }
    sort_and_sweep([&](const SweepEntry& e, const SweepEntry& f) {
      // The body moving on first (the lower index when both are).
      if (e.swept && (!f.swept || e.id < f.id))
        add_round_pair(e.id, f.id);
      else
        add_round_pair(f.id, e.id);
    });
    counts.candidate_pairs += static_cast<std::int64_t>(round_pairs_.size());
    tests_.assign(round_pairs_.size(), PairTest{});
    // Each pair's rest of motions, and its earlier answer for the same ones if there is one
    // (tested_pairs_ is only read here; it changes after the loop).
    constexpr std::int32_t kPairsPerChunk = 16;
    runner.for_chunks(static_cast<std::int32_t>(round_pairs_.size()), kPairsPerChunk,
                      [&](std::int32_t begin, std::int32_t end) {
                        for (std::int32_t k = begin; k < end; ++k) {
                          RoundPair& p = round_pairs_[std::size_t(k)];
                          PairTest& t = tests_[std::size_t(k)];
                          p.motion_a = rest_of_motion(std::size_t(p.a), p.from);
                          p.motion_b = rest_of_motion(std::size_t(p.b), p.from);
                          const auto known = reuse_tests_
                                                 ? find_tested(p.a, p.b, tested_pairs_.size())
                                                 : tested_pairs_.end();
                          p.known = known != tested_pairs_.end() &&
                                    same_bits(known->from, p.from) &&
                                    same_motion(known->motion_a, p.motion_a) &&
                                    same_motion(known->motion_b, p.motion_b);
                          if (p.known) {
                            t = known->test;
                            t.queries = 0;  // none run
                            continue;
                          }
                          t.a = p.a;
                          t.b = p.b;
                          test_motions(scene, p.motion_a, p.motion_b, true, t);
                          t.time = p.from + t.time * (1 - p.from);
                        }
                      });
    const std::size_t tested_before = tested_pairs_.size();
    for (std::size_t k = 0; k < round_pairs_.size(); ++k) {
      const RoundPair& p = round_pairs_[k];
      if (p.known)
        continue;
      const TestedPair tested{p.a, p.b, p.from, p.motion_a, p.motion_b, tests_[k]};
      const auto known = find_tested(p.a, p.b, tested_before);
      if (known != tested_pairs_.end())
        *known = tested;
      else
        tested_pairs_.push_back(tested);
    }
    if (tested_pairs_.size() != tested_before) {
      std::sort(tested_pairs_.begin(), tested_pairs_.end(),
                [](const TestedPair& x, const TestedPair& y) {
                  return x.a < y.a || (x.a == y.a && x.b < y.b);
                });
    }
    // Groups of bodies that may meet this round: joined by the pairs tested (immovable bodies
    // join nothing, their motion never changes). In each group only its first hit is taken:
    // what that impact changes may bring any member to an earlier meeting than the group's
    // later hits. Groups apart take their first hits together, unless a motion an earlier hit
    // changed reaches the group's box.
    for (const RoundPair& p : round_pairs_) {
      for (const std::int32_t c : {p.a, p.b}) {
        if (group_of_[std::size_t(c)] < 0) {
          group_of_[std::size_t(c)] = c;
          group_box_[std::size_t(c)] = round_box(scene, c);
          grouped_.push_back(c);
        }
      }
      if (masses[std::size_t(p.a)].inverse_mass > 0 && masses[std::size_t(p.b)].inverse_mass > 0) {
        const std::int32_t ra = group_root(p.a), rb = group_root(p.b);
        if (ra != rb) {
          const std::int32_t low = std::min(ra, rb), high = std::max(ra, rb);
          group_of_[std::size_t(high)] = low;
          group_box_[std::size_t(low)].grow(group_box_[std::size_t(high)]);
        }
      }
    }
    round_order_.clear();
    for (std::size_t k = 0; k < tests_.size(); ++k) {
      counts.toi_queries += tests_[k].queries;
      if (tests_[k].hit)
        round_order_.push_back(static_cast<std::uint32_t>(k));
    }
    std::sort(round_order_.begin(), round_order_.end(), [&](std::uint32_t x, std::uint32_t y) {
      const PairTest& p = tests_[x];
      const PairTest& q = tests_[y];
      return p.time < q.time || (p.time == q.time && (p.a < q.a || (p.a == q.a && p.b < q.b)));
    });
    changed_boxes_.clear();
    for (const std::uint32_t k : round_order_) {
      const PairTest& t = tests_[k];
      const std::size_t a = std::size_t(t.a);
      const std::size_t b = std::size_t(t.b);
      // The group of the movable body (a moving body's pair always has one).
      const std::size_t g = std::size_t(group_root(masses[a].inverse_mass > 0 ? t.a : t.b));
      if (group_hit_[g])
        continue;
      group_hit_[g] = 1;
      bool reached = false;
      for (const Aabb& changed : changed_boxes_)
        reached = reached || changed.overlaps(group_box_[g]);
      if (reached)
        continue;
      hit_this_round_[a] = 1;
      hit_this_round_[b] = 1;
      ++counts.stopped_bodies;
      // Both where they are then (a static body where it stands), and the impact there.
      for (const std::size_t c : {a, b}) {
        if (scene.bodies[c].is_static)
          continue;
        const Transform at = rest_of_motion(c, t.time).start();
        bodies[c].position = at.translation;
        bodies[c].orientation = at.rotation;
      }
      const bool pushed = resolve_impact(model, a, b, t.normal, bodies, masses);
      for (const std::size_t c : {a, b}) {
        if (scene.bodies[c].is_static)
          continue;
        const Real rest = (1 - t.time) * dt;
        changed_boxes_.push_back(
            motion_box(
                scene.bodies[c].shape,
                RigidMotion::from_velocity(Transform{bodies[c].position, bodies[c].orientation},
                                           bodies[c].velocity * (pushed ? rest : 0),
                                           bodies[c].angular_velocity * (pushed ? rest : 0)),
                radius_[c])
                .inflated(skin));
        if (pushed && masses[c].inverse_mass > 0) {
          moving_on_[c] = 1;
          move_time_[c] = t.time;
          next_moving_on_.push_back(static_cast<std::int32_t>(c));
        } else {
          motions_[c] =
              RigidMotion::stationary(Transform{bodies[c].position, bodies[c].orientation});
          plan_from_[c] = t.time;
          moving_on_[c] = 0;
        }
      }
    }
    // A body moving on whose group met nothing ends the step where its motion ends; the others
    // are tested again next round, against what this round's impacts changed.
    for (const std::int32_t a : moving_on_list_) {
      const std::size_t i = std::size_t(a);
      if (hit_this_round_[i])
        continue;
      if (group_of_[i] >= 0 && group_hit_[std::size_t(group_root(a))]) {
        next_moving_on_.push_back(a);
        continue;
      }
      moving_on_[i] = 0;
      const Transform end = motions_[i].end();
      bodies[i].position = end.translation;
      bodies[i].orientation = end.rotation;
    }
    for (const std::int32_t c : grouped_) {
      group_of_[std::size_t(c)] = -1;
      group_hit_[std::size_t(c)] = 0;
      hit_this_round_[std::size_t(c)] = 0;
    }
    grouped_.clear();
    std::sort(next_moving_on_.begin(), next_moving_on_.end());
    next_moving_on_.erase(std::unique(next_moving_on_.begin(), next_moving_on_.end()),
                          next_moving_on_.end());
    // A body that waited keeps its motion: moving on from its start with the same velocity
    // makes the same one.
    for (const std::int32_t c : next_moving_on_)
      move_on(std::size_t(c), bodies, dt);
  }
  // Bodies still in a chain of impacts after the last round stay where it left them.
  for (const std::int32_t c : next_moving_on_) {
    moving_on_[std::size_t(c)] = 0;
    motions_[std::size_t(c)] = RigidMotion::stationary(
        Transform{bodies[std::size_t(c)].position, bodies[std::size_t(c)].orientation});
  }
  next_moving_on_.clear();
}

// A pair apart at the start of the step is stopped a little before contact, within the next
// step's contact margin. A pair already touching (within the margin) is left to the discrete
// contacts unless it would sink deeper than half the thinner body's thickness, which only a body
// passing through does; one already deeper than that may sink by 2% of that thickness more per
// step (the solver pushes it out meanwhile), so it cannot creep through.
void ContinuousCollision::add_pair(std::int32_t ia, std::int32_t ib,
                                   ContinuousCollisionCounts& counts) {
  ++counts.candidate_pairs;
  PairTest t;
  t.a = ia;
  t.b = ib;
  tests_.push_back(t);
}

void ContinuousCollision::test_pair(const Scene& scene, PairTest& test) const {
  test_motions(scene, motions_[std::size_t(test.a)], motions_[std::size_t(test.b)], false, test);
}

void ContinuousCollision::test_motions(const Scene& scene, const RigidMotion& ma,
                                       const RigidMotion& mb, bool closing_is_an_impact,
                                       PairTest& test) const {
  const std::int32_t ia = test.a;
  const std::int32_t ib = test.b;
  const Real skin = std::max(scene.world.contact_margin, Real(1e-6));
  ToiSettings apart;
  apart.target_distance = Real(0.25) * skin;
  apart.tolerance = Real(0.25) * skin;
  apart.max_iterations = 32;
  const BodyDesc& a = scene.bodies[std::size_t(ia)];
  const BodyDesc& b = scene.bodies[std::size_t(ib)];
  test.queries = 1;
  ToiResult r = time_of_impact(a.shape, ma, b.shape, mb, apart);
  if (r.status == ToiStatus::overlapping && closing_is_an_impact &&
      (ma.linear_velocity() - mb.linear_velocity()).dot(r.normal) < 0) {
    // In a round after an impact nothing else will stop a pair that starts in touch and closes
    // (the contacts come only with the next step): the impact is now.
    test.hit = true;
    test.time = 0;
    test.normal = r.normal;
    return;
  }
  if (r.status == ToiStatus::overlapping) {
    // Planes and meshes (static only) have no thickness: the body against one sets the depth.
    // (A mesh counted as thickness 0 once made a body resting on it be stopped step after step
    // a hair above it, where conservative advancement crawls towards a target of zero gap.)
    const Real ta =
        thickness_[std::size_t(ia)] > 0 ? thickness_[std::size_t(ia)] : thickness_[std::size_t(ib)];
    const Real tb =
        thickness_[std::size_t(ib)] > 0 ? thickness_[std::size_t(ib)] : thickness_[std::size_t(ia)];
    const Real thinner = std::min(ta, tb);
    ToiSettings touching = apart;
    touching.target_distance = std::min(r.distance - Real(0.02) * thinner, Real(-0.5) * thinner);
    touching.tolerance = Real(0.01) * thinner;
    // The distance at the start is the one just measured: where the pair cannot close from it
    // to the target within the step even at the fastest closing speed the advancement assumes,
    // the second search would end at its first query. Most touching pairs are resting ones.
    // The bodies' bounding radii, kept per body (radius_ holds 0 for an unbounded shape, whose
    // bounding radius is infinite).
    const auto radius_of = [&](std::int32_t i, const Shape& shape) {
      return shape.is_bounded() ? radius_[std::size_t(i)] : std::numeric_limits<Real>::infinity();
    };
    if (greatest_closing_speed(ma, radius_of(ia, a.shape), mb, radius_of(ib, b.shape)) <
        r.distance - touching.target_distance)
      return;
    test.queries = 2;
    r = time_of_impact(a.shape, ma, b.shape, mb, touching);
    if (r.status == ToiStatus::overlapping)
      return;  // cannot happen but for rounding: the target is below the start
  }
  // A capped search still gives a time up to which the motion is safe.
  if (r.status != ToiStatus::hit && r.status != ToiStatus::max_iterations)
    return;
  // The normal runs from B to A, and is known only for a hit (not at the iteration cap).
  test.hit = true;
  test.time = r.time_of_impact;
  test.normal = r.status == ToiStatus::hit ? r.normal : Vec3::Zero();
}

}  // namespace tumble
