// The world answers its box-box candidate pairs all at once (collide_box_pairs) and the others
// pair by pair, then puts the manifolds back in the broad phase's order. Every overlapping box
// pair of a step must be among its contacts and carry the manifold of its own two boxes: the
// normal and the deepest depth that collide() finds for them at the poses the step started from.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <utility>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "scenes/scene_loader.hpp"
#include "tests/physics/scene_fixture.hpp"

namespace tumble::test {
namespace {

Real deepest(const Manifold& m) {
  Real depth = -std::numeric_limits<Real>::infinity();
  for (int p = 0; p < m.count; ++p)
    depth = std::max(depth, m.points[p].depth);
  return depth;
}

struct Tolerance {
  Real normal = 1e-12;  // |n - n_fresh|
  Real depth = 1e-12;   // |deepest - deepest_fresh| [m]
};

// Steps `scene_name` for `steps` steps; returns how many touching box pairs were checked. Every
// box-box candidate pair that collide() finds overlapping (deeper than 1e-9 m) at the poses the
// step started from must be among the step's contacts, with collide()'s normal and deepest depth
// (to `tolerance`; with contact recycling off, exactly up to rounding).
int check_box_pairs(const std::string& scene_name, int steps, bool recycling = false,
                    Tolerance tolerance = {}, ShapeType type = ShapeType::box) {
  auto edited = std::make_shared<Scene>(
      scene_name.starts_with("tests/")
          ? load_scene_file(std::string(TUMBLE_SOURCE_DIR) + "/" + scene_name)
          : *shipped_scene(scene_name));
  edited->world.contact_recycling = recycling;
  const std::shared_ptr<const Scene> scene = edited;
  Simulation world(scene);
  Real worst_normal = 0;
  Real worst_depth = 0;
  int checked = 0;
  for (int k = 0; k < steps; ++k) {
    const State before = world.state();
    world.step();
    std::map<std::pair<int, int>, const PairContact*> contact_of;
    for (const PairContact& pc : world.contacts())
      contact_of[{pc.body_a, pc.body_b}] = &pc;
    for (const ProxyPair& pair : world.candidate_pairs()) {
      const Shape& a = scene->bodies[pair.a].shape;
      const Shape& b = scene->bodies[pair.b].shape;
      if (a.type != type || b.type != type)
        continue;
      const BodyState& sa = before.bodies[pair.a];
      const BodyState& sb = before.bodies[pair.b];
      Manifold expected;
      collide(a, {sa.position, sa.orientation}, b, {sb.position, sb.orientation}, 0, expected);
      if (expected.count == 0 || deepest(expected) <= 1e-9)
        continue;  // apart, or within the speculative margin only (its points depend on it)
      const auto found = contact_of.find({pair.a, pair.b});
      if (found == contact_of.end()) {
        ADD_FAILURE() << scene_name << " step " << k << ": no contact for bodies " << pair.a << ", "
                      << pair.b;
        continue;
      }
      const Manifold& m = found->second->manifold;
      EXPECT_NEAR((m.normal - expected.normal).norm(), 0, tolerance.normal)
          << scene_name << " step " << k << " bodies " << pair.a << ", " << pair.b;
      EXPECT_NEAR(deepest(m), deepest(expected), tolerance.depth)
          << scene_name << " step " << k << " bodies " << pair.a << ", " << pair.b;
      worst_normal = std::max(worst_normal, (m.normal - expected.normal).norm());
      worst_depth = std::max(worst_depth, std::abs(deepest(m) - deepest(expected)));
      ++checked;
    }
  }
  std::printf("[box pairs] %s recycling %d: %d pairs, worst normal %.3g, worst depth %.3g m\n",
              scene_name.c_str(), recycling ? 1 : 0, checked, worst_normal, worst_depth);
  return checked;
}

TEST(WorldBoxPairs, EachTouchingBoxPairCarriesItsOwnManifold) {
  // A pyramid of 210 cubes on a floor (box pairs touching face on face, layer on layer) and the
  // demo scene (boxes falling and tumbling onto each other).
  EXPECT_GT(check_box_pairs("bench/pyramid_20.yaml", 60), 60 * 150);
  EXPECT_GT(check_box_pairs("demo.yaml", 400), 100);
}

// With contact recycling (the default), a pair that barely moved keeps its manifold: its normal
// turns with body A and its depths are measured again from the moved bodies, so it stays within
// what the recycling tolerances allow of collide()'s answer (which may take the other box's face
// as reference: a normal off by the relative turn, corners off by that turn times the half size).
TEST(WorldBoxPairs, RecycledManifoldsStayCloseToFreshOnes) {
  Tolerance tolerance;
  tolerance.normal = Simulation::kRecycleAngle;
  // Unit cubes: bounding radius 0.866 m.
  tolerance.depth = (Simulation::kRecycleDistance + Simulation::kRecycleAngle) * 0.866;
  EXPECT_GT(check_box_pairs("bench/pyramid_20.yaml", 60, true, tolerance), 60 * 150);
  EXPECT_GT(check_box_pairs("demo.yaml", 400, true, tolerance), 100);
}

}  // namespace
}  // namespace tumble::test

namespace tumble::test {
namespace {

// Sphere-sphere pairs go through the sphere batch (collide_sphere_pairs_dense), which gives
// collide()'s bits: every overlapping sphere pair carries collide()'s normal and depth exactly.
TEST(WorldSpherePairs, EachTouchingSpherePairCarriesCollidesManifold) {
  const std::string pile = "tests/data/scenes/sphere_pile.yaml";
  EXPECT_GT(check_box_pairs(pile, 120, false, {}, ShapeType::sphere), 1000);
  EXPECT_GT(check_box_pairs(pile, 120, true, {}, ShapeType::sphere), 1000)
      << "spheres never recycle: the same with recycling on";
}

}  // namespace
}  // namespace tumble::test
