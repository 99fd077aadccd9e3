// The world's separating-axis cache for box pairs (collision/narrow_phase/box_axis_cache.hpp)
// changes no bit of a trajectory: a pile of tumbling boxes is stepped twice, once as it is and once
// with the cached axes dropped before every step (so every box pair is queried in full), and the
// bodies must agree bit for bit at every step, while the cache does skip most of the separated
// pairs.
#include <gtest/gtest.h>

#include <memory>

#include "engine/simulation.hpp"
#include "tests/physics/body_builders.hpp"
#include "tests/physics/cache_dropping_run.hpp"
#include "tests/property_scale.hpp"

namespace tumble::test {
namespace {

// Boxes of three sizes dropped in a loose, slightly turned grid onto a floor box, so that they
// land on each other, tumble and come apart.
std::shared_ptr<const Scene> tumbling_boxes(int per_side, int layers) {
  Scene s;
  s.materials.push_back(Material{"default", 0.4, 0.2});
  s.bodies.push_back(static_body("floor", Shape::box(Vec3(20, 20, 1)), Vec3(0, 0, -1)));
  for (int k = 0; k < layers; ++k) {
    for (int i = 0; i < per_side; ++i) {
      for (int j = 0; j < per_side; ++j) {
        const int n = (k * per_side + i) * per_side + j;
        const Vec3 half(0.3 + 0.1 * (n % 3), 0.25 + 0.05 * (n % 2), 0.2 + 0.1 * (n % 4));
        const Vec3 at((i - 0.5 * per_side) * 1.3 + 0.2 * k, (j - 0.5 * per_side) * 1.3,
                      0.6 + 1.2 * k);
        BodyDesc b = dynamic_body("box", Shape::box(half), at, Vec3(0, 0, -2), 1 + n % 3);
        b.orientation = Quat(Eigen::AngleAxis<Real>(0.3 * n, Vec3(1, 2, 3).normalized()));
        s.bodies.push_back(b);
      }
    }
  }
  return std::make_shared<const Scene>(std::move(s));
}

TEST(BoxAxisCacheWorld, DroppingTheCacheChangesNoBit) {
  const AxisCacheUse use = expect_same_bits_without_cache(tumbling_boxes(5, 4), scaled(240),
                                                          [](State& s) { s.box_axes.clear(); });
  // The cache was used, and mostly held.
  EXPECT_GT(use.tries, 1000);
  EXPECT_GT(use.hits, use.tries / 2);
}

}  // namespace
}  // namespace tumble::test
