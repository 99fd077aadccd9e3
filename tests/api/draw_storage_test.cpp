// A batch's randomized resets write each draw over the storage of an earlier one
// (engine/draw_storage.hpp): such a draw must be the fresh draw of its seed, field for field and
// step for step, whatever was drawn there before; a model someone else still holds is never
// written over; and a draw that fails its check leaves the last model as it was.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "engine/draw_storage.hpp"
#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

using testing::box_at;
using testing::ground;
using testing::scene_of;

// Every kind of body a draw changes differently: a box with a training shape, a hull, a
// compound, a capsule, a kinematic box, and a static obstacle it must leave alone; two
// materials; every quantity randomized.
std::shared_ptr<const Scene> varied_scene(Geometry geometry) {
  BodyDesc trained = box_at("trained", Vec3(0, 0, 1), 0.4);
  trained.train_shape = Shape::sphere(0.45);
  const std::vector<Vec3> points{
      {-0.5, -0.4, -0.3}, {0.5, -0.4, -0.3}, {0, 0.5, -0.3}, {0, 0, 0.6}, {0.2, 0.1, -0.3}};
  BodyDesc hull = dynamic_body("hull", hull_from_points(points), 700);
  hull.position = Vec3(2, 0, 1);
  BodyDesc compound = testing::compound_at(
      "compound", testing::box_and_sphere(Vec3(0.3, 0.2, 0.2), -0.4, 0.25, 0.5), 900,
      Vec3(-2, 0, 1));
  compound.material = 1;
  BodyDesc capsule = dynamic_body("capsule", Shape::capsule(0.2, 0.4), 600);
  capsule.position = Vec3(0, 2, 0.5);
  BodyDesc pusher = box_at("pusher", Vec3(0, -2, 0.5), 0.3);
  pusher.kinematic = true;
  pusher.mass = 0;
  pusher.inertia = Mat3::Zero();
  BodyDesc obstacle = box_at("obstacle", Vec3(3, 3, 0.5), 0.5);
  obstacle.is_static = true;
  obstacle.mass = 0;
  obstacle.inertia = Mat3::Zero();
  auto scene = scene_of({ground(), trained, hull, compound, capsule, pusher, obstacle});
  scene->materials = {Material{"default"}, Material{"rubber", 0.9, 0.4}};
  scene->world.geometry = geometry;
  Randomization& r = scene->randomize;
  r.friction = Interval{0.2, 1.0};
  r.restitution = Interval{0.0, 0.5};
  r.mass_scale = Interval{0.5, 2.0};
  r.size_noise = 0.05;
  r.position_noise = 0.02;
  r.orientation_noise = 0.1;
  r.gravity_low = Vec3(-1, -1, -10.5);
  r.gravity_high = Vec3(1, 1, -9);
  check_scene(*scene);
  return scene;
}

void expect_same_shape(const Shape& a, const Shape& b, const std::string& where) {
  ASSERT_EQ(a.type, b.type) << where;
  EXPECT_EQ(a.radius, b.radius) << where;
  EXPECT_EQ(a.half_length, b.half_length) << where;
  EXPECT_EQ(a.half_extents, b.half_extents) << where;
  if (a.type == ShapeType::hull) {
    const auto va = a.hull->vertices(), vb = b.hull->vertices();
    ASSERT_EQ(va.size(), vb.size()) << where;
    for (std::size_t k = 0; k < va.size(); ++k)
      EXPECT_EQ(va[k], vb[k]) << where << " vertex " << k;
  }
  if (a.type == ShapeType::compound) {
    const auto& pa = a.compound->parts();
    const auto& pb = b.compound->parts();
    ASSERT_EQ(pa.size(), pb.size()) << where;
    for (std::size_t k = 0; k < pa.size(); ++k) {
      expect_same_shape(pa[k].shape, pb[k].shape, where + " part " + std::to_string(k));
      EXPECT_EQ(pa[k].pose.translation, pb[k].pose.translation) << where;
    }
  }
}

// Field for field: everything a draw writes, and the model's derived masses.
void expect_same_draw(const Model& written, const Model& fresh, std::uint64_t seed) {
  const Scene& a = written.described_scene();
  const Scene& b = fresh.described_scene();
  const std::string at = "seed " + std::to_string(seed);
  EXPECT_EQ(a.world.gravity, b.world.gravity) << at;
  ASSERT_EQ(a.materials.size(), b.materials.size()) << at;
  for (std::size_t m = 0; m < a.materials.size(); ++m) {
    EXPECT_EQ(a.materials[m].friction, b.materials[m].friction) << at;
    EXPECT_EQ(a.materials[m].restitution, b.materials[m].restitution) << at;
  }
  ASSERT_EQ(a.bodies.size(), b.bodies.size()) << at;
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const BodyDesc& p = a.bodies[i];
    const BodyDesc& q = b.bodies[i];
    const std::string where = at + ", body " + p.name;
    EXPECT_EQ(p.position, q.position) << where;
    EXPECT_EQ(p.orientation.coeffs(), q.orientation.coeffs()) << where;
    EXPECT_EQ(p.mass, q.mass) << where;
    EXPECT_EQ(p.inertia, q.inertia) << where;
    expect_same_shape(p.shape, q.shape, where);
    ASSERT_EQ(p.train_shape.has_value(), q.train_shape.has_value()) << where;
    if (p.train_shape)
      expect_same_shape(*p.train_shape, *q.train_shape, where + " (training shape)");
    expect_same_shape(written.scene().bodies[i].shape, fresh.scene().bodies[i].shape,
                      where + " (as collided)");
    EXPECT_EQ(written.masses()[i].inverse_mass, fresh.masses()[i].inverse_mass) << where;
    EXPECT_EQ(written.bounding_radii()[i], fresh.bounding_radii()[i]) << where;
  }
}

std::uint64_t hash_after_steps(std::shared_ptr<const Model> model, int steps) {
  World world(std::move(model));
  world.step(steps);
  return world.state_hash();
}

// Resets every world of `batch`, steps 30 times, and compares each with the lone world of its
// draw.
void expect_reset_worlds_are_lone_draws(BatchWorld& batch, const Scene& scene) {
  std::vector<int> all(std::size_t(batch.size()));
  for (int w = 0; w < batch.size(); ++w)
    all[std::size_t(w)] = w;
  batch.reset(all);
  batch.step(30);
  for (int w = 0; w < batch.size(); ++w) {
    World lone(std::make_shared<Scene>(randomized(scene, batch.seed(w))));
    lone.step(30);
    EXPECT_EQ(lone.state_hash(), batch.state_hash(w)) << "world " << w;
  }
}

// Seeds drawn from a small set, so that a seed is often drawn over another's draw and over its
// own; every tenth draw is also stepped against the fresh draw's world.
TEST(DrawStorage, ADrawWrittenOverEarlierOnesIsTheFreshDrawOfItsSeed) {
  for (const Geometry geometry : {Geometry::deploy, Geometry::train}) {
    const std::shared_ptr<const Scene> scene = varied_scene(geometry);
    DrawStorage storage;
    std::mt19937_64 pick(20261128);
    std::uniform_int_distribution<std::uint64_t> seeds(0, 40);
    for (int k = 0; k < 400; ++k) {
      const std::uint64_t seed = seeds(pick);
      const std::shared_ptr<const Model> written = storage.draw(scene, seed);
      const std::shared_ptr<const Model> fresh =
          compile(std::make_shared<const Scene>(randomized(*scene, seed)));
      expect_same_draw(*written, *fresh, seed);
      if (k % 10 == 0) {
        EXPECT_EQ(hash_after_steps(written, 20), hash_after_steps(fresh, 20)) << "seed " << seed;
      }
    }
  }
}

TEST(DrawStorage, AModelHeldElsewhereIsNeverWrittenOver) {
  const std::shared_ptr<const Scene> scene = varied_scene(Geometry::deploy);
  DrawStorage storage;
  const std::shared_ptr<const Model> kept = storage.draw(scene, 1);
  const Scene* kept_scene = &kept->described_scene();
  for (std::uint64_t seed = 2; seed < 12; ++seed)
    EXPECT_NE(storage.draw(scene, seed).get(), kept.get());
  EXPECT_EQ(&kept->described_scene(), kept_scene);
  expect_same_draw(*kept, *compile(std::make_shared<const Scene>(randomized(*scene, 1))), 1);
}

// The draw that fails leaves the model drawn before it as it was, and the next draw into the
// same storage is the fresh draw of its seed.
TEST(DrawStorage, AFailedDrawLeavesTheLastModelAndTheNextDrawIsFresh) {
  auto heavy = std::make_shared<Scene>(*varied_scene(Geometry::deploy));
  BodyDesc& b = heavy->bodies[1];
  const Real mass = 0.8e15;  // kg; the limit is 1e15, passed at a scale above 1.25
  b.inertia *= mass / b.mass;
  b.mass = mass;
  const std::shared_ptr<const Scene> scene = heavy;
  std::vector<std::uint64_t> failing, passing;
  for (std::uint64_t seed = 0; failing.size() < 20 || passing.size() < 20; ++seed)
    (testing::draw_passes(*scene, seed) ? passing : failing).push_back(seed);
  DrawStorage storage;
  for (std::size_t k = 0; k < 20; ++k) {
    const std::shared_ptr<const Model> last = storage.draw(scene, passing[k]);
    const std::uint64_t hash = hash_after_steps(last, 5);
    EXPECT_THROW(storage.draw(scene, failing[k]), SceneError);
    EXPECT_EQ(hash_after_steps(last, 5), hash);
    expect_same_draw(*last, *compile(std::make_shared<const Scene>(randomized(*scene, passing[k]))),
                     passing[k]);
  }
}

// A batch's reset of a world to another draw of its scene compares no static bodies (a draw
// leaves them as they are), but a static body the user moved in that world is still put back,
// and the world is then the lone world of its draw.
TEST(DrawStorage, AResetWorldWhoseStaticBodyWasMovedIsTheLoneWorldOfItsDraw) {
  const std::shared_ptr<const Scene> scene = varied_scene(Geometry::deploy);
  for (const int threads : {1, 2}) {
    BatchWorld batch(scene, 3, threads, 11);
    batch.step(10);
    World& world = batch.world(1);
    world.set_pose(world.body("obstacle"), Vec3(0, 0, 1.2), Quat::Identity());
    batch.step(10);
    expect_reset_worlds_are_lone_draws(batch, *scene);
  }
}

// A world whose bodies the user changed is no longer a draw of the batch's scene: its reset
// compares the bodies, finds them changed, and builds the world anew from its draw.
TEST(DrawStorage, AResetWorldWhoseBodiesWereChangedIsTheLoneWorldOfItsDraw) {
  const std::shared_ptr<const Scene> scene = varied_scene(Geometry::deploy);
  BatchWorld batch(scene, 3, 1, 23);
  batch.step(5);
  batch.world(0).add_body(box_at("extra", Vec3(1, 1, 2), 0.2));
  batch.world(2).remove_body(batch.world(2).body("capsule"));
  batch.step(5);
  expect_reset_worlds_are_lone_draws(batch, *scene);
  for (int w = 0; w < batch.size(); ++w)
    EXPECT_EQ(batch.world(w).bodies().size(), scene->bodies.size()) << "world " << w;
}

}  // namespace
}  // namespace tumble
