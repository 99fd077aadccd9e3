// Triangle-mesh queries: the BVH box query against a scan of every triangle's box, and a box
// resting on a flat grid mesh through the narrow phase (BVH query, per-triangle SAT, merge).
// Sizes: grids of n x n cells (2 n^2 triangles).
#include <benchmark/benchmark.h>

#include <memory>
#include <random>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/shapes/triangle_mesh.hpp"

namespace tumble {
namespace {

TriangleMesh bumpy_grid(int n) {
  std::vector<Vec3> v;
  std::vector<TriangleMesh::Triangle> t;
  const Real cell = 10.0 / n;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      v.emplace_back(i * cell - 5, j * cell - 5, 0.2 * std::sin(i * 0.7) * std::cos(j * 0.3));
  const auto at = [n](int i, int j) { return std::int32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      t.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      t.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return TriangleMesh::build(v, t);
}

std::vector<Aabb> query_boxes() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<Real> pos(-5, 5);
  std::vector<Aabb> boxes;
  for (int i = 0; i < 256; ++i) {
    const Vec3 c(pos(rng), pos(rng), 0);
    boxes.push_back({c - Vec3(0.3, 0.3, 0.3), c + Vec3(0.3, 0.3, 0.3)});
  }
  return boxes;
}

void bvh_query(benchmark::State& state) {
  const TriangleMesh mesh = bumpy_grid(int(state.range(0)));
  const std::vector<Aabb> boxes = query_boxes();
  std::size_t k = 0;
  long found = 0;
  for (auto _ : state) {
    mesh.for_each_overlapping(boxes[k++ % boxes.size()], [&](int) { ++found; });
    benchmark::DoNotOptimize(found);
  }
  state.counters["triangles"] = mesh.triangle_count();
}

void brute_query(benchmark::State& state) {
  const TriangleMesh mesh = bumpy_grid(int(state.range(0)));
  const std::vector<Aabb> boxes = query_boxes();
  std::size_t k = 0;
  long found = 0;
  for (auto _ : state) {
    const Aabb& box = boxes[k++ % boxes.size()];
    for (int t = 0; t < mesh.triangle_count(); ++t) {
      Aabb tb;
      for (int c = 0; c < 3; ++c)
        tb.grow(mesh.corner(t, c));
      found += tb.overlaps(box);
    }
    benchmark::DoNotOptimize(found);
  }
  state.counters["triangles"] = mesh.triangle_count();
}

void box_on_mesh(benchmark::State& state) {
  const Shape mesh =
      Shape::triangle_mesh(std::make_shared<const TriangleMesh>(bumpy_grid(int(state.range(0)))));
  const Shape box = Shape::box({0.4, 0.3, 0.2});
  const std::vector<Aabb> boxes = query_boxes();
  std::size_t k = 0;
  Manifold m;
  for (auto _ : state) {
    const Aabb& b = boxes[k++ % boxes.size()];
    const Vec3 c = (b.min + b.max) / 2;
    benchmark::DoNotOptimize(
        collide(box, {Vec3(c.x(), c.y(), 0.15), Quat::Identity()}, mesh, Transform{}, 0.01, m));
  }
}

BENCHMARK(bvh_query)->Arg(20)->Arg(100)->Arg(300);
BENCHMARK(brute_query)->Arg(20)->Arg(100)->Arg(300);
BENCHMARK(box_on_mesh)->Arg(20)->Arg(300);

}  // namespace
}  // namespace tumble

BENCHMARK_MAIN();
