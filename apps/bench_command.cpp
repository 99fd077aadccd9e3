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
#include "apps/scene_access.hpp"
#include "apps/spread.hpp"
#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble::app {
namespace {

using Clock = std::chrono::steady_clock;

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
  summary << "scene,sleeping,bodies,steps,repetitions,engine,threads,min_ms,median_ms,max_ms,"
             "mean_ms,ratio_median_tumble_over_bullet";
  for (int k = 0; k < kStageCount; ++k)
    summary << ",tumble_" << stage_name(static_cast<Stage>(k)) << "_ms";
  for (int k = 0; k < kSolvePhaseCount; ++k)
    summary << ",tumble_solve_" << solve_phase_name(static_cast<SolvePhase>(k)) << "_ms";
  summary << ",tumble_ns_per_point_pass,tumble_ns_per_narrow_phase_pair,"
             "tumble_contact_points_per_step,tumble_max_substeps,tumble_bytes_per_body,"
             "tumble_bytes_per_contact_point,tumble_speedup_over_one_thread,"
             "tumble_recycled_pair_share,tumble_ns_per_recycled_pair,"
             "tumble_ns_per_recomputed_pair\n";

  // tumble's runs at one thread count.
  struct TumbleRuns {
    int threads = 1;
    std::vector<double> step_seconds;
    StepStatistics totals;
    WorldMemory memory;
  };
  for (const auto& path : scenes) {
    // Each scene twice: sleeping off in both engines, then on in both (tumble's
    // world.sleeping, Bullet's default deactivation).
    for (const bool sleeping : {false, true}) {
      auto scene = std::make_shared<Scene>(load_scene_file(path, {}, scene_load_options()));
      scene->world.sleeping = sleeping;
      const std::int64_t steps = options.steps ? *options.steps : scene_steps(*scene);
      std::vector<TumbleRuns> tumble;
      for (const int threads : options.threads)
        tumble.push_back(TumbleRuns{threads, {}, {}, {}});
      std::vector<double> bullet_steps;
      std::ostringstream per_step;
      per_step << "engine,threads,repetition,step,seconds\n";
      // Per repetition: Bullet, then tumble at each thread count, or the reverse, alternating so
      // that neither engine always gets the warm cache.
      const int turns = static_cast<int>(tumble.size()) + 1;
      for (int rep = 0; rep < options.repetitions; ++rep) {
        for (int turn = 0; turn < turns; ++turn) {
          const int slot = rep % 2 == 0 ? turn : turns - 1 - turn;  // 0 = Bullet
          if (slot > 0) {
            TumbleRuns& runs = tumble[std::size_t(slot - 1)];
            Simulation world(scene);
            world.set_threads(runs.threads);
            for (std::int64_t k = 1; k <= steps; ++k) {
              const auto t0 = Clock::now();
              world.step();
              const double s = std::chrono::duration<double>(Clock::now() - t0).count();
              runs.step_seconds.push_back(s);
              per_step << "tumble," << runs.threads << ',' << rep << ',' << k << ',';
              write_number(per_step, s);
              per_step << '\n';
              runs.totals.accumulate(world.last_step_statistics());
            }
            runs.memory = world.memory();
          } else if (with_bullet) {
            BulletSettings settings = benchmark_bullet_settings(*scene);
            settings.sleeping = sleeping;
            BulletWorld bullet(*scene, settings);
            for (std::int64_t k = 1; k <= steps; ++k) {
              const auto t0 = Clock::now();
              bullet.step();
              const double s = std::chrono::duration<double>(Clock::now() - t0).count();
              bullet_steps.push_back(s);
              per_step << "bullet,1," << rep << ',' << k << ',';
              write_number(per_step, s);
              per_step << '\n';
            }
          }
        }
      }
      const Spread b = spread_of(bullet_steps);
      const std::string name = path.stem().string();
      const std::string label = name + (sleeping ? " (sleeping on)" : " (sleeping off)");
      std::cout << label << ": " << scene->bodies.size() << " bodies, " << steps << " steps x "
                << options.repetitions << " repetitions\n";
      if (with_bullet) {
        std::cout << "  Bullet step time  min " << ms(b.min) << "  median " << ms(b.median)
                  << "  max " << ms(b.max) << " ms\n";
      }
      const auto per = [](double seconds, double count) {
        return count > 0 ? seconds / count : 0.0;
      };
      const double one_thread_median = spread_of(tumble.front().step_seconds).median;
      for (const TumbleRuns& runs : tumble) {
        const StepStatistics& totals = runs.totals;
        const Spread t = spread_of(runs.step_seconds);
        const double ratio = with_bullet && b.median > 0 ? t.median / b.median : 0;
        const double speedup = per(one_thread_median, t.median);
        const double total_steps = static_cast<double>(runs.step_seconds.size());
        const double pass_seconds =
            totals.solve_phase_seconds[static_cast<int>(SolvePhase::soft_passes)] +
            totals.solve_phase_seconds[static_cast<int>(SolvePhase::relax_passes)];
        const double ns_per_point_pass =
            1e9 * per(pass_seconds, static_cast<double>(totals.point_passes));
        const double ns_per_pair = 1e9 * per(totals.seconds[static_cast<int>(Stage::narrow_phase)],
                                             static_cast<double>(totals.candidate_pairs));
        const double points_per_step = per(static_cast<double>(totals.contact_points), total_steps);
        // Resting pairs (sleeping bodies, left out of the narrow phase) go through the sorting
        // pass with the recycled ones.
        const double all_pairs = static_cast<double>(
            totals.recycled_pairs + totals.recomputed_pairs + totals.resting_pairs);
        const double recycled_share = per(static_cast<double>(totals.recycled_pairs), all_pairs);
        const double resting_share = per(static_cast<double>(totals.resting_pairs), all_pairs);
        const double ns_per_recycled =
            1e9 * per(totals.recycle_seconds,
                      static_cast<double>(totals.recycled_pairs + totals.resting_pairs));
        const double ns_per_recomputed =
            1e9 * per(totals.recompute_seconds, static_cast<double>(totals.recomputed_pairs));
        const double bytes_per_body = per(static_cast<double>(runs.memory.body_bytes),
                                          static_cast<double>(scene->bodies.size()));
        const double bytes_per_point =
            per(static_cast<double>(runs.memory.contact_bytes + runs.memory.scratch_bytes),
                points_per_step);
        std::cout << "  tumble, " << runs.threads << (runs.threads == 1 ? " thread" : " threads")
                  << ": step time  min " << ms(t.min) << "  median " << ms(t.median) << "  max "
                  << ms(t.max) << " ms";
        if (runs.threads != tumble.front().threads) {
          std::cout << "  (x" << speedup << " the " << tumble.front().threads
                    << "-thread throughput)";
        }
        std::cout << "\n";
        if (with_bullet)
          std::cout << "    ratio tumble / Bullet (median): " << ratio << " (aim: <= 0.2)\n";
        std::cout << "    stages (mean ms per step):";
        for (int j = 0; j < kStageCount; ++j) {
          std::cout << ' ' << stage_name(static_cast<Stage>(j)) << ' '
                    << ms(totals.seconds[std::size_t(j)] / total_steps);
        }
        std::cout << "\n    solve phases (mean ms per step):";
        for (int j = 0; j < kSolvePhaseCount; ++j) {
          std::cout << ' ' << solve_phase_name(static_cast<SolvePhase>(j)) << ' '
                    << ms(totals.solve_phase_seconds[std::size_t(j)] / total_steps);
        }
        std::cout << "\n    " << points_per_step << " contact points per step, "
                  << ns_per_point_pass << " ns per point per pass, " << ns_per_pair
                  << " ns per narrow-phase pair, substeps up to " << totals.max_substeps << ", "
                  << bytes_per_body << " bytes per body, " << bytes_per_point
                  << " bytes per contact point\n    narrow phase: " << 100 * recycled_share
                  << "% of pairs recycled, " << 100 * resting_share << "% resting, "
                  << ns_per_recycled << " ns per recycled or resting pair (with "
                  << "sorting the candidates), " << ns_per_recomputed
                  << " ns per recomputed pair\n";
        summary << name << ',' << (sleeping ? "on" : "off") << ',' << scene->bodies.size() << ','
                << steps << ',' << options.repetitions << ",tumble," << runs.threads << ','
                << ms(t.min) << ',' << ms(t.median) << ',' << ms(t.max) << ',' << ms(t.mean) << ','
                << ratio;
        for (int j = 0; j < kStageCount; ++j)
          summary << ',' << ms(totals.seconds[std::size_t(j)] / total_steps);
        for (int j = 0; j < kSolvePhaseCount; ++j)
          summary << ',' << ms(totals.solve_phase_seconds[std::size_t(j)] / total_steps);
        summary << ',' << ns_per_point_pass << ',' << ns_per_pair << ',' << points_per_step << ','
                << totals.max_substeps << ',' << bytes_per_body << ',' << bytes_per_point << ','
                << speedup << ',' << recycled_share << ',' << ns_per_recycled << ','
                << ns_per_recomputed << "\n";
      }
      if (with_bullet) {
        summary << name << ',' << (sleeping ? "on" : "off") << ',' << scene->bodies.size() << ','
                << steps << ',' << options.repetitions << ",bullet,1," << ms(b.min) << ','
                << ms(b.median) << ',' << ms(b.max) << ',' << ms(b.mean) << ',';
        for (int j = 0; j < kStageCount + kSolvePhaseCount + 10; ++j)
          summary << ',';
        summary << "\n";
      }
      write_file_atomically(
          options.output_dir / (name + (sleeping ? "_sleeping" : "") + "_steps.csv"),
          per_step.str());
    }
  }
  write_file_atomically(options.output_dir / "oracle_bench.csv", summary.str());
  std::cout << "CSV: " << (options.output_dir / "oracle_bench.csv").string() << "\n";
  return 0;
}

}  // namespace tumble::app
