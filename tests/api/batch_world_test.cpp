// BatchWorld: world i is bit-identical to a lone World given the same actions, on any thread
// count; a reset world replays exactly; the arrays hold what the worlds hold.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "collision/cache_prefetch.hpp"
#include "engine/simulation.hpp"
#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

using testing::box_at;
using testing::ground;
using testing::scene_of;

std::shared_ptr<Scene> pile() {
  std::vector<BodyDesc> bodies{ground()};
  for (int k = 0; k < 6; ++k) {
    std::string name = "b";
    name += std::to_string(k);
    bodies.push_back(box_at(name, Vec3(0.3 * (k % 2), 0.2 * k, 1 + 1.1 * k), 0.4));
  }
  return scene_of(bodies);
}

// The force on body b of world w at step s: a fixed, per-world pseudo-random push.
Vec3 push(int w, int b, int s) {
  std::mt19937 random(std::uint32_t(1000003 * w + 1009 * b + s));
  std::uniform_real_distribution<Real> u(-40, 40);
  return Vec3(u(random), u(random), u(random));
}

// Twenty boxes resting on the ground, apart: a world of twenty touching pairs, like an RL
// environment's.
std::shared_ptr<Scene> boxes_on_ground() {
  std::vector<BodyDesc> bodies{ground()};
  for (int k = 0; k < 20; ++k) {
    std::string name = "b";
    name += std::to_string(k);
    bodies.push_back(box_at(name, Vec3(0.9 * (k % 5), 0.9 * (k / 5), 0.2), 0.2));
  }
  return scene_of(bodies);
}

std::vector<std::uint64_t> batch_hashes(int threads, int worlds, int steps) {
  BatchWorld batch(pile(), worlds, threads);
  for (int s = 0; s < steps; ++s) {
    testing::write_batch_forces(batch, [s](int w, int b) { return push(w, b, s); });
    batch.step();
  }
  std::vector<std::uint64_t> hashes;
  for (int w = 0; w < worlds; ++w)
    hashes.push_back(batch.state_hash(w));
  return hashes;
}

// The state hash of a lone World of `scene` given world w's pushes for `steps` steps.
std::uint64_t lone_world_hash(const std::shared_ptr<Scene>& scene, int w, int steps) {
  World lone(scene);
  for (int s = 0; s < steps; ++s) {
    for (const BodyId id : lone.bodies())
      if (id.index > 0)
        lone.add_force(id, push(w, id.index, s));
    lone.step();
  }
  return lone.state_hash();
}

TEST(BatchWorld, EachWorldIsALoneWorldOnAnyThreadCount) {
  // Enough worlds that two threads' ranges hold several each: a range steps its worlds in order
  // (BatchWorld::Impl::step_range).
  const int worlds = 24, steps = 40;
  const std::vector<std::uint64_t> one = batch_hashes(1, worlds, steps);
  EXPECT_EQ(one, batch_hashes(2, worlds, steps));
  EXPECT_EQ(one, batch_hashes(4, worlds, steps));
  for (int w = 0; w < worlds; w += 3)
    EXPECT_EQ(lone_world_hash(pile(), w, steps), one[std::size_t(w)]) << "world " << w;
  // The worlds were pushed differently, so they differ.
  EXPECT_NE(one[0], one[1]);
}

// A batch too large to stay in the cache asks for each next world while the one before steps
// (BatchWorld::Impl::worlds_leave_the_cache): every world is still its lone world, on one thread
// and on two (where each thread records the lines of worlds of its own ranges only).
TEST(BatchWorld, ABatchThatAsksAheadKeepsEveryWorldALoneWorld) {
  const int steps = 4;
  // Enough worlds that two threads' shares pass the cached bytes a thread, measured on a world
  // that has stepped once (its contact lists have grown), with room to spare.
  BatchWorld probe(boxes_on_ground(), 1, 1);
  probe.step();
  const WorldMemory m = probe.world(0).simulation().memory();
  const std::size_t per_world = m.body_bytes + m.contact_bytes;
  const int worlds = int(3 * CachePrefetch::kWorldBytesCachedPerThread / per_world);
  std::vector<std::uint64_t> one;
  for (const int threads : {1, 2}) {
    BatchWorld batch(boxes_on_ground(), worlds, threads);
    std::int64_t asked = 0;  // from the second step, when the worlds' lists have grown
    for (int s = 0; s < steps; ++s) {
      testing::write_batch_forces(batch, [s](int w, int b) { return push(w, b, s); });
      batch.step();
      for (int w = 0; s > 0 && w < worlds; ++w)
        asked += batch.world(w).simulation().last_step_statistics().lines_asked_ahead;
    }
    // Most worlds ask for the next one's lines (all but the last of each range).
    EXPECT_GT(asked, std::int64_t(worlds)) << threads << " threads";
    std::vector<std::uint64_t> hashes;
    for (int w = 0; w < worlds; ++w)
      hashes.push_back(batch.state_hash(w));
    if (threads == 1)
      one = hashes;
    else
      EXPECT_EQ(one, hashes);
  }
  for (int w = 0; w < worlds; w += worlds / 5)
    EXPECT_EQ(lone_world_hash(boxes_on_ground(), w, steps), one[std::size_t(w)]) << "world " << w;
  EXPECT_NE(one[0], one[1]);
}

// Loads on a few bodies of some worlds, none on others, changing from step to step (the step
// reads again only the rows its check found loaded): every world is still its lone world.
TEST(BatchWorld, SparseLoadsActOnTheirBodiesAlone) {
  const int worlds = 5, steps = 30;
  // Body b of world w is loaded at step s for about one (w, b, s) in four; a torque on another.
  const auto loaded = [](int w, int b, int s) { return (3 * w + 5 * b + 7 * s) % 4 == 0; };
  const auto turned = [](int w, int b, int s) { return (w + 2 * b + s) % 5 == 0; };
  BatchWorld batch(pile(), worlds, 2);
  const int bodies = batch.body_count();
  for (int s = 0; s < steps; ++s) {
    testing::write_batch_forces(
        batch, [&](int w, int b) { return loaded(w, b, s) ? push(w, b, s) : Vec3::Zero(); });
    std::span<Real> t = batch.torques();
    for (int w = 0; w < worlds; ++w)
      for (int b = 1; b < bodies; ++b)
        t[std::size_t((w * bodies + b) * 3 + 2)] = turned(w, b, s) ? Real(3) : Real(0);
    batch.step();
  }
  for (int w = 0; w < worlds; ++w) {
    World lone(pile());
    for (int s = 0; s < steps; ++s) {
      for (const BodyId id : lone.bodies()) {
        if (id.index == 0)
          continue;
        if (loaded(w, id.index, s))
          lone.add_force(id, push(w, id.index, s));
        if (turned(w, id.index, s))
          lone.add_torque(id, Vec3(0, 0, 3));
      }
      lone.step();
    }
    EXPECT_EQ(lone.state_hash(), batch.state_hash(w)) << "world " << w;
  }
}

TEST(BatchWorld, AResetWorldReplaysExactly) {
  BatchWorld batch(pile(), 3, 2);
  std::span<Real> f = batch.forces();
  f[3 * (0 * batch.body_count() + 2)] = 25;  // world 0, body 2, along x
  batch.step(30);
  const std::uint64_t first = batch.state_hash(0);
  const std::uint64_t untouched = batch.state_hash(2);
  const int again[] = {0};
  batch.reset(again);
  EXPECT_EQ(batch.world(0).step_count(), 0);
  EXPECT_EQ(batch.state_hash(0), World(pile()).state_hash());
  batch.step(30);
  EXPECT_EQ(batch.state_hash(0), first);
  EXPECT_NE(batch.state_hash(2), untouched) << "world 2 kept stepping";
}

TEST(BatchWorld, ObservationsAndContactForcesMatchTheWorlds) {
  auto scene = scene_of({ground(), box_at("a", Vec3(0, 0, 1.0)), box_at("b", Vec3(3, 0, 1.0))});
  BatchWorld batch(scene, 2, 2);
  batch.step(90);
  const int bodies = batch.body_count();
  const std::span<const Real> obs = batch.observations();
  for (int w = 0; w < 2; ++w) {
    for (int b = 0; b < bodies; ++b) {
      const BodyState s = batch.world(w).body_state(BodyId{b, 0});
      const Real* o = obs.data() + (w * bodies + b) * BatchWorld::kObservationWidth;
      EXPECT_EQ(o[0], s.position.x());
      EXPECT_EQ(o[2], s.position.z());
      EXPECT_EQ(o[3], s.orientation.w());
      EXPECT_EQ(o[6], s.orientation.z());
      EXPECT_EQ(o[9], s.velocity.z());
      EXPECT_EQ(o[12], s.angular_velocity.z());
    }
    // Each resting box is held up by its weight; the ground carries both.
    const Real weight = scene->bodies[1].mass * 9.81;
    const std::span<const Real> cf = batch.contact_forces();
    for (int b = 1; b < bodies; ++b) {
      EXPECT_NEAR(cf[std::size_t((w * bodies + b) * 3 + 2)] / weight, 1.0, 1e-6);
      EXPECT_EQ(batch.contact_counts()[std::size_t(w * bodies + b)], 1);
    }
    EXPECT_NEAR(cf[std::size_t((w * bodies) * 3 + 2)] / weight, -2.0, 1e-6);
    EXPECT_EQ(batch.contact_counts()[std::size_t(w * bodies)], 2);
  }
}

TEST(BatchWorld, KinematicTargetsAreReached) {
  BodyDesc paddle = kinematic_body("paddle", Shape::box(Vec3(0.1, 0.5, 0.3)));
  paddle.position = Vec3(0, 0, 1);
  BatchWorld batch(scene_of({ground(), paddle}), 3, 2);
  const int bodies = batch.body_count();
  for (int w = 0; w < 3; ++w) {
    Real* t = batch.kinematic_targets().data() + (w * bodies + 1) * BatchWorld::kTargetWidth;
    t[0] = 0.1 * (w + 1);
    t[2] = 1;
    t[3] = 1;
    batch.kinematic_target_set()[std::size_t(w * bodies + 1)] = 1;
  }
  batch.step();
  for (int w = 0; w < 3; ++w) {
    EXPECT_EQ(batch.observations()[std::size_t((w * bodies + 1) * 13)], 0.1 * (w + 1));
    EXPECT_EQ(batch.kinematic_target_set()[std::size_t(w * bodies + 1)], 0);
  }
}

TEST(BatchWorld, RefusesATurnALoneWorldRefuses) {
  BodyDesc paddle = kinematic_body("paddle", Shape::box(Vec3(0.1, 0.5, 0.3)));
  auto scene = scene_of({ground(), paddle});
  scene->world.dt = 1e-6;  // half a turn in one step: 3.1e6 rad/s
  BatchWorld batch(scene, 1, 1);
  Real* t = batch.kinematic_targets().data() + BatchWorld::kTargetWidth;
  t[6] = 1;  // w x y z = 0 0 0 1
  batch.kinematic_target_set()[1] = 1;
  EXPECT_THROW(batch.step(), Error);
  World lone(scene);
  EXPECT_THROW(lone.set_kinematic_target(lone.body("paddle"), Vec3::Zero(), Quat(0, 0, 0, 1)),
               Error);
}

TEST(BatchWorld, BadActionsStepNothingAndNameWorldAndBody) {
  BatchWorld batch(pile(), 4, 2);
  const int bodies = batch.body_count();
  const auto message = [&] {
    try {
      batch.step();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  batch.forces()[std::size_t((2 * bodies + 3) * 3 + 1)] = std::numeric_limits<Real>::quiet_NaN();
  std::string m = message();
  EXPECT_NE(m.find("world 2, body 3 'b2'"), std::string::npos) << m;
  EXPECT_NE(m.find("nan"), std::string::npos) << m;
  EXPECT_EQ(batch.world(0).step_count(), 0) << "a world stepped";
  batch.forces()[std::size_t((2 * bodies + 3) * 3 + 1)] = 0;
  batch.torques()[std::size_t((1 * bodies + 0) * 3)] = 5;  // the ground is static
  m = message();
  EXPECT_NE(m.find("world 1, body 0 'ground'"), std::string::npos) << m;
  batch.torques()[std::size_t((1 * bodies + 0) * 3)] = 0;
  batch.kinematic_target_set()[1] = 1;
  EXPECT_NE(message().find("not kinematic"), std::string::npos);
  batch.kinematic_target_set()[1] = 0;
  const int out_of_range[] = {4};
  EXPECT_THROW(batch.reset(out_of_range), Error);
  EXPECT_THROW(batch.world(-1), Error);
  EXPECT_THROW(BatchWorld(pile(), 0), Error);
  batch.step();
  EXPECT_EQ(batch.world(3).step_count(), 1);
}

}  // namespace
}  // namespace tumble
