// Resetting a batch of worlds (docs/rl.md): 1024 worlds of PushBoxEnv's world (python/tumble/
// envs.py: a table, two obstacles, a box and a kinematic pusher) reset together,
// with its randomize block (each reset draws and compiles a new model) and without (the initial
// state put back). items_per_second counts world resets (1e6 / it is microseconds per world); the
// thread count is the argument.
#include <benchmark/benchmark.h>

#include <memory>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "scenes/scene_loader.hpp"
#include "tumble/batch_world.hpp"

namespace {

constexpr int kWorlds = 1024;

// tests/data/scenes/push_box.yaml: PushBoxEnv's world with its randomize block, which the plain
// reset leaves out.
std::shared_ptr<const tumble::Scene> push_box_scene(bool randomized) {
  tumble::Scene scene =
      tumble::load_scene_file(std::string(TUMBLE_SOURCE_DIR) + "/tests/data/scenes/push_box.yaml");
  if (!randomized)
    scene.randomize = {};
  return std::make_shared<const tumble::Scene>(std::move(scene));
}

void reset_all(benchmark::State& state, bool randomized) {
  tumble::BatchWorld batch(push_box_scene(randomized), kWorlds, int(state.range(0)), 0);
  std::vector<int> ids(kWorlds);
  std::iota(ids.begin(), ids.end(), 0);
  for (auto _ : state)
    batch.reset(ids);
  state.SetItemsProcessed(state.iterations() * kWorlds);
}

void BM_RandomizedReset(benchmark::State& state) {
  reset_all(state, true);
}
void BM_PlainReset(benchmark::State& state) {
  reset_all(state, false);
}

}  // namespace

BENCHMARK(BM_RandomizedReset)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlainReset)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
