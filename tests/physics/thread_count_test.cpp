// A step gives the same bits on 1, 2 and 4 threads (dynamics/parallel_runner.hpp): three scenes
// large enough that every split loop of the step runs split (the box batch and the solver's
// colours in a field of pyramids; collide() pair by pair, a mesh and continuous collision under
// mixed shapes falling on a terrain; the sphere batch, restitution and sleeping in a rain of
// spheres), compared state hash by state hash at every step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/triangle_mesh.hpp"
#include "engine/simulation.hpp"
#include "tests/physics/body_builders.hpp"
#include "tests/property_scale.hpp"

namespace tumble::test {
namespace {

// Pyramids of boxes side by side on a floor box, each `base` boxes wide at the bottom.
std::shared_ptr<const Scene> pyramid_field(int pyramids, int base) {
  Scene s;
  s.materials.push_back(Material{"default"});
  s.bodies.push_back(static_body("floor", Shape::box(Vec3(60, 60, 1)), Vec3(0, 0, -1)));
  const Real half = 0.5;
  for (int p = 0; p < pyramids; ++p) {
    const Real x0 = (p - pyramids / 2) * (base + 2) * 2 * half;
    for (int layer = 0; layer < base; ++layer) {
      const int row = base - layer;
      for (int i = 0; i < row; ++i) {
        for (int j = 0; j < row; ++j) {
          const Vec3 at(x0 + (i - 0.5 * (row - 1)) * 2 * half, (j - 0.5 * (row - 1)) * 2 * half,
                        half + layer * 2 * half);
          s.bodies.push_back(
              dynamic_body("box", Shape::box(Vec3(half, half, half)), at, Vec3::Zero(), 1));
        }
      }
    }
  }
  return std::make_shared<const Scene>(std::move(s));
}

// A terrain of `cells` x `cells` triangle pairs, and on it a grid of boxes, spheres, capsules
// and hulls in turn, thrown down fast enough to be swept, bouncy.
std::shared_ptr<const Scene> shapes_on_terrain(int cells, int grid) {
  Scene s;
  s.materials.push_back(Material{"default", 0.5, 0.6});
  std::vector<Vec3> vertices;
  std::vector<TriangleMesh::Triangle> triangles;
  const Real cell = 1.5;
  for (int i = 0; i <= cells; ++i) {
    for (int j = 0; j <= cells; ++j) {
      const Real x = (i - 0.5 * cells) * cell;
      const Real y = (j - 0.5 * cells) * cell;
      vertices.emplace_back(x, y, 0.5 * std::sin(0.7 * i) * std::cos(0.6 * j));
    }
  }
  const auto vertex = [&](int i, int j) { return std::int32_t(i * (cells + 1) + j); };
  for (int i = 0; i < cells; ++i) {
    for (int j = 0; j < cells; ++j) {
      triangles.push_back({vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)});
      triangles.push_back({vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
    }
  }
  auto terrain = std::make_shared<const TriangleMesh>(
      TriangleMesh::build(std::move(vertices), std::move(triangles)));
  s.bodies.push_back(static_body("terrain", Shape::triangle_mesh(terrain), Vec3::Zero()));
  const Vec3 tip[5] = {{0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  const Shape hull = Shape::convex_hull(
      std::make_shared<const ConvexHull>(ConvexHull::from_points(std::span(tip, 5))));
  const Shape shapes[4] = {Shape::box(Vec3(0.5, 0.4, 0.3)), Shape::sphere(0.45),
                           Shape::capsule(0.3, 0.4), hull};
  const Real spacing = 2.2;
  for (int i = 0; i < grid; ++i) {
    for (int j = 0; j < grid; ++j) {
      const Vec3 at((i - 0.5 * (grid - 1)) * spacing, (j - 0.5 * (grid - 1)) * spacing,
                    1.5 + 0.25 * ((i * 7 + j * 3) % 5));
      BodyDesc b = dynamic_body("body", shapes[(i + j) % 4], at, Vec3(0, 0, -14), 2);
      b.angular_velocity = Vec3(0.3 * (i % 3), -0.2 * (j % 4), 0.1);
      s.bodies.push_back(b);
    }
  }
  return std::make_shared<const Scene>(std::move(s));
}

// Spheres raining on a plane, a little bouncy, sleeping on: the sphere batch, impacts and
// islands falling asleep.
std::shared_ptr<const Scene> sphere_rain(int side, int layers) {
  Scene s;
  s.materials.push_back(Material{"default", 0.4, 0.3});
  s.world.sleeping = true;
  s.bodies.push_back(static_body("ground", Shape::plane(), Vec3::Zero()));
  for (int k = 0; k < layers; ++k) {
    for (int i = 0; i < side; ++i) {
      for (int j = 0; j < side; ++j) {
        // Layers offset by a third of a radius so that the spheres roll off one another.
        const Vec3 at(i * 1.0 + 0.15 * (k % 2), j * 1.0 + 0.1 * (k % 3), 0.5 + 1.05 * k);
        s.bodies.push_back(dynamic_body("ball", Shape::sphere(0.5), at, Vec3::Zero(), 1));
      }
    }
  }
  return std::make_shared<const Scene>(std::move(s));
}

struct Stepping {
  std::vector<std::uint64_t> hashes;  // after each step
  std::int64_t split_loops = 0;
  std::int64_t swept_bodies = 0;
};

Stepping run(const std::shared_ptr<const Scene>& scene, int threads, int steps) {
  Simulation world(scene);
  world.set_threads(threads);
  EXPECT_EQ(world.threads(), threads);
  Stepping r;
  for (int k = 0; k < steps; ++k) {
    world.step();
    r.hashes.push_back(world.state_hash());
    r.split_loops += world.last_step_statistics().split_loops;
    r.swept_bodies += world.last_step_statistics().swept_bodies;
  }
  return r;
}

Stepping expect_same_bits_on_any_thread_count(const std::shared_ptr<const Scene>& scene,
                                              int steps) {
  const Stepping one = run(scene, 1, steps);
  EXPECT_EQ(one.split_loops, 0);
  for (const int threads : {2, 4}) {
    const Stepping many = run(scene, threads, steps);
    // The scene is large enough that the step did split its loops.
    EXPECT_GT(many.split_loops, steps) << threads << " threads";
    for (int k = 0; k < steps; ++k) {
      EXPECT_EQ(many.hashes[std::size_t(k)], one.hashes[std::size_t(k)])
          << threads << " threads, step " << k + 1;
      if (many.hashes[std::size_t(k)] != one.hashes[std::size_t(k)])
        break;  // the first step that differs is the one to look at
    }
  }
  return one;
}

TEST(ThreadCount, PyramidFieldGivesTheSameBitsOnOneTwoAndFourThreads) {
  expect_same_bits_on_any_thread_count(pyramid_field(3, 8), scaled(40));
}

TEST(ThreadCount, ShapesOnATerrainGiveTheSameBitsOnOneTwoAndFourThreads) {
  const Stepping one = expect_same_bits_on_any_thread_count(shapes_on_terrain(24, 16), scaled(60));
  EXPECT_GT(one.swept_bodies, 100) << "continuous collision's queries ran";
}

TEST(ThreadCount, SphereRainWithSleepingGivesTheSameBitsOnOneTwoAndFourThreads) {
  expect_same_bits_on_any_thread_count(sphere_rain(12, 3), scaled(80));
}

}  // namespace
}  // namespace tumble::test
