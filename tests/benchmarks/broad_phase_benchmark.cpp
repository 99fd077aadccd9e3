// Broad-phase benchmark: every tumble structure and Bullet's btDbvtBroadphase and
// bt32BitAxisSweep3 in the same binary, on the same boxes, moving coherently each frame. One
// iteration is one frame: update every box, then find all overlapping pairs.
//
// Run: bench_broad_phase --benchmark_out=results.json --benchmark_out_format=json
// scripts/broad_phase_report.sh turns the results into docs/broad-phase-benchmark.md and a plot.
#include <benchmark/benchmark.h>
#include <btBulletCollisionCommon.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "collision/broad_phase/broad_phase_factory.hpp"

namespace tumble::bench {
namespace {

enum class Layout { uniform, clustered, mixed };
const char* layout_name(Layout l) {
  return l == Layout::uniform ? "uniform" : l == Layout::clustered ? "clustered" : "mixed";
}

// N boxes whose region grows with cbrt(N), so that the density, and so the pairs per box, stay
// the same whatever N; each box drifts with its own small velocity and bounces off the walls of
// its home region (the whole region, or its cluster), so a layout keeps its character.
class MovingBoxes {
 public:
  MovingBoxes(Layout layout, int n) : extent_(Real(2.5) * std::cbrt(Real(n))) {
    std::mt19937_64 rng(42);
    auto u = [&](Real a, Real b) { return std::uniform_real_distribution<Real>(a, b)(rng); };
    const Vec3 clusters[4] = {Vec3(-0.6, -0.6, 0), Vec3(0.6, 0.5, 0.2), Vec3(0, 0.6, -0.6),
                              Vec3(-0.5, 0.4, 0.6)};
    for (int i = 0; i < n; ++i) {
      Vec3 c;
      Vec3 h;
      Vec3 home = Vec3::Zero();
      Real home_extent = extent_;
      switch (layout) {
        case Layout::uniform:
          c = Vec3(u(-1, 1), u(-1, 1), u(-1, 1)) * extent_;
          h = Vec3(u(0.5, 1.5), u(0.5, 1.5), u(0.5, 1.5));
          break;
        case Layout::clustered: {
          // Four clusters each a tenth of the region across: dense.
          home = clusters[i % 4] * extent_;
          home_extent = Real(0.1) * extent_;
          c = home + Vec3(u(-1, 1), u(-1, 1), u(-1, 1)) * home_extent;
          h = Vec3(u(0.2, 0.5), u(0.2, 0.5), u(0.2, 0.5));
          break;
        }
        case Layout::mixed: {
          c = Vec3(u(-1, 1), u(-1, 1), u(-1, 1)) * extent_;
          const Real s = std::pow(Real(10), u(-1.5, 0.8));  // 0.03 .. 6.3
          h = Vec3(s * u(0.5, 1), s * u(0.5, 1), s * u(0.5, 1));
          break;
        }
      }
      homes_.push_back(home);
      home_extents_.push_back(home_extent);
      centres_.push_back(c);
      halves_.push_back(h);
      velocities_.push_back(Vec3(u(-1, 1), u(-1, 1), u(-1, 1)) * Real(0.05));
    }
  }

  void advance() {
    for (std::size_t i = 0; i < centres_.size(); ++i) {
      centres_[i] += velocities_[i];
      for (int k = 0; k < 3; ++k) {
        const Real offset = centres_[i][k] - homes_[i][k];
        if (std::abs(offset) > home_extents_[i] && offset * velocities_[i][k] > 0) {
          velocities_[i][k] = -velocities_[i][k];
        }
      }
    }
  }
  int size() const { return static_cast<int>(centres_.size()); }
  Aabb box(int i) const { return {centres_[i] - halves_[i], centres_[i] + halves_[i]}; }
  Real extent() const { return extent_; }

 private:
  Real extent_;
  std::vector<Vec3> centres_, halves_, velocities_, homes_;
  std::vector<Real> home_extents_;
};

void run_tumble(benchmark::State& state, BroadPhaseType type, Layout layout) {
  MovingBoxes boxes(layout, static_cast<int>(state.range(0)));
  auto bp = make_broad_phase(type);
  for (int i = 0; i < boxes.size(); ++i)
    bp->insert(i, boxes.box(i), false);
  std::vector<ProxyPair> pairs;
  bp->find_pairs(pairs);
  // Pairs at the first frame, where every structure and engine sees the same boxes (later
  // frames differ because each benchmark runs its own number of frames).
  state.counters["pairs"] = static_cast<double>(pairs.size());
  for (auto _ : state) {
    boxes.advance();
    for (int i = 0; i < boxes.size(); ++i)
      bp->update(i, boxes.box(i));
    bp->find_pairs(pairs);
    benchmark::DoNotOptimize(pairs.data());
  }
}

btVector3 bt(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

enum class BulletKind { dbvt, sweep };

void run_bullet(benchmark::State& state, BulletKind kind, Layout layout) {
  MovingBoxes boxes(layout, static_cast<int>(state.range(0)));
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  std::unique_ptr<btBroadphaseInterface> bp;
  const Vec3 bound = Vec3::Constant(boxes.extent() * 2 + 20);
  if (kind == BulletKind::dbvt) {
    bp = std::make_unique<btDbvtBroadphase>();
  } else {
    bp = std::make_unique<bt32BitAxisSweep3>(bt(-bound), bt(bound), boxes.size() + 16);
  }
  std::vector<btBroadphaseProxy*> proxies;
  for (int i = 0; i < boxes.size(); ++i) {
    const Aabb b = boxes.box(i);
    proxies.push_back(bp->createProxy(bt(b.min), bt(b.max), BOX_SHAPE_PROXYTYPE, nullptr,
                                      int(btBroadphaseProxy::DefaultFilter),
                                      int(btBroadphaseProxy::AllFilter), &dispatcher));
  }
  bp->calculateOverlappingPairs(&dispatcher);
  // Bullet's pairs come from its own enlarged boxes (btDbvtBroadphase fattens leaves,
  // btAxisSweep3 quantises), so the count is a superset of the exact one.
  state.counters["pairs"] = bp->getOverlappingPairCache()->getNumOverlappingPairs();
  for (auto _ : state) {
    boxes.advance();
    for (int i = 0; i < boxes.size(); ++i) {
      const Aabb b = boxes.box(i);
      bp->setAabb(proxies[i], bt(b.min), bt(b.max), &dispatcher);
    }
    bp->calculateOverlappingPairs(&dispatcher);
    benchmark::ClobberMemory();
  }
  for (btBroadphaseProxy* p : proxies)
    bp->destroyProxy(p, &dispatcher);
}

void register_all() {
  const std::vector<std::int64_t> sizes = {1000, 10000, 100000};
  for (Layout layout : {Layout::uniform, Layout::clustered, Layout::mixed}) {
    for (BroadPhaseType type : concrete_broad_phases()) {
      const std::string name =
          std::string("tumble/") + std::string(broad_phase_name(type)) + "/" + layout_name(layout);
      auto* b = benchmark::RegisterBenchmark(name.c_str(), run_tumble, type, layout);
      for (std::int64_t n : sizes) {
        // All-pairs brute force at 100k boxes is 5e9 tests a frame: not worth a benchmark.
        if (type == BroadPhaseType::brute && n > 10000)
          continue;
        b->Arg(n);
      }
      b->Unit(benchmark::kMillisecond);
    }
    for (BulletKind kind : {BulletKind::dbvt, BulletKind::sweep}) {
      const std::string name =
          std::string("bullet/") +
          (kind == BulletKind::dbvt ? "btDbvtBroadphase" : "bt32BitAxisSweep3") + "/" +
          layout_name(layout);
      auto* b = benchmark::RegisterBenchmark(name.c_str(), run_bullet, kind, layout);
      for (std::int64_t n : sizes) {
        // bt32BitAxisSweep3 inserts each new proxy into its sorted endpoint arrays one by one,
        // O(n) each: creating 100k proxies alone ran for minutes here, so it stops at 10k.
        if (kind == BulletKind::sweep && n > 10000)
          continue;
        b->Arg(n);
      }
      b->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace
}  // namespace tumble::bench

int main(int argc, char** argv) {
  tumble::bench::register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
