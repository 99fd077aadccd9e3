// World::ray_cast against brute force: random rays through a field of spheres, where the first hit
// is the smallest root of |o + t d - c|^2 = r^2 over all spheres.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/api/api_scenes.hpp"

namespace tumble {
namespace {

TEST(WorldRayCast, MatchesBruteForceOverSpheres) {
  std::mt19937 random(11);
  std::uniform_real_distribution<Real> across(-10, 10);
  std::uniform_real_distribution<Real> size(0.2, 1.5);
  std::vector<BodyDesc> bodies;
  for (int k = 0; k < 60; ++k) {
    std::string name = "s";
    name += std::to_string(k);
    BodyDesc b = dynamic_body(name, Shape::sphere(size(random)));
    b.position = Vec3(across(random), across(random), across(random));
    bodies.push_back(b);
  }
  auto scene = testing::scene_of(bodies, Vec3::Zero());
  const World world(scene);
  int hits = 0;
  for (int q = 0; q < 3000; ++q) {
    const Vec3 origin(across(random), across(random), across(random));
    const Vec3 direction = Vec3(across(random), across(random), across(random)).normalized();
    const Real max_distance = 15;
    // Brute force: the nearest entry t in [0, max_distance], 0 from inside.
    int want = -1;
    Real want_t = max_distance;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const Vec3 m = origin - bodies[i].position;
      const Real r = bodies[i].shape.radius;
      const Real c = m.squaredNorm() - r * r;
      Real t = 0;
      if (c > 0) {
        const Real b = m.dot(direction);
        const Real disc = b * b - c;
        if (b > 0 || disc < 0)
          continue;
        t = -b - std::sqrt(disc);
      }
      if (t <= max_distance && (want < 0 || t < want_t)) {
        want = static_cast<int>(i);
        want_t = t;
      }
    }
    const std::optional<RayHit> hit = world.ray_cast(origin, direction * 3, max_distance);
    ASSERT_EQ(hit.has_value(), want >= 0) << "ray " << q;
    if (!hit)
      continue;
    ++hits;
    EXPECT_EQ(hit->body.index, want) << "ray " << q;
    EXPECT_NEAR(hit->distance, want_t, 1e-9) << "ray " << q;
    EXPECT_LE((hit->point - (origin + direction * want_t)).norm(), 1e-9);
    if (want_t > 0) {
      const Vec3 outward = (hit->point - bodies[std::size_t(want)].position).normalized();
      EXPECT_LE((hit->normal - outward).norm(), 1e-6) << "ray " << q;
    }
  }
  EXPECT_GT(hits, 300);
}

TEST(WorldRayCast, DownOntoTheGround) {
  const World world(testing::scene_of({testing::ground()}));
  const std::optional<RayHit> hit = world.ray_cast(Vec3(1, 2, 5), Vec3(0, 0, -1), 100);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distance, 4.5, 1e-12);
  EXPECT_NEAR(hit->normal.z(), 1, 1e-12);
  EXPECT_FALSE(world.ray_cast(Vec3(1, 2, 5), Vec3(0, 0, 1), 100));
  EXPECT_FALSE(world.ray_cast(Vec3(1, 2, 5), Vec3(0, 0, -1), 4));
}

}  // namespace
}  // namespace tumble
