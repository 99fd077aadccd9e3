// Signed distance fields and distance gradients (docs/sdf.md): ns per SDF sample (a primitive, a
// placed primitive, CSG trees of growing size, the smooth union, a grid trilinear and tricubic, a
// network of the committed fit's size), the cost of an SDF contact against the analytic or GJK/EPA
// contact of the same two shapes, and the cost of the distance gradients of distance_between
// relative to the distance alone, per pair type.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/sdf/sdf_tree.hpp"
#include "collision/sdf/vdb_level_set.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "tests/collision/closed_meshes.hpp"
#include "tests/collision/sampled_grid.hpp"
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

// 4,096 fixed points within 5 cm of the torus (0.4, 0.15), and a sampler of them timed.
template <class Sample>
void run_near_torus(benchmark::State& state, Sample&& sample) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<Real> u(-1, 1);
  std::vector<Vec3> points;
  while (points.size() < 4096) {
    const Vec3 p(0.6 * u(rng), 0.6 * u(rng), 0.2 * u(rng));
    if (std::abs(sdf::torus(p, 0.4, 0.15).distance) < 0.05)
      points.push_back(p);
  }
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(sample(points[i]));
    i = (i + 1) & 4095;
  }
}

// The torus gridded from its exact field at 2 cm cells.
void run_grid(benchmark::State& state, GridInterpolation how) {
  const Real cell = 0.02, half = 0.65;
  const int n = int(2 * half / cell) + 1, nz = int(2 * 0.25 / cell) + 1;
  const Vec3 origin(-half, -half, -0.25);
  const SdfGrid grid = test::sampled_grid(
      origin, cell, {n, n, nz}, [](const Vec3& p) { return sdf::torus(p, 0.4, 0.15).distance; });
  run_near_torus(state, [&](const Vec3& p) { return grid.sample(p, how); });
}
void BM_SdfGridTrilinear(benchmark::State& state) {
  run_grid(state, GridInterpolation::trilinear);
}
void BM_SdfGridTricubic(benchmark::State& state) {
  run_grid(state, GridInterpolation::tricubic);
}
BENCHMARK(BM_SdfGridTrilinear);
BENCHMARK(BM_SdfGridTricubic);

// The same torus as an OpenVDB level set of a 192 x 96 quad mesh, 2 cm voxels, a band of 3 + 2
// voxels (covering the 5 cm sampled): the sparse tree's lookups against the dense array's.
void run_level_set(benchmark::State& state, GridInterpolation how) {
  if (!VdbLevelSet::available()) {
    state.SkipWithError("this build has no OpenVDB");
    return;
  }
  std::vector<Vec3> v;
  test_meshes::Triangles t;
  test_meshes::torus_mesh(0.4, 0.15, 192, 96, v, t);
  const auto level_set = VdbLevelSet::from_mesh(v, t, 0.02, 5);
  run_near_torus(state, [&](const Vec3& p) { return level_set->sample(p, how); });
}
void BM_SdfLevelSetTrilinear(benchmark::State& state) {
  run_level_set(state, GridInterpolation::trilinear);
}
void BM_SdfLevelSetTricubic(benchmark::State& state) {
  run_level_set(state, GridInterpolation::tricubic);
}
BENCHMARK(BM_SdfLevelSetTrilinear);
BENCHMARK(BM_SdfLevelSetTricubic);

// A softplus network of the committed fit's shape (tests/data/neural: 2 bands, 3 hidden layers of
// 32), random weights: the cost does not depend on their values.
void BM_SdfNeural(benchmark::State& state) {
  std::mt19937_64 rng(10);
  std::normal_distribution<Real> w(0, 0.3);
  NeuralSdfDescription d;
  d.frequencies = 2;
  d.bounds = {Vec3::Constant(-1), Vec3::Constant(1)};
  int inputs = 3 + 6 * d.frequencies;
  for (int layer = 0; layer < 4; ++layer) {
    NeuralLayer l;
    l.inputs = inputs;
    l.outputs = layer == 3 ? 1 : 32;
    l.activation = layer == 3 ? Activation::none : Activation::softplus;
    for (int k = 0; k < l.inputs * l.outputs; ++k)
      l.weights.push_back(w(rng));
    l.bias.assign(std::size_t(l.outputs), 0.1);
    inputs = l.outputs;
    d.layers.push_back(std::move(l));
  }
  const NeuralSdf net(std::move(d));
  const std::vector<Vec3> points = sample_points(4096);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(net.sample(points[i] / 2));
    i = (i + 1) & 4095;
  }
}
BENCHMARK(BM_SdfNeural);

// One contact query of shape A (range: 0 sphere, 1 box, 2 cylinder, 3 hull) against a box of
// half extents (0.5, 0.4, 0.3), given as an SDF (state.range(1) = 1) or as the box itself (0: the
// analytic pair, box-box by SAT, cylinder-box and hull-box by GJK/EPA), at 256 poses touching it.
Shape shape_of(int kind);
void BM_Contact(benchmark::State& state) {
  const Shape a = shape_of(int(state.range(0)));
  const Vec3 half(0.5, 0.4, 0.3);
  const Shape b = state.range(1) == 1 ? sdf_shape(SdfNode::box(half)) : Shape::box(half);
  std::vector<Transform> poses;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (int i = 0; i < 256; ++i)
    poses.push_back(
        {Vec3(u(rng) * 0.4, u(rng) * 0.3, 0.3 + bounding_radius(a) * 0.9),
         Quat(Eigen::AngleAxis<Real>(u(rng) * 3, Vec3(u(rng), u(rng), 1).normalized()))});
  std::size_t i = 0;
  Manifold m;
  for (auto _ : state) {
    benchmark::DoNotOptimize(collide(a, poses[i], b, Transform{}, 0.01, m));
    i = (i + 1) & 255;
  }
}
BENCHMARK(BM_Contact)->ArgsProduct({{0, 1, 2, 3}, {0, 1}});

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

// distance_between for a box against a sphere, a box, a cylinder and a hull (range 0..3), and
// against fields (4: a box and a torus field, 5: a field ball and a torus field, 6: a plane and a
// torus field), the partner placed in a ring of poses half of which penetrate; with and without
// gradients (for fields the gradients are grad phi at the optimum the distance needs anyway).
void run_distance(benchmark::State& state, bool gradients) {
  const int kind = int(state.range(0));
  const Shape torus = sdf_shape(SdfNode::torus(0.6, 0.2));
  const Shape a = kind == 5   ? sdf_shape(SdfNode::sphere(0.3))
                  : kind == 6 ? Shape::plane()
                              : Shape::box(Vec3(0.5, 0.4, 0.3));
  const Shape b = kind >= 4 ? torus : shape_of(kind);
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
BENCHMARK(BM_DistanceOnly)->DenseRange(0, 6);
BENCHMARK(BM_DistanceWithGradients)->DenseRange(0, 6);

}  // namespace
}  // namespace tumble

BENCHMARK_MAIN();
