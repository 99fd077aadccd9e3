// The world answers its box-box candidate pairs all at once (collide_box_pairs) and the others
// pair by pair, then puts the manifolds back in the broad phase's order. Every touching box pair
// of a step must carry the manifold of its own two boxes: the normal and the deepest depth that
// collide() finds for them at the poses the step started from.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

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

// Steps `scene_name` for `steps` steps; returns how many touching box pairs were checked.
int check_box_pairs(const std::string& scene_name, int steps) {
  const auto scene = shipped_scene(scene_name);
  World world(scene);
  int checked = 0;
  for (int k = 0; k < steps; ++k) {
    const State before = world.state();
    world.step();
    for (const PairContact& pc : world.contacts()) {
      const Shape& a = scene->bodies[pc.body_a].shape;
      const Shape& b = scene->bodies[pc.body_b].shape;
      if (a.type != ShapeType::box || b.type != ShapeType::box)
        continue;
      const Real world_depth = deepest(pc.manifold);
      if (world_depth <= 1e-9)
        continue;  // within the speculative margin only: its points depend on that margin
      const BodyState& sa = before.bodies[pc.body_a];
      const BodyState& sb = before.bodies[pc.body_b];
      Manifold expected;
      collide(a, {sa.position, sa.orientation}, b, {sb.position, sb.orientation}, 0, expected);
      EXPECT_GT(expected.count, 0) << scene_name << " step " << k;
      EXPECT_NEAR((pc.manifold.normal - expected.normal).norm(), 0, 1e-12)
          << scene_name << " step " << k << " bodies " << pc.body_a << ", " << pc.body_b;
      EXPECT_NEAR(world_depth, deepest(expected), 1e-12)
          << scene_name << " step " << k << " bodies " << pc.body_a << ", " << pc.body_b;
      ++checked;
    }
  }
  return checked;
}

TEST(WorldBoxPairs, EachTouchingBoxPairCarriesItsOwnManifold) {
  // A pyramid of 210 cubes on a floor (box pairs touching face on face, layer on layer) and the
  // demo scene (boxes falling and tumbling onto each other).
  EXPECT_GT(check_box_pairs("bench/pyramid_20.yaml", 60), 60 * 150);
  EXPECT_GT(check_box_pairs("demo.yaml", 300), 100);
}

}  // namespace
}  // namespace tumble::test
