// Resetting a batch of worlds (docs/rl.md, "Reset"): 1024 worlds of PushBoxEnv's world
// (python/tumble/envs.py: a table, two obstacles, a box and a kinematic pusher) reset together,
// with its randomize block (each reset draws and compiles a new model) and without (the initial
// state put back). items_per_second counts world resets (1e6 / it is microseconds per world); the
// thread count is the argument.
#include <benchmark/benchmark.h>

#include <memory>
#include <numeric>
#include <vector>

#include "scenes/scene_loader.hpp"
#include "tumble/batch_world.hpp"

namespace {

constexpr int kWorlds = 1024;

std::shared_ptr<const tumble::Scene> push_box_scene(bool randomized) {
  std::string text = R"(
world: {dt: 0.016666666666666666, gravity: [0, 0, -9.81]}
materials:
  table: {friction: 0.6}
bodies:
  - {name: table, static: true, material: table,
     shape: {type: box, half_extents: [1.0, 1.0, 0.05]}, position: [0, 0, -0.05]}
  - {name: obstacle_left, static: true,
     shape: {type: box, half_extents: [0.1, 0.1, 0.1]}, position: [0.35, 0.4, 0.1]}
  - {name: obstacle_right, static: true,
     shape: {type: box, half_extents: [0.1, 0.1, 0.1]}, position: [0.35, -0.4, 0.1]}
  - {name: box, density: 250, shape: {type: box, half_extents: [0.1, 0.1, 0.1]},
     position: [0, 0, 0.13]}
  - {name: pusher, kinematic: true,
     shape: {type: box, half_extents: [0.05, 0.15, 0.08]}, position: [-0.3, 0, 0.09]}
)";
  if (randomized)
    text += R"(
randomize:
  friction: [0.4, 0.9]
  mass_scale: [0.7, 1.4]
  size_noise: 0.02
  position_noise: 0.01
  orientation_noise: 0.05
)";
  return std::make_shared<const tumble::Scene>(tumble::load_scene_string(text, "push_box.yaml"));
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
