// The world answers its box-box candidate pairs all at once (collide_box_pairs) and the others
// pair by pair, then puts the manifolds back in the broad phase's order. Every overlapping box
// pair of a step must be among its contacts and carry the manifold of its own two boxes: the
// normal and the deepest depth that collide() finds for them at the poses the step started from.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <utility>

#include "collision/narrow_phase.hpp"
#include "tests/physics/scene_fixture.hpp"

namespace tumble::test {
namespace {

Real deepest(const Manifold& m) {
  Real depth = -std::numeric_limits<Real>::infinity();
  for (int p = 0; p < m.count; ++p)
    depth = std::max(depth, m.points[p].depth);
  return depth;
}

// Steps `scene_name` for `steps` steps; returns how many touching box pairs were checked. Every
// box-box candidate pair that collide() finds overlapping (deeper than 1e-9 m) at the poses the
// step started from must be among the step's contacts, with collide()'s normal and deepest depth.
int check_box_pairs(const std::string& scene_name, int steps) {
  const auto scene = shipped_scene(scene_name);
  World world(scene);
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
      if (a.type != ShapeType::box || b.type != ShapeType::box)
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
      EXPECT_NEAR((m.normal - expected.normal).norm(), 0, 1e-12)
          << scene_name << " step " << k << " bodies " << pair.a << ", " << pair.b;
      EXPECT_NEAR(deepest(m), deepest(expected), 1e-12)
          << scene_name << " step " << k << " bodies " << pair.a << ", " << pair.b;
      ++checked;
    }
  }
  return checked;
}

TEST(WorldBoxPairs, EachTouchingBoxPairCarriesItsOwnManifold) {
  // A pyramid of 210 cubes on a floor (box pairs touching face on face, layer on layer) and the
  // demo scene (boxes falling and tumbling onto each other).
  EXPECT_GT(check_box_pairs("bench/pyramid_20.yaml", 60), 60 * 150);
  EXPECT_GT(check_box_pairs("demo.yaml", 400), 100);
}

}  // namespace
}  // namespace tumble::test
