// The world's separating-direction cache for hull pairs
// (collision/narrow_phase/hull_axis_cache.hpp) changes no bit of a trajectory: hulls dropped in a
// loose grid onto a floor, landing on each other, are stepped twice, once as they are and once with
// the cached directions dropped before every step (every hull pair queried in full), and the bodies
// must agree bit for bit at every step, while the cache does skip most of the separated pairs.
#include <gtest/gtest.h>

#include <memory>

#include "collision/shapes/convex_hull.hpp"
#include "engine/simulation.hpp"
#include "tests/physics/body_builders.hpp"
#include "tests/physics/cache_dropping_run.hpp"
#include "tests/property_scale.hpp"

namespace tumble::test {
namespace {

std::shared_ptr<const Scene> tumbling_hulls(int per_side, int layers) {
  Scene s;
  s.materials.push_back(Material{"default", 0.5, 0.3});
  s.bodies.push_back(static_body("floor", Shape::box(Vec3(20, 20, 1)), Vec3(0, 0, -1)));
  const Vec3 tip[5] = {{0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  const Vec3 prism[8] = {{-0.6, -0.5, -0.3}, {0.6, -0.5, -0.3}, {0.6, 0.5, -0.3}, {-0.6, 0.5, -0.3},
                         {-0.4, -0.3, 0.3},  {0.5, -0.4, 0.3},  {0.4, 0.3, 0.3},  {-0.5, 0.4, 0.3}};
  const Shape hulls[2] = {Shape::convex_hull(std::make_shared<const ConvexHull>(
                              ConvexHull::from_points(std::span(tip, 5)))),
                          Shape::convex_hull(std::make_shared<const ConvexHull>(
                              ConvexHull::from_points(std::span(prism, 8))))};
  for (int k = 0; k < layers; ++k) {
    for (int i = 0; i < per_side; ++i) {
      for (int j = 0; j < per_side; ++j) {
        const int n = (k * per_side + i) * per_side + j;
        const Vec3 at((i - 0.5 * per_side) * 1.6 + 0.3 * k, (j - 0.5 * per_side) * 1.6,
                      1.2 + 1.5 * k);
        BodyDesc b = dynamic_body("hull", hulls[n % 2], at, Vec3(0, 0, -2), 1 + n % 3);
        b.orientation = Quat(Eigen::AngleAxis<Real>(0.4 * n, Vec3(3, 1, 2).normalized()));
        s.bodies.push_back(b);
      }
    }
  }
  return std::make_shared<const Scene>(std::move(s));
}

TEST(HullAxisCacheWorld, DroppingTheCacheChangesNoBit) {
  const AxisCacheUse use = expect_same_bits_without_cache(tumbling_hulls(4, 3), scaled(240),
                                                          [](State& s) { s.hull_axes.clear(); });
  // The cache was used, and mostly held.
  EXPECT_GT(use.tries, 500);
  EXPECT_GT(use.hits, use.tries / 2);
}

}  // namespace
}  // namespace tumble::test
