// YAML aliases of a shape are one shape: loaded once (a file of many aliases of a large hull runs
// Qhull once) and shared, with the same centre of mass for every body that uses it.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "scenes/scene_loader.hpp"

namespace tumble {
namespace {

TEST(ShapeAliases, EveryAliasIsTheSameLoadedShape) {
  std::ostringstream yaml;
  yaml << "bodies:\n  - name: first\n    position: [0, 0, 0]\n    shape: &rock\n      type: hull\n"
          "      points: [";
  for (int i = 0; i < 400; ++i) {
    const double a = 0.37 * i, b = 0.11 * i;
    yaml << (i ? ", " : "") << "[" << std::cos(a) * std::cos(b) << ", " << std::sin(a) * std::cos(b)
         << ", " << 0.5 + std::sin(b) << "]";
  }
  yaml << "]\n";
  for (int k = 1; k < 1000; ++k)
    yaml << "  - {name: copy" << k << ", shape: *rock, position: [" << 3 * k << ", 0, 0]}\n";
  const Scene scene = load_scene_string(yaml.str(), "aliases.yaml");
  ASSERT_EQ(scene.bodies.size(), 1000u);
  const BodyDesc& first = scene.bodies[0];
  for (std::size_t k = 1; k < scene.bodies.size(); ++k) {
    const BodyDesc& b = scene.bodies[k];
    ASSERT_EQ(b.shape.hull, first.shape.hull) << k;  // the same hull object, built once
    // Each body is moved by the same centre of mass offset from where the file placed it.
    EXPECT_NEAR(b.position.x() - 3.0 * double(k), first.position.x(), 1e-9) << k;
    EXPECT_EQ(b.position.z(), first.position.z());
    EXPECT_EQ(b.mass, first.mass);
  }
  EXPECT_GT(first.position.z(), 0.1);  // the hull's centre of mass is above its frame's origin
}

}  // namespace
}  // namespace tumble
