// The continuous-collision stage tests only the pairs whose motion boxes overlap
// (engine/continuous_collision.hpp): swept bodies query the broad phase for static and unswept
// bodies and are sorted and swept against each other. These tests check that the pruning never
// drops an impact, against brute force and in whole worlds:
//   - random sets of bodies (spheres, boxes, capsules, cylinders; fast, slow, spinning, static
//     walls and a plane) with random end poses: the stage with pruning leaves every body at
//     exactly the pose (bit for bit) that testing every pair with a swept body gives, for every
//     broad phase and for broad-phase boxes grown by any margin;
//   - two centimetre spheres flying at each other at 500 m/s each (both swept: only the
//     swept-against-swept sort finds them) never pass through each other;
//   - a centimetre sphere at 1000 m/s against a 1 cm plate that is itself dynamic and drifting
//     (unswept: found through the broad phase) never passes it;
//   - taking a pair's earlier answer again in a round after an impact, when both its motions are
//     the same to the bit, leaves every pose as testing the pair again does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "collision/broad_phase/broad_phase_factory.hpp"
#include "collision/ccd/rigid_motion.hpp"
#include "engine/continuous_collision.hpp"
#include "engine/simulation.hpp"
#include "tests/property_scale.hpp"

namespace tumble::test {
namespace {

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<Real> n(0, 1);
  for (;;) {
    const Vec3 v(n(rng), n(rng), n(rng));
    if (v.norm() > 1e-3)
      return v.normalized();
  }
}

// Where a body starting at its description's pose ends a step that moves it by `move` and turns
// it by the rotation vector `turn`, with the velocities that carry it there.
BodyState moved(const BodyDesc& b, const Vec3& move, const Vec3& turn, Real dt) {
  BodyState e;
  e.position = b.position + move;
  e.orientation = (quaternion_from_rotation_vector(turn) * b.orientation).normalized();
  e.velocity = move / dt;
  e.angular_velocity = turn / dt;
  return e;
}

Shape random_small_shape(std::mt19937_64& rng) {
  std::uniform_real_distribution<Real> size(0.03, 0.25);
  switch (rng() % 4) {
    case 0:
      return Shape::sphere(size(rng));
    case 1:
      return Shape::box(Vec3(size(rng), size(rng), size(rng)));
    case 2:
      return Shape::capsule(size(rng) * 0.5, size(rng));
    default:
      return Shape::cylinder(size(rng) * 0.5, size(rng));
  }
}

struct RandomCase {
  Scene scene;
  std::vector<Transform> start;
  std::vector<BodyState> end;
};

// 14 dynamic bodies in a 3 m cube with two static walls and a floor plane. A third move far
// (0.5 to 4 m in the step, some spinning at up to 200 rad/s), a third little, a third not at
// all; some carry `fast: true`.
RandomCase make_case(std::mt19937_64& rng, CcdMode mode) {
  std::uniform_real_distribution<Real> unit(0, 1);
  RandomCase c;
  Scene& s = c.scene;
  s.source = "ccd_candidates_test";
  s.world.ccd = mode;
  s.materials.push_back(Material{"default", 0.5, 0.0});
  BodyDesc wall;
  wall.is_static = true;
  wall.shape = Shape::box(Vec3(0.01, 1.5, 1.5));
  wall.position = Vec3(0.6 * unit(rng) - 0.3, 0, 0);
  s.bodies.push_back(wall);
  wall.shape = Shape::box(Vec3(1.5, 0.02, 1.5));
  wall.position = Vec3(0, 1.5 * unit(rng) - 0.75, 0);
  s.bodies.push_back(wall);
  BodyDesc floor;
  floor.is_static = true;
  floor.shape = Shape::plane();
  floor.position = Vec3(0, 0, -1.5);
  s.bodies.push_back(floor);
  for (int i = 0; i < 14; ++i) {
    BodyDesc b;
    b.shape = random_small_shape(rng);
    b.mass = 1;
    b.inertia = Mat3::Identity();
    b.fast = unit(rng) < 0.15;
    b.position = Vec3(3 * unit(rng) - 1.5, 3 * unit(rng) - 1.5, 3 * unit(rng) - 1.5);
    std::normal_distribution<Real> n(0, 1);
    b.orientation = Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
    s.bodies.push_back(b);
  }
  const Real dt = s.world.dt;
  for (const BodyDesc& b : s.bodies) {
    c.start.push_back({b.position, b.orientation});
    BodyState e;
    e.position = b.position;
    e.orientation = b.orientation;
    if (!b.is_static) {
      const Real kind = unit(rng);
      Vec3 move = Vec3::Zero();
      Vec3 turn = Vec3::Zero();
      if (kind < 0.35) {
        move = random_unit(rng) * (0.5 + 3.5 * unit(rng));
        if (unit(rng) < 0.5)
          turn = random_unit(rng) * (200 * dt * unit(rng));
      } else if (kind < 0.7) {
        move = random_unit(rng) * (0.02 * unit(rng));
        turn = random_unit(rng) * (0.1 * unit(rng));
      }
      e = moved(b, move, turn, dt);
    }
    c.end.push_back(e);
  }
  return c;
}

// The stage's result with pruning and with every pair, on a broad phase of `type` whose boxes
// are the start poses' boxes grown by random margins (as the bounds stage grows them, by at
// least half the contact margin).
void expect_pruning_changes_nothing(const RandomCase& c, BroadPhaseType type, std::mt19937_64& rng,
                                    std::int64_t& queried_pairs, std::int64_t& sorted_pairs,
                                    std::int64_t& all_pairs, std::int64_t& stops) {
  std::uniform_real_distribution<Real> unit(0, 1);
  auto broad_phase = make_broad_phase(type);
  for (std::size_t i = 0; i < c.scene.bodies.size(); ++i) {
    const BodyDesc& d = c.scene.bodies[i];
    const Real margin = 0.5 * c.scene.world.contact_margin + (d.is_static ? 0 : 0.1 * unit(rng));
    broad_phase->insert(static_cast<std::int32_t>(i),
                        world_aabb(d.shape, c.start[i]).inflated(margin), d.is_static);
  }
  std::vector<ProxyPair> pairs;
  broad_phase->find_pairs(pairs);  // some structures settle their boxes here

  std::vector<BodyMass> masses;
  for (const BodyDesc& d : c.scene.bodies)
    masses.push_back(BodyMass::make(d.mass, d.inertia, d.is_static));
  // The unpruned search on one thread, the pruned ones on two: the same stops either way.
  const ParallelRunner one_thread(1);
  const ParallelRunner two_threads(2);
  const std::shared_ptr<const Model> model = Model::build(std::make_shared<const Scene>(c.scene));
  ContinuousCollision every(c.scene);
  every.set_pair_search(ContinuousCollision::PairSearch::every_pair);
  std::vector<BodyState> with_every_pair = c.end;
  const ContinuousCollisionCounts b =
      every.run(*model, c.start, *broad_phase, with_every_pair, masses, one_thread);
  all_pairs += b.candidate_pairs;
  stops += b.stopped_bodies;

  for (const auto search :
       {ContinuousCollision::PairSearch::broad_phase, ContinuousCollision::PairSearch::sort_all}) {
    ContinuousCollision pruned(c.scene);
    pruned.set_pair_search(search);
    std::vector<BodyState> with_pruning = c.end;
    const ContinuousCollisionCounts a =
        pruned.run(*model, c.start, *broad_phase, with_pruning, masses, two_threads);
    const char* name =
        search == ContinuousCollision::PairSearch::sort_all ? "sort_all" : "broad_phase";
    EXPECT_EQ(a.swept_bodies, b.swept_bodies) << name;
    EXPECT_EQ(a.stopped_bodies, b.stopped_bodies) << name;
    for (std::size_t i = 0; i < c.end.size(); ++i) {
      EXPECT_TRUE(with_pruning[i].position == with_every_pair[i].position &&
                  with_pruning[i].orientation.coeffs() == with_every_pair[i].orientation.coeffs())
          << name << ": body " << i << " pruned " << with_pruning[i].position.transpose()
          << " every pair " << with_every_pair[i].position.transpose();
    }
    (search == ContinuousCollision::PairSearch::sort_all ? sorted_pairs : queried_pairs) +=
        a.candidate_pairs;
  }
}

TEST(CcdCandidates, PruningByMotionBoxesGivesTheSamePosesAsTestingEveryPair) {
  std::mt19937_64 rng(2611);
  const int cases = scaled(1500);
  const BroadPhaseType types[] = {BroadPhaseType::kdtree, BroadPhaseType::bvh, BroadPhaseType::sap,
                                  BroadPhaseType::brute};
  std::int64_t queried = 0;
  std::int64_t sorted = 0;
  std::int64_t all = 0;
  std::int64_t stops = 0;
  for (int k = 0; k < cases; ++k) {
    const CcdMode mode = k % 3 == 0 ? CcdMode::on : CcdMode::automatic;
    const RandomCase c = make_case(rng, mode);
    expect_pruning_changes_nothing(c, types[k % 4], rng, queried, sorted, all, stops);
    if (HasFailure())
      return;
  }
  std::printf(
      "%d random cases: pairs tested %lld through the broad phase, %lld sorting all, %lld "
      "without pruning; %lld stops\n",
      cases, static_cast<long long>(queried), static_cast<long long>(sorted),
      static_cast<long long>(all), static_cast<long long>(stops));
  EXPECT_GT(stops, cases / 4);  // the cases do hit things
  EXPECT_LT(queried, all);      // and both searches prune
  EXPECT_LT(sorted, all);
}

// A round after an impact takes a pair's earlier answer again when both motions are the same to
// the bit (a body waiting while its group's first hit is resolved keeps its motion). Random
// cases, and clusters of fast bodies started overlapping one another (where a body waits round
// after round), leave every body at exactly the pose that testing every pair again gives, with
// fewer queries.
void expect_reuse_changes_nothing(const Scene& scene, const std::vector<Transform>& start,
                                  const std::vector<BodyState>& end, std::int64_t& queries_reused,
                                  std::int64_t& queries_all, std::int64_t& rounds) {
  auto broad_phase = make_broad_phase(BroadPhaseType::bvh);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDesc& d = scene.bodies[i];
    broad_phase->insert(static_cast<std::int32_t>(i),
                        world_aabb(d.shape, start[i]).inflated(scene.world.contact_margin),
                        d.is_static);
  }
  std::vector<ProxyPair> pairs;
  broad_phase->find_pairs(pairs);
  std::vector<BodyMass> masses;
  for (const BodyDesc& d : scene.bodies)
    masses.push_back(BodyMass::make(d.mass, d.inertia, d.is_static));
  const ParallelRunner two_threads(2);
  const std::shared_ptr<const Model> model = Model::build(std::make_shared<const Scene>(scene));
  ContinuousCollision again(scene);
  again.set_reuse_tests(false);
  std::vector<BodyState> tested_again = end;
  const ContinuousCollisionCounts b =
      again.run(*model, start, *broad_phase, tested_again, masses, two_threads);
  ContinuousCollision reusing(scene);
  std::vector<BodyState> reused = end;
  const ContinuousCollisionCounts a =
      reusing.run(*model, start, *broad_phase, reused, masses, two_threads);
  EXPECT_EQ(a.stopped_bodies, b.stopped_bodies);
  EXPECT_EQ(a.impact_rounds, b.impact_rounds);
  EXPECT_LE(a.toi_queries, b.toi_queries);
  for (std::size_t i = 0; i < end.size(); ++i) {
    EXPECT_TRUE(reused[i].position == tested_again[i].position &&
                reused[i].orientation.coeffs() == tested_again[i].orientation.coeffs() &&
                reused[i].velocity == tested_again[i].velocity)
        << "body " << i << " reusing " << reused[i].position.transpose() << " testing again "
        << tested_again[i].position.transpose();
  }
  queries_reused += a.toi_queries;
  queries_all += b.toi_queries;
  rounds += b.impact_rounds;
}

// Four to eight fast bodies (spheres, boxes, capsules) started within a few centimetres of one
// point, so that each overlaps the others, flying and spinning apart or together.
RandomCase overlapping_cluster(std::mt19937_64& rng) {
  std::uniform_real_distribution<Real> unit(0, 1);
  RandomCase c;
  Scene& s = c.scene;
  s.source = "ccd_candidates_test";
  s.world.ccd = CcdMode::on;
  s.materials.push_back(Material{"default", 0.5, 0.0});
  const int count = 4 + static_cast<int>(rng() % 5);
  const Real dt = s.world.dt;
  for (int i = 0; i < count; ++i) {
    BodyDesc b;
    b.shape = random_small_shape(rng);
    b.mass = 0.1 + unit(rng);
    b.inertia = b.mass * unit_inertia(b.shape);
    b.fast = true;
    b.position = random_unit(rng) * (0.05 * unit(rng));
    std::normal_distribution<Real> n(0, 1);
    b.orientation = Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
    s.bodies.push_back(b);
    c.start.push_back({b.position, b.orientation});
    const Vec3 move = random_unit(rng) * (2 * unit(rng));
    const Vec3 turn = random_unit(rng) * (100 * dt * unit(rng));
    c.end.push_back(moved(b, move, turn, dt));
  }
  return c;
}

TEST(CcdCandidates, ReusingATestForTheSameMotionsGivesTheSamePoses) {
  std::mt19937_64 rng(4409);
  const int cases = scaled(1000);
  std::int64_t reused = 0, all = 0, rounds = 0;
  for (int k = 0; k < cases; ++k) {
    const RandomCase c = k % 2 == 0 ? make_case(rng, CcdMode::on) : overlapping_cluster(rng);
    expect_reuse_changes_nothing(c.scene, c.start, c.end, reused, all, rounds);
    if (HasFailure())
      return;
  }
  std::printf("%d cases, %lld rounds after impacts: %lld queries reusing answers, %lld without\n",
              cases, static_cast<long long>(rounds), static_cast<long long>(reused),
              static_cast<long long>(all));
  EXPECT_GT(rounds, cases);  // the cases do chain impacts
  EXPECT_LT(reused, all);    // and some answers are taken again
}

BodyDesc centimetre_sphere(const Vec3& position, const Vec3& velocity) {
  BodyDesc b;
  b.shape = Shape::sphere(0.005);
  b.position = position;
  b.velocity = velocity;
  b.mass = 0.01;
  b.inertia = b.mass * unit_inertia(b.shape);
  return b;
}

Scene empty_scene() {
  Scene s;
  s.source = "ccd_candidates_test";
  s.world.gravity = Vec3::Zero();
  s.materials.push_back(Material{"default", 0.5, 0.0});
  return s;
}

// Two 1 cm spheres fly at each other at 500 m/s each, their lines at most 7 mm apart, so they
// must meet. Through: within one step, the straight segment of their relative motion comes
// closer than 8 mm between the centres (2 mm deep for spheres of 5 mm radius; contacts stay
// within the solver's slop of touching, and after an impact the relative motion is tangent).
TEST(CcdCandidates, TwoFastSpheresHeadOnNeverPassThroughEachOther) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<Real> unit(0, 1);
  const int cases = scaled(500);
  int through = 0;
  for (int k = 0; k < cases; ++k) {
    const Vec3 dir = random_unit(rng);
    const Vec3 side = dir.unitOrthogonal();
    const Real gap = 0.5 + 20 * unit(rng);
    Scene s = empty_scene();
    s.bodies.push_back(centimetre_sphere(-dir * gap, 500 * dir));
    s.bodies.push_back(centimetre_sphere(dir * gap + side * (0.007 * unit(rng)), -500 * dir));
    Simulation world(std::make_shared<const Scene>(std::move(s)));
    const int steps = 3 + static_cast<int>(std::ceil(gap / 500 / world.scene().world.dt));
    for (int i = 0; i < steps; ++i) {
      const Vec3 r0 = world.state().bodies[1].position - world.state().bodies[0].position;
      world.step();
      const Vec3 r1 = world.state().bodies[1].position - world.state().bodies[0].position;
      const Vec3 d = r1 - r0;
      const Real t = d.squaredNorm() > 0 ? std::clamp(-r0.dot(d) / d.squaredNorm(), 0.0, 1.0) : 0;
      if ((r0 + t * d).norm() < 0.008) {
        ++through;
        ADD_FAILURE() << "case " << k << ": the spheres passed through each other in step " << i;
        break;
      }
    }
  }
  std::printf("two spheres at 500 m/s head on: %d of %d through\n", through, cases);
  EXPECT_EQ(through, 0);
}

// A 1 cm sphere at 1000 m/s toward a dynamic plate 1 cm thick that drifts slowly (unswept: its
// box sits in the broad phase, grown by its own small motion).
TEST(CcdCandidates, FastSphereNeverCrossesADriftingDynamicPlate) {
  std::mt19937_64 rng(91);
  std::uniform_real_distribution<Real> unit(0, 1);
  const int cases = scaled(500);
  int through = 0;
  for (int k = 0; k < cases; ++k) {
    Vec3 dir = random_unit(rng);
    dir.x() = std::abs(dir.x()) + 0.3;
    dir.normalize();
    const Real distance = 0.05 + 20 * unit(rng);
    const Vec3 hit(0, 1.6 * unit(rng) - 0.8, 1.6 * unit(rng) - 0.8);
    Scene s = empty_scene();
    s.bodies.push_back(centimetre_sphere(hit - dir * (distance / dir.x()), 1000 * dir));
    BodyDesc plate;
    plate.shape = Shape::box(Vec3(0.005, 1, 1));
    plate.velocity = random_unit(rng) * 0.1;
    plate.mass = 1000;  // heavy: the sphere barely moves it
    plate.inertia = plate.mass * unit_inertia(plate.shape);
    s.bodies.push_back(plate);
    Simulation world(std::make_shared<const Scene>(std::move(s)));
    const int steps =
        3 + static_cast<int>(std::ceil(distance / dir.x() / 1000 / world.scene().world.dt));
    for (int i = 0; i < steps; ++i) {
      const Vec3 before = world.state().bodies[0].position - world.state().bodies[1].position;
      world.step();
      const Vec3 after = world.state().bodies[0].position - world.state().bodies[1].position;
      // In the plate's frame (it does not turn here: no torque reaches it but the impact's).
      if (before.x() <= 0 && after.x() > 0) {
        const Vec3 crossing = before + (after - before) * (-before.x() / (after.x() - before.x()));
        if (std::abs(crossing.y()) <= 1 && std::abs(crossing.z()) <= 1) {
          ++through;
          ADD_FAILURE() << "case " << k << ": the sphere crossed the plate in step " << i;
          break;
        }
      }
    }
  }
  std::printf("sphere at 1000 m/s vs drifting dynamic 1 cm plate: %d of %d through\n", through,
              cases);
  EXPECT_EQ(through, 0);
}

}  // namespace
}  // namespace tumble::test
