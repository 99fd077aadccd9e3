// A batch lends its worlds' steps scratch arrays of its own (engine/step_workspace.hpp), one set
// per step running at once: whatever another world left in them, each world steps as the lone
// world of its draw, bit for bit; and a world holds none of them itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

using testing::box_at;
using testing::ground;
using testing::scene_of;

// Every narrow-phase route a step takes: boxes (the box batch and its separating axes), spheres
// (the sphere batch), hulls (GJK's warm start and the hull axes), a capsule; dropped in a column
// whose draws scatter them differently in every world, so that the worlds' candidate pairs and
// contacts differ in number and kind.
std::shared_ptr<const Scene> mixed_column() {
  std::vector<BodyDesc> bodies{ground()};
  const std::vector<Vec3> points{
      {-0.3, -0.3, -0.2}, {0.3, -0.3, -0.2}, {0, 0.35, -0.2}, {0, 0, 0.4}, {0.1, 0.1, -0.2}};
  for (int k = 0; k < 10; ++k) {
    const Vec3 at(0.25 * (k % 3) - 0.25, 0.2 * (k % 2), 0.6 + 0.55 * k);
    std::string name = "b";  // (not "b" + ...: g++ 12 warns wrongly of an overflow there)
    name += std::to_string(k);
    switch (k % 4) {
      case 0:
        bodies.push_back(box_at(name, at, 0.25));
        break;
      case 1: {
        BodyDesc b = dynamic_body(name, Shape::sphere(0.22));
        b.position = at;
        bodies.push_back(b);
        break;
      }
      case 2: {
        BodyDesc b = dynamic_body(name, hull_from_points(points), 800);
        b.position = at;
        bodies.push_back(b);
        break;
      }
      default: {
        BodyDesc b = dynamic_body(name, Shape::capsule(0.15, 0.25));
        b.position = at;
        bodies.push_back(b);
      }
    }
  }
  auto scene = scene_of(bodies);
  Randomization& r = scene->randomize;
  r.friction = Interval{0.1, 1.0};
  r.restitution = Interval{0.0, 0.6};
  r.size_noise = 0.05;
  r.position_noise = 0.3;
  r.orientation_noise = 0.5;
  check_scene(*scene);
  return scene;
}

// A push on body b of world w at step s; worlds w % 3 == 0 are left alone.
Vec3 push(int w, int b, int s) {
  if (w % 3 == 0)
    return Vec3::Zero();
  std::mt19937 random(std::uint32_t(7919 * w + 131 * b + s));
  std::uniform_real_distribution<Real> u(-60, 60);
  return Vec3(u(random), u(random), u(random));
}

TEST(StepWorkspace, WorldsThatShareScratchArraysStepAsLoneWorlds) {
  const std::shared_ptr<const Scene> scene = mixed_column();
  const int worlds = 9, steps = 60;
  for (const int threads : {1, 2}) {
    BatchWorld batch(scene, worlds, threads, 5);
    // One step at a time, so that each world's step follows other worlds' in the same arrays.
    for (int s = 0; s < steps; ++s) {
      testing::write_batch_forces(batch, [s](int w, int b) { return push(w, b, s); });
      batch.step();
    }
    std::vector<std::int64_t> contacts;
    for (int w = 0; w < worlds; ++w) {
      World lone(std::make_shared<Scene>(randomized(*scene, batch.seed(w))));
      std::int64_t touching = 0;
      for (int s = 0; s < steps; ++s) {
        for (const BodyId id : lone.bodies())
          if (id.index > 0)
            lone.add_force(id, push(w, id.index, s));
        lone.step();
        touching += static_cast<std::int64_t>(lone.contact_reports().size());
      }
      contacts.push_back(touching);
      EXPECT_EQ(lone.state_hash(), batch.state_hash(w))
          << "world " << w << ", " << threads << " threads";
    }
    // The worlds did differ in what their steps filled in.
    EXPECT_NE(*std::min_element(contacts.begin(), contacts.end()),
              *std::max_element(contacts.begin(), contacts.end()));
  }
}

// Identical worlds need identical arrays: a batch of many on one thread holds one set, as a
// batch of one does, not one per world.
TEST(StepWorkspace, ABatchOnOneThreadHoldsOneSetWhateverItsSize) {
  auto scene = std::const_pointer_cast<Scene>(mixed_column());
  scene->randomize = Randomization{};
  BatchWorld one(scene, 1, 1);
  BatchWorld many(scene, 32, 1);
  EXPECT_EQ(one.scratch_bytes(), 0u) << "nothing is lent before a step";
  one.step(20);
  many.step(20);
  EXPECT_GT(one.scratch_bytes(), 0u);
  EXPECT_EQ(many.scratch_bytes(), one.scratch_bytes());
  EXPECT_EQ(many.state_hash(31), one.state_hash(0));
}

}  // namespace
}  // namespace tumble
