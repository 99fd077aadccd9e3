// Domain randomization (tumble/randomization.hpp): draws are reproducible per seed, have the
// documented distributions over thousands of seeds, keep each body's density and its compound
// parts in place, and a batch world is the lone world of its draw bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <set>

#include "collision/shapes/compound_shape.hpp"
#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

using testing::box_at;
using testing::ground;
using testing::scene_of;

struct Moments {
  Real mean = 0, deviation = 0, largest = 0;
};

Moments moments(const std::vector<Real>& v) {
  Moments m;
  m.mean = std::accumulate(v.begin(), v.end(), Real(0)) / Real(v.size());
  for (const Real x : v) {
    m.deviation += (x - m.mean) * (x - m.mean);
    m.largest = std::max(m.largest, std::abs(x));
  }
  m.deviation = std::sqrt(m.deviation / Real(v.size() - 1));
  return m;
}

std::shared_ptr<Scene> two_boxes() {
  auto scene =
      scene_of({ground(), box_at("a", Vec3(0, 0, 1), 0.5), box_at("b", Vec3(2, 0, 1), 0.25)});
  scene->materials = {Material{"default"}, Material{"ice", 0.05, 0.0}};
  scene->bodies[2].material = 1;
  return scene;
}

constexpr int kSeeds = 4000;

TEST(Randomization, TheSameSeedGivesTheSameSceneAndSeedsDiffer) {
  auto scene = two_boxes();
  scene->randomize.friction = Interval{0.2, 1.0};
  scene->randomize.size_noise = 0.02;
  scene->randomize.position_noise = 0.01;
  scene->randomize.orientation_noise = 0.05;
  scene->randomize.mass_scale = Interval{0.5, 2};
  scene->randomize.gravity_low = Vec3(-1, -1, -10);
  scene->randomize.gravity_high = Vec3(1, 1, -9);
  const Scene a = randomized(*scene, 42), b = randomized(*scene, 42), c = randomized(*scene, 43);
  EXPECT_FALSE(a.randomize.any());  // a drawn scene does not draw again
  EXPECT_EQ(a.world.gravity, b.world.gravity);
  EXPECT_NE(a.world.gravity, c.world.gravity);
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    EXPECT_EQ(a.bodies[i].position, b.bodies[i].position);
    EXPECT_EQ(a.bodies[i].orientation.coeffs(), b.bodies[i].orientation.coeffs());
    EXPECT_EQ(a.bodies[i].shape.half_extents, b.bodies[i].shape.half_extents);
    EXPECT_EQ(a.bodies[i].mass, b.bodies[i].mass);
  }
  EXPECT_NE(a.bodies[1].shape.half_extents, c.bodies[1].shape.half_extents);
  EXPECT_EQ(World(std::make_shared<Scene>(a)).state_hash(),
            World(std::make_shared<Scene>(b)).state_hash());
}

TEST(Randomization, StaticBodiesAndUnlistedQuantitiesStayAsTheyWere) {
  auto scene = two_boxes();
  scene->randomize.size_noise = 0.05;
  const Scene a = randomized(*scene, 7);
  EXPECT_EQ(a.bodies[0].shape.half_extents, scene->bodies[0].shape.half_extents);
  EXPECT_EQ(a.world.gravity, scene->world.gravity);
  EXPECT_EQ(a.materials[1].friction, scene->materials[1].friction);
  EXPECT_EQ(a.bodies[1].position, scene->bodies[1].position);
  // Each quantity has its own stream: turning friction on does not change the sizes.
  scene->randomize.friction = Interval{0.1, 0.9};
  const Scene b = randomized(*scene, 7);
  EXPECT_EQ(a.bodies[1].shape.half_extents, b.bodies[1].shape.half_extents);
  EXPECT_NE(a.materials[1].friction, b.materials[1].friction);
}

TEST(Randomization, SizeNoiseIsNormalCutAtThreeDeviationsAndKeepsTheDensity) {
  auto scene = two_boxes();
  const Real sigma = 0.02;
  scene->randomize.size_noise = sigma;
  const BodyDesc& before = scene->bodies[1];
  const Real density = before.mass / 1.0;  // a unit cube
  std::vector<Real> noise;
  for (int s = 0; s < kSeeds; ++s) {
    const BodyDesc b = randomized(*scene, std::uint64_t(s)).bodies[1];
    const Vec3 h = b.shape.half_extents;
    for (int k = 0; k < 3; ++k)
      noise.push_back(h[k] / 0.5 - 1);
    // Mass and inertia of a box of the new size at the old density.
    const Real mass = density * 8 * h.prod();
    EXPECT_NEAR(b.mass, mass, 1e-12 * mass);
    const Vec3 moments_expected(mass / 3 * (h.y() * h.y() + h.z() * h.z()),
                                mass / 3 * (h.x() * h.x() + h.z() * h.z()),
                                mass / 3 * (h.x() * h.x() + h.y() * h.y()));
    EXPECT_LT((b.inertia.diagonal() - moments_expected).norm(), 1e-12 * mass);
  }
  const Moments m = moments(noise);
  // 12,000 draws: the mean within 4 standard errors, the deviation within 3%.
  EXPECT_LT(std::abs(m.mean), 4 * sigma / std::sqrt(Real(noise.size())));
  EXPECT_NEAR(m.deviation, sigma, 0.03 * sigma);
  EXPECT_LE(m.largest, 3 * sigma + 1e-15);
  EXPECT_GT(m.largest, 2.5 * sigma);  // the tails are drawn, only cut
}

TEST(Randomization, MaterialsMassGravityAreUniformInTheirRanges) {
  auto scene = two_boxes();
  scene->randomize.friction = Interval{0.2, 1.0};
  scene->randomize.restitution = Interval{0.1, 0.3};
  scene->randomize.mass_scale = Interval{0.5, 2.0};
  scene->randomize.gravity_low = Vec3(-1, 0, -10);
  scene->randomize.gravity_high = Vec3(1, 0, -9);
  std::vector<Real> friction, restitution, scale, gx, gz;
  for (int s = 0; s < kSeeds; ++s) {
    const Scene a = randomized(*scene, std::uint64_t(s) * 7919);
    for (const Material& m : a.materials) {
      friction.push_back(m.friction);
      restitution.push_back(m.restitution);
    }
    scale.push_back(a.bodies[2].mass / scene->bodies[2].mass);
    EXPECT_NEAR(a.bodies[2].inertia(0, 0) / scene->bodies[2].inertia(0, 0), scale.back(), 1e-12);
    gx.push_back(a.world.gravity.x());
    gz.push_back(a.world.gravity.z());
    EXPECT_EQ(a.world.gravity.y(), 0);
  }
  // A uniform [a, b]: mean (a + b) / 2, deviation (b - a) / sqrt(12), every draw inside.
  const auto uniform = [](const std::vector<Real>& v, Real a, Real b) {
    const Moments m = moments(v);
    const Real sd = (b - a) / std::sqrt(Real(12));
    EXPECT_NEAR(m.mean, (a + b) / 2, 4 * sd / std::sqrt(Real(v.size())));
    EXPECT_NEAR(m.deviation, sd, 0.03 * sd);
    for (const Real x : v) {
      EXPECT_GE(x, a);
      EXPECT_LE(x, b);
    }
  };
  uniform(friction, 0.2, 1.0);
  uniform(restitution, 0.1, 0.3);
  uniform(scale, 0.5, 2.0);
  uniform(gx, -1, 1);
  uniform(gz, -10, -9);
  // The two materials draw apart.
  EXPECT_NE(friction[0], friction[1]);
}

TEST(Randomization, PoseNoiseHasTheGivenDeviations) {
  auto scene = two_boxes();
  scene->randomize.position_noise = 0.01;
  scene->randomize.orientation_noise = 0.05;
  std::vector<Real> dx, dz, angle_squared;
  for (int s = 0; s < kSeeds; ++s) {
    const BodyDesc b = randomized(*scene, std::uint64_t(s)).bodies[1];
    dx.push_back(b.position.x() - 0);
    dz.push_back(b.position.z() - 1);
    EXPECT_NEAR(b.orientation.norm(), 1, 1e-12);
    const Real angle = Eigen::AngleAxis<Real>(b.orientation).angle();
    angle_squared.push_back(angle * angle);
  }
  EXPECT_NEAR(moments(dx).deviation, 0.01, 0.0003);
  EXPECT_NEAR(moments(dz).deviation, 0.01, 0.0003);
  EXPECT_LT(std::abs(moments(dx).mean), 4 * 0.01 / std::sqrt(Real(kSeeds)));
  // The angle of a rotation vector of three Normal(0, s) components: E[angle^2] = 3 s^2.
  EXPECT_NEAR(moments(angle_squared).mean, 3 * 0.05 * 0.05, 0.05 * 3 * 0.05 * 0.05);
}

TEST(Randomization, HullsStayCentredAndCompoundPartsStayInPlace) {
  const std::vector<Vec3> corners{{-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1},
                                  {-1, -1, 1},  {1, -1, 1},  {-1, 1, 1},  {1, 1, 1}};
  BodyDesc hull = dynamic_body("hull", hull_from_points(corners), 500);
  hull.position = Vec3(0, 0, 3);
  const std::vector<CompoundPart> parts =
      testing::box_and_sphere(Vec3::Constant(0.5), -1, 0.4, 1.5);
  BodyDesc compound = testing::compound_at("compound", parts, 800, Vec3(0, 0, 6));
  auto scene = scene_of({ground(), hull, compound});
  scene->randomize.size_noise = 0.1;
  for (int s = 0; s < 200; ++s) {
    const Scene a = randomized(*scene, std::uint64_t(s));
    const BodyDesc& h = a.bodies[1];
    // The hull of a scaled cube is a box of the scaled half extents: its mass and moments.
    const Real mass = h.mass;
    const Vec3 half =
        Vec3(std::sqrt(3 * (h.inertia(1, 1) + h.inertia(2, 2) - h.inertia(0, 0)) / (2 * mass)),
             std::sqrt(3 * (h.inertia(0, 0) + h.inertia(2, 2) - h.inertia(1, 1)) / (2 * mass)),
             std::sqrt(3 * (h.inertia(0, 0) + h.inertia(1, 1) - h.inertia(2, 2)) / (2 * mass)));
    EXPECT_NEAR(mass, 500 * 8 * half.prod(), 1e-9 * mass) << "seed " << s;
    EXPECT_LT((h.position - Vec3(0, 0, 3)).norm(), 1e-12) << "seed " << s;
    // The compound's parts keep their centres in the world, whatever their new sizes.
    const BodyDesc& c = a.bodies[2];
    const auto& moved = c.shape.compound->parts();
    for (std::size_t p = 0; p < moved.size(); ++p) {
      const Vec3 world = c.position + c.orientation * moved[p].pose.translation;
      EXPECT_LT((world - (Vec3(0, 0, 6) + parts[p].pose.translation)).norm(), 1e-12)
          << "seed " << s << " part " << p;
    }
    EXPECT_NE(moved[0].shape.half_extents, Vec3::Constant(0.5));
  }
}

TEST(Randomization, BadRangesAreRefusedNamingTheField) {
  auto scene = two_boxes();
  scene->randomize.friction = Interval{0.9, 0.1};
  try {
    randomized(*scene, 1);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field, "randomize.friction");
    EXPECT_NE(std::string(e.what()).find("low <= high"), std::string::npos) << e.what();
  }
  scene->randomize = {};
  scene->randomize.size_noise = 0.5;
  EXPECT_THROW(check_scene(*scene), SceneError);
  scene->randomize = {};
  scene->randomize.gravity_low = Vec3(0, 0, -10);
  EXPECT_THROW(check_scene(*scene), SceneError);
  scene->randomize.gravity_high = Vec3(0, 0, -11);
  EXPECT_THROW(check_scene(*scene), SceneError);
  scene->randomize.gravity_high = Vec3(0, 0, std::nan(""));
  EXPECT_THROW(check_scene(*scene), SceneError);
}

std::shared_ptr<Scene> randomized_pile() {
  std::vector<BodyDesc> bodies{ground()};
  for (int k = 0; k < 4; ++k) {
    std::string name = "b";
    name += std::to_string(k);
    bodies.push_back(box_at(name, Vec3(0.1 * k, 0, 1 + 1.05 * k), 0.5));
  }
  auto scene = scene_of(bodies);
  scene->randomize.friction = Interval{0.3, 1.0};
  scene->randomize.mass_scale = Interval{0.5, 2.0};
  scene->randomize.size_noise = 0.02;
  scene->randomize.position_noise = 0.01;
  scene->randomize.orientation_noise = 0.02;
  scene->randomize.gravity_low = Vec3(-0.5, -0.5, -10.3);
  scene->randomize.gravity_high = Vec3(0.5, 0.5, -9.3);
  return scene;
}

TEST(Randomization, EachBatchWorldIsTheLoneWorldOfItsDraw) {
  auto scene = randomized_pile();
  const int worlds = 6, steps = 30;
  std::vector<std::uint64_t> hashes;
  for (const int threads : {1, 2, 4}) {
    BatchWorld batch(scene, worlds, threads, 99);
    batch.step(steps);
    std::vector<std::uint64_t> now;
    for (int w = 0; w < worlds; ++w)
      now.push_back(batch.state_hash(w));
    if (hashes.empty())
      hashes = now;
    EXPECT_EQ(now, hashes) << threads << " threads";
  }
  BatchWorld batch(scene, worlds, 2, 99);
  std::set<std::uint64_t> seeds;
  for (int w = 0; w < worlds; ++w) {
    EXPECT_EQ(batch.seed(w), BatchWorld::draw_seed(99, w, 0));
    seeds.insert(batch.seed(w));
    World lone(std::make_shared<Scene>(randomized(*scene, batch.seed(w))));
    lone.step(steps);
    EXPECT_EQ(lone.state_hash(), hashes[std::size_t(w)]) << "world " << w;
  }
  EXPECT_EQ(seeds.size(), std::size_t(worlds));
  std::set<std::uint64_t> distinct(hashes.begin(), hashes.end());
  EXPECT_EQ(distinct.size(), std::size_t(worlds));  // the draws made different worlds
}

// Worlds reset together run their resets on the batch's threads; each is then the lone world of
// its new draw. A world listed twice draws twice, in order.
TEST(Randomization, WorldsResetOnSeveralThreadsAreTheLoneWorldsOfTheirDraws) {
  auto scene = randomized_pile();
  const int worlds = 6;
  for (const int threads : {1, 2}) {
    BatchWorld batch(scene, worlds, threads, 7);
    batch.step(15);
    const std::vector<int> all{0, 1, 2, 3, 4, 5};
    batch.reset(all);
    const std::vector<int> twice{4, 4};
    batch.reset(twice);
    batch.step(25);
    for (int w = 0; w < worlds; ++w) {
      const int draw = w == 4 ? 3 : 1;
      EXPECT_EQ(batch.seed(w), BatchWorld::draw_seed(7, w, std::uint64_t(draw)));
      World lone(std::make_shared<Scene>(randomized(*scene, batch.seed(w))));
      lone.step(25);
      EXPECT_EQ(lone.state_hash(), batch.state_hash(w))
          << "world " << w << ", " << threads << " threads";
    }
  }
}

// A draw can leave the ranges (a mass near the limit scaled past it): the reset throws, and the
// world of that draw is left as it was, its seed and state unchanged; a world reset in the same
// call on another thread is either reset with its draw or left, never half done.
TEST(Randomization, AResetWhoseDrawFailsItsChecksLeavesThatWorldAsItWas) {
  auto scene = randomized_pile();
  const Real heavy = 0.8e15;  // kg; the limit is 1e15, reached at a scale of 1.25
  scene->bodies[1].inertia *= heavy / scene->bodies[1].mass;
  scene->bodies[1].mass = heavy;
  const auto passes = [&](std::uint64_t seed) { return testing::draw_passes(*scene, seed); };
  std::uint64_t failing = 0, passing = 0;
  while (passes(failing))
    ++failing;
  while (!passes(passing))
    ++passing;
  for (const int threads : {1, 2}) {
    std::uint64_t base = 0;
    while (!passes(BatchWorld::draw_seed(base, 0, 0)) || !passes(BatchWorld::draw_seed(base, 1, 0)))
      ++base;
    BatchWorld batch(scene, 2, threads, base);
    batch.step(5);
    const std::uint64_t seed0 = batch.seed(0), hash0 = batch.state_hash(0);
    const std::uint64_t seed1 = batch.seed(1), hash1 = batch.state_hash(1);
    const std::vector<int> both{0, 1};
    const std::vector<std::uint64_t> seeds{failing, passing};
    EXPECT_ANY_THROW(batch.reset(both, seeds));
    EXPECT_EQ(batch.seed(0), seed0);
    EXPECT_EQ(batch.state_hash(0), hash0);
    if (batch.seed(1) == passing) {
      EXPECT_EQ(batch.state_hash(1),
                World(std::make_shared<Scene>(randomized(*scene, passing))).state_hash());
    } else {
      EXPECT_EQ(batch.seed(1), seed1);
      EXPECT_EQ(batch.state_hash(1), hash1);
    }
    // Its next reset draws as if the failed one had not been asked for.
    const std::vector<int> first{0};
    batch.reset(first);
    EXPECT_EQ(batch.seed(0), BatchWorld::draw_seed(base, 0, 1));
  }
}

TEST(Randomization, ResetDrawsAgainAndAGivenSeedReplays) {
  auto scene = randomized_pile();
  BatchWorld batch(scene, 3, 1, 5);
  batch.step(20);
  const std::uint64_t first_hash = batch.state_hash(1);
  const std::vector<int> one{1};
  batch.reset(one);
  EXPECT_EQ(batch.seed(1), BatchWorld::draw_seed(5, 1, 1));
  batch.step(20);
  EXPECT_NE(batch.state_hash(1), first_hash);  // a new draw, a new world
  // Given the seed of the first draw, the world replays its first episode exactly.
  const std::vector<std::uint64_t> seed{BatchWorld::draw_seed(5, 1, 0)};
  batch.reset(one, seed);
  batch.step(20);
  EXPECT_EQ(batch.state_hash(1), first_hash);
  // The observation of a reset world is its draw's initial state.
  batch.reset(one, seed);
  const Scene drawn = randomized(*scene, seed[0]);
  const auto obs = batch.observations();
  const std::size_t row = std::size_t(1 * batch.body_count() + 2) * BatchWorld::kObservationWidth;
  EXPECT_EQ(obs[row + 2], drawn.bodies[2].position.z());
  const std::vector<std::uint64_t> two_seeds{1, 2};
  EXPECT_THROW(batch.reset(one, two_seeds), Error);
}

TEST(Randomization, ShardsOfABatchStepItsWorlds) {
  // A batch of 7 worlds cut into shards of 3 and 4 (first_world 0 and 3): every world draws,
  // steps and resets as in the whole batch.
  auto scene = randomized_pile();
  BatchWorld whole(scene, 7, 1, 42);
  BatchWorld head(scene, 3, 1, 42, 0);
  BatchWorld tail(scene, 4, 2, 42, 3);
  const auto same = [&](const char* when) {
    for (int w = 0; w < 7; ++w) {
      const BatchWorld& shard = w < 3 ? head : tail;
      const int local = w < 3 ? w : w - 3;
      EXPECT_EQ(shard.seed(local), whole.seed(w)) << when << ", world " << w;
      EXPECT_EQ(shard.state_hash(local), whole.state_hash(w)) << when << ", world " << w;
    }
  };
  same("made");
  for (BatchWorld* b : {&whole, &head, &tail})
    b->step(15);
  same("stepped");
  // Worlds 1 and 5 end their episode: the next draw is the whole batch's.
  const std::vector<int> whole_ids{1, 5}, head_ids{1}, tail_ids{2};
  whole.reset(whole_ids);
  head.reset(head_ids);
  tail.reset(tail_ids);
  for (BatchWorld* b : {&whole, &head, &tail})
    b->step(15);
  same("reset and stepped");
  EXPECT_THROW(BatchWorld(scene, 3, 1, 42, -1), Error);
  EXPECT_THROW(BatchWorld(scene, 3, 1, 42, std::numeric_limits<int>::max() - 1), Error);
}

}  // namespace
}  // namespace tumble
