#include "apps/bench_command.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "apps/atomic_file.hpp"
#include "apps/bullet_bridge.hpp"
#include "apps/compare_command.hpp"
#include "apps/number_format.hpp"
#include "engine/world.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble::app {
namespace {

using Clock = std::chrono::steady_clock;

struct Spread {
  double min = 0, median = 0, max = 0, mean = 0;
};

Spread spread_of(std::vector<double> v) {
  Spread s;
  if (v.empty())
    return s;
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.max = v.back();
  const std::size_t n = v.size();
  s.median = n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  double total = 0;
  for (double x : v)
    total += x;
  s.mean = total / static_cast<double>(n);
  return s;
}

// Bullet as its own benchmark demos run it: one internal step per step, 10 iterations, split
// impulse. Matching tumble's substeps would make Bullet collide four times per step and so
// flatter tumble; the accuracy each buys is in the reports (docs/reports/).
BulletSettings bench_bullet_settings(const Scene& scene) {
  BulletSettings s;
  s.dt = scene.world.dt;
  s.substeps = 1;
  s.iterations = 10;
  s.restitution_threshold = scene.world.restitution_threshold;
  return s;
}

std::string ms(double seconds) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3f", seconds * 1e3);
  return buffer;
}

}  // namespace

int bench_command(const BenchOptions& options) {
  std::vector<std::filesystem::path> scenes = options.scenes;
  if (scenes.empty()) {
    const std::filesystem::path dir = "scenes/bench";
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
      if (e.path().extension() == ".yaml")
        scenes.push_back(e.path());
    }
    if (ec || scenes.empty()) {
      std::cerr << "tumble bench: no scenes given and none found in " << dir.string()
                << " (run from the repository root or name the scenes)\n";
      return 1;
    }
    std::sort(scenes.begin(), scenes.end());
  }
  const bool with_bullet = bullet_available();
  if (!with_bullet) {
    std::cerr << "tumble bench: this build has no Bullet (configure with -DTUMBLE_WITH_BULLET=ON "
                 "and the bullet-float64 package); timing tumble alone\n";
  }
  std::error_code ec;
  std::filesystem::create_directories(options.output_dir, ec);
  if (ec) {
    std::cerr << "tumble bench: " << options.output_dir.string()
              << ": cannot create output directory (" << ec.message() << ")\n";
    return 1;
  }

  std::ostringstream summary;
  summary << "scene,bodies,steps,repetitions,engine,min_ms,median_ms,max_ms,mean_ms,"
             "ratio_median_tumble_over_bullet";
  for (int k = 0; k < kStageCount; ++k)
    summary << ",tumble_" << stage_name(static_cast<Stage>(k)) << "_ms";
  summary << "\n";

  for (const auto& path : scenes) {
    auto scene = std::make_shared<Scene>(load_scene_file(path));
    const std::int64_t steps = options.steps ? *options.steps : scene_steps(*scene);
    std::vector<double> tumble_steps, bullet_steps;
    std::array<double, kStageCount> stage_seconds{};
    std::ostringstream per_step;
    per_step << "engine,repetition,step,seconds\n";
    for (int rep = 0; rep < options.repetitions; ++rep) {
      // Alternate which engine runs first, so neither always gets the warm cache.
      for (int turn = 0; turn < 2; ++turn) {
        const bool tumble_turn = (turn == 0) == (rep % 2 == 0);
        if (tumble_turn) {
          World world(scene);
          for (std::int64_t k = 1; k <= steps; ++k) {
            const auto t0 = Clock::now();
            world.step();
            const double s = std::chrono::duration<double>(Clock::now() - t0).count();
            tumble_steps.push_back(s);
            per_step << "tumble," << rep << ',' << k << ',';
            write_number(per_step, s);
            per_step << '\n';
            const StepStatistics& st = world.last_step_statistics();
            for (int j = 0; j < kStageCount; ++j)
              stage_seconds[j] += st.seconds[j];
          }
        } else if (with_bullet) {
          BulletWorld bullet(*scene, bench_bullet_settings(*scene));
          for (std::int64_t k = 1; k <= steps; ++k) {
            const auto t0 = Clock::now();
            bullet.step();
            const double s = std::chrono::duration<double>(Clock::now() - t0).count();
            bullet_steps.push_back(s);
            per_step << "bullet," << rep << ',' << k << ',';
            write_number(per_step, s);
            per_step << '\n';
          }
        }
      }
    }
    const Spread t = spread_of(tumble_steps);
    const Spread b = spread_of(bullet_steps);
    const double ratio = with_bullet && b.median > 0 ? t.median / b.median : 0;
    const std::string name = path.stem().string();
    const double total_steps = static_cast<double>(tumble_steps.size());
    std::cout << name << ": " << scene->bodies.size() << " bodies, " << steps << " steps x "
              << options.repetitions << " repetitions\n"
              << "  tumble step time  min " << ms(t.min) << "  median " << ms(t.median) << "  max "
              << ms(t.max) << " ms\n";
    if (with_bullet) {
      std::cout << "  Bullet step time  min " << ms(b.min) << "  median " << ms(b.median)
                << "  max " << ms(b.max) << " ms\n"
                << "  ratio tumble / Bullet (median): " << ratio << " (aim: <= 0.333)\n";
    }
    std::cout << "  tumble stages (mean ms per step):";
    for (int j = 0; j < kStageCount; ++j) {
      std::cout << ' ' << stage_name(static_cast<Stage>(j)) << ' '
                << ms(stage_seconds[j] / total_steps);
    }
    std::cout << "\n";
    for (int e = 0; e < (with_bullet ? 2 : 1); ++e) {
      const Spread& s = e == 0 ? t : b;
      summary << name << ',' << scene->bodies.size() << ',' << steps << ',' << options.repetitions
              << ',' << (e == 0 ? "tumble" : "bullet") << ',' << ms(s.min) << ',' << ms(s.median)
              << ',' << ms(s.max) << ',' << ms(s.mean) << ',' << ratio;
      for (int j = 0; j < kStageCount; ++j)
        summary << ',' << (e == 0 ? ms(stage_seconds[j] / total_steps) : std::string());
      summary << "\n";
    }
    write_file_atomically(options.output_dir / (name + "_steps.csv"), per_step.str());
  }
  write_file_atomically(options.output_dir / "oracle_bench.csv", summary.str());
  std::cout << "CSV: " << (options.output_dir / "oracle_bench.csv").string() << "\n";
  return 0;
}

}  // namespace tumble::app
