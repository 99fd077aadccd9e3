// Signed distance fields and distance gradients (docs/sdf.md): ns per SDF sample (a primitive, a
// placed primitive, CSG trees of growing size, the smooth union), and the cost of the distance
// gradients of distance_between relative to the distance alone, per pair type.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "collision/sdf/sdf_tree.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "tumble/distance.hpp"

namespace tumble {
namespace {

std::vector<Vec3> sample_points(int count) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<Real> u(-2, 2);
  std::vector<Vec3> points(static_cast<std::size_t>(count));
  for (Vec3& p : points)
    p = Vec3(u(rng), u(rng), u(rng));
  return points;
}

void run_samples(benchmark::State& state, const SdfTree& tree) {
  const std::vector<Vec3> points = sample_points(4096);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(tree.sample(points[i]));
    i = (i + 1) & 4095;
  }
}

void BM_SdfSphere(benchmark::State& state) {
  run_samples(state, SdfTree(SdfNode::sphere(1)));
}
BENCHMARK(BM_SdfSphere);

void BM_SdfPlacedTorus(benchmark::State& state) {
  const Quat q = Quat(Eigen::AngleAxis<Real>(0.7, Vec3(1, 2, 3).normalized()));
  run_samples(state, SdfTree(SdfNode::torus(1, 0.25).placed({Vec3(0.1, 0.2, 0.3), q})));
}
BENCHMARK(BM_SdfPlacedTorus);

// A union of n placed boxes (n = 2, 8, 32): the cost grows with the operands.
void BM_SdfUnionOfBoxes(benchmark::State& state) {
  std::vector<SdfNode> boxes;
  for (int i = 0; i < state.range(0); ++i)
    boxes.push_back(SdfNode::box(Vec3(0.3, 0.2, 0.1))
                        .placed({Vec3(0.1 * i - 1, 0.05 * i, 0), Quat::Identity()}));
  run_samples(state, SdfTree(SdfNode::combine(SdfKind::union_of, boxes)));
}
BENCHMARK(BM_SdfUnionOfBoxes)->Arg(2)->Arg(8)->Arg(32);

void BM_SdfSmoothUnion(benchmark::State& state) {
  run_samples(state, SdfTree(SdfNode::combine(
                         SdfKind::smooth_union_of,
                         {SdfNode::sphere(0.5),
                          SdfNode::capsule(0.2, 0.6).placed({Vec3(0.3, 0, 0), Quat::Identity()})},
                         8)));
}
BENCHMARK(BM_SdfSmoothUnion);

// The bowl of docs/sdf.md: a box minus a sphere.
void BM_SdfBowl(benchmark::State& state) {
  run_samples(state, SdfTree(SdfNode::combine(
                         SdfKind::difference_of,
                         {SdfNode::box(Vec3(1, 1, 0.5)),
                          SdfNode::sphere(0.9).placed({Vec3(0, 0, 0.6), Quat::Identity()})})));
}
BENCHMARK(BM_SdfBowl);

Shape shape_of(int kind) {
  switch (kind) {
    case 0:
      return Shape::sphere(0.5);
    case 1:
      return Shape::box(Vec3(0.5, 0.3, 0.2));
    case 2:
      return Shape::cylinder(0.4, 0.5);
    default: {
      std::mt19937_64 rng(3);
      std::normal_distribution<Real> n(0, 1);
      std::vector<Vec3> points(24);
      for (Vec3& p : points)
        p = Vec3(n(rng), n(rng), n(rng)).normalized() * 0.5;
      return hull_from_points(points);
    }
  }
}

// distance_between for a box against a sphere, a box, a cylinder and a hull (range 0..3), the
// partner placed in a ring of poses half of which penetrate; with and without gradients.
void run_distance(benchmark::State& state, bool gradients) {
  const Shape a = Shape::box(Vec3(0.5, 0.4, 0.3));
  const Shape b = shape_of(int(state.range(0)));
  std::vector<Transform> poses;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (int i = 0; i < 256; ++i) {
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    poses.push_back({dir * (0.6 + 0.8 * (i % 2)),
                     Quat(Eigen::AngleAxis<Real>(u(rng) * 3, dir.unitOrthogonal()))});
  }
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(distance_between(a, Transform{}, b, poses[i], gradients));
    i = (i + 1) & 255;
  }
}

void BM_DistanceOnly(benchmark::State& state) {
  run_distance(state, false);
}
void BM_DistanceWithGradients(benchmark::State& state) {
  run_distance(state, true);
}
BENCHMARK(BM_DistanceOnly)->DenseRange(0, 3);
BENCHMARK(BM_DistanceWithGradients)->DenseRange(0, 3);

}  // namespace
}  // namespace tumble

BENCHMARK_MAIN();
