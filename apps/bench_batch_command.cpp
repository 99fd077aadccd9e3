// `tumble bench-batch` (apps/bench_batch_command.hpp). For each world count and thread count, the
// engines run in turn, repetition by repetition: tumble's BatchWorld, then N MuJoCo mjData, then N
// Bullet worlds, each from the scene's initial state for the same number of steps, the worlds
// spread over the same number of oneTBB threads. Only the steps are timed; building and
// resetting the worlds, and reading tumble's per-world statistics, are not.
#include "apps/bench_batch_command.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>

#include "apps/atomic_file.hpp"
#include "apps/bullet_bridge.hpp"
#include "apps/mujoco_bridge.hpp"
#include "apps/number_format.hpp"
#include "apps/scene_access.hpp"
#include "apps/spread.hpp"
#include "engine/simulation.hpp"
#include "tumble/batch_world.hpp"
#include "tumble/load_scene.hpp"

namespace tumble::app {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// One engine's repetitions at one (worlds, threads).
struct Runs {
  std::vector<double> total_seconds;       // per repetition
  std::vector<double> batch_step_seconds;  // every batch step of every repetition
  std::int64_t pairs = 0;                  // narrow-phase pairs over all repetitions (tumble)
  std::array<double, kStageCount> stage_seconds{};  // summed over worlds and steps (tumble)
  double contacts = 0;                              // mean contacts per world after the run
};

template <class Work>
void over_worlds(tbb::task_arena& arena, int threads, int worlds, const Work& work) {
  if (threads <= 1 || worlds == 1) {
    for (int w = 0; w < worlds; ++w)
      work(w);
    return;
  }
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, worlds, 1), [&](const tbb::blocked_range<int>& r) {
      for (int w = r.begin(); w < r.end(); ++w)
        work(w);
    });
  });
}

std::string machine_name() {
  std::ifstream cpu("/proc/cpuinfo");
  std::string line;
  std::ostringstream name;
  while (std::getline(cpu, line)) {
    const auto colon = line.find(':');
    if (line.rfind("model name", 0) == 0 && colon != std::string::npos) {
      name << line.substr(colon + 2) << ", ";
      break;
    }
  }
  name << std::thread::hardware_concurrency() << " hardware threads";
  return name.str();
}

// Whether glibc's malloc backs the heap with transparent huge pages (its `glibc.malloc.hugetlb`
// tunable, read at the process's start): a large batch's worlds then miss the TLB far less
// (docs/rl.md, "Memory"), so the figures depend on it.
std::string malloc_huge_pages() {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::string_view text = tunables == nullptr ? std::string_view() : tunables;
  constexpr std::string_view key = "glibc.malloc.hugetlb=";
  const std::size_t at = text.find(key);
  const char value =
      at == std::string_view::npos || at + key.size() >= text.size() ? '0' : text[at + key.size()];
  if (value == '1' || value == '2')
    return std::string("on (GLIBC_TUNABLES glibc.malloc.hugetlb=") + value + ")";
  return "off (GLIBC_TUNABLES=glibc.malloc.hugetlb=1 turns them on: docs/rl.md)";
}

// 1234567 -> "1,234,567" (built forwards: GCC 12 warns falsely on insert into a short string).
std::string thousands(double v) {
  const std::string digits = fixed_digits(v, 0);
  std::string out;
  const std::size_t lead = digits.size() % 3 == 0 ? 3 : digits.size() % 3;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (i - lead) % 3 == 0 && i >= lead && digits[i - 1] != '-')
      out += ',';
    out += digits[i];
  }
  return out;
}

Runs run_tumble(const std::shared_ptr<const Scene>& scene, int worlds, int threads, int steps,
                int repetitions, std::size_t& bytes_per_world) {
  BatchWorld batch(scene, worlds, threads);
  Runs runs;
  for (int r = 0; r < repetitions; ++r) {
    batch.reset();
    double total = 0;
    for (int s = 0; s < steps; ++s) {
      const Clock::time_point start = Clock::now();
      batch.step(1);
      const double t = seconds_since(start);
      total += t;
      runs.batch_step_seconds.push_back(t);
      for (int w = 0; w < worlds; ++w) {
        const StepStatistics& st = batch.world(w).simulation().last_step_statistics();
        runs.pairs += st.candidate_pairs;
        for (int k = 0; k < kStageCount; ++k)
          runs.stage_seconds[std::size_t(k)] += st.seconds[std::size_t(k)];
      }
    }
    runs.total_seconds.push_back(total);
  }
  double contacts = 0;
  for (int w = 0; w < worlds; ++w)
    contacts +=
        static_cast<double>(batch.world(w).simulation().last_step_statistics().contact_points);
  runs.contacts = contacts / worlds;
  const WorldMemory memory = batch.world(0).simulation().memory();
  const std::size_t bodies = std::size_t(batch.body_count());
  // The world, its rows of the batch's arrays (observations, forces, torques, targets and
  // their flags, contact forces and counts) and its share of the scratch arrays the batch lends
  // the steps (one set per thread).
  bytes_per_world = memory.body_bytes + memory.contact_bytes +
                    bodies * (sizeof(Real) * (13 + 3 + 3 + 7 + 3) + 1 + sizeof(std::int32_t)) +
                    batch.scratch_bytes() / std::size_t(worlds);
  return runs;
}

Runs run_mujoco(const Scene& scene, int worlds, int threads, int steps, int repetitions,
                std::size_t& bytes_per_world) {
  MujocoBatch batch(scene, worlds);
  tbb::task_arena arena(threads);
  Runs runs;
  for (int r = 0; r < repetitions; ++r) {
    for (int w = 0; w < worlds; ++w)
      batch.reset(w);
    double total = 0;
    for (int s = 0; s < steps; ++s) {
      const Clock::time_point start = Clock::now();
      over_worlds(arena, threads, worlds, [&](int w) { batch.step(w); });
      const double t = seconds_since(start);
      total += t;
      runs.batch_step_seconds.push_back(t);
    }
    runs.total_seconds.push_back(total);
  }
  double contacts = 0;
  for (int w = 0; w < worlds; ++w)
    contacts += batch.contacts(w);
  runs.contacts = contacts / worlds;
  bytes_per_world = batch.bytes_per_world();
  return runs;
}

Runs run_bullet(const Scene& scene, int worlds, int threads, int steps, int repetitions) {
  tbb::task_arena arena(threads);
  const BulletSettings settings = benchmark_bullet_settings(scene);
  Runs runs;
  for (int r = 0; r < repetitions; ++r) {
    std::vector<std::unique_ptr<BulletWorld>> batch;
    for (int w = 0; w < worlds; ++w)
      batch.push_back(std::make_unique<BulletWorld>(scene, settings));
    double total = 0;
    for (int s = 0; s < steps; ++s) {
      const Clock::time_point start = Clock::now();
      over_worlds(arena, threads, worlds, [&](int w) { batch[std::size_t(w)]->step(); });
      const double t = seconds_since(start);
      total += t;
      runs.batch_step_seconds.push_back(t);
    }
    runs.total_seconds.push_back(total);
    double contacts = 0;
    for (const auto& world : batch)
      contacts += world->contact_points();
    runs.contacts = contacts / worlds;
  }
  return runs;
}

struct Row {
  int worlds = 0, threads = 0;
  std::string engine;
  Spread rate;  // env-steps/s over the repetitions
  double p50_ms = 0, p99_ms = 0;
  double pairs_per_second = 0;
  double contacts = 0;
  std::size_t bytes_per_world = 0;
};

Row row_of(const Runs& runs, const std::string& engine, int worlds, int threads, int steps,
           std::size_t bytes) {
  Row row;
  row.worlds = worlds;
  row.threads = threads;
  row.engine = engine;
  std::vector<double> rates;
  double total = 0;
  for (const double t : runs.total_seconds) {
    rates.push_back(double(worlds) * steps / t);
    total += t;
  }
  row.rate = spread_of(rates);
  row.p50_ms = quantile(runs.batch_step_seconds, 0.5) * 1e3;
  row.p99_ms = quantile(runs.batch_step_seconds, 0.99) * 1e3;
  row.pairs_per_second = double(runs.pairs) / total;
  row.contacts = runs.contacts;
  row.bytes_per_world = bytes;
  return row;
}

}  // namespace

int bench_batch_command(const BenchBatchOptions& options) {
  const std::shared_ptr<const Scene> scene = load_scene(options.scene, scene_load_options());
  const int bodies = static_cast<int>(scene->bodies.size());
  std::cout << "tumble bench-batch " << options.scene.string() << " (" << bodies << " bodies), "
            << options.steps << " steps from the start, dt " << fixed_digits(scene->world.dt, 6)
            << " s, " << options.repetitions << " repetitions\nmachine: " << machine_name()
            << "\nmalloc huge pages: " << malloc_huge_pages() << "\npeers: MuJoCo "
            << mujoco_version() << (bullet_available() ? ", Bullet 3.24" : ", no Bullet") << "\n\n";

  std::vector<Row> rows;
  std::map<std::pair<int, int>, Runs> tumble_runs;
  for (const int worlds : options.worlds) {
    for (const int threads : options.threads) {
      std::size_t bytes = 0;
      Runs ours = run_tumble(scene, worlds, threads, options.steps, options.repetitions, bytes);
      rows.push_back(row_of(ours, "tumble", worlds, threads, options.steps, bytes));
      tumble_runs[{worlds, threads}] = ours;
      for (const std::string& peer : options.peers) {
        if (worlds > options.peer_max_worlds)
          continue;
        if (peer == "mujoco" && mujoco_available()) {
          std::size_t peer_bytes = 0;
          const Runs r =
              run_mujoco(*scene, worlds, threads, options.steps, options.repetitions, peer_bytes);
          rows.push_back(row_of(r, "MuJoCo", worlds, threads, options.steps, peer_bytes));
        } else if (peer == "bullet" && bullet_available()) {
          const Runs r = run_bullet(*scene, worlds, threads, options.steps, options.repetitions);
          rows.push_back(row_of(r, "Bullet", worlds, threads, options.steps, 0));
        }
      }
      std::cerr << "  measured " << worlds << " worlds on " << threads << " threads\n";
    }
  }

  std::ostringstream table;
  table << "| worlds | threads | engine | env-steps/s median (min / max) | p50 batch step ms | p99 "
           "ms | narrow pairs/s | contacts per world | tumble / engine |\n"
        << "|---|---|---|---|---|---|---|---|---|\n";
  std::map<std::pair<int, int>, double> tumble_rate;
  for (const Row& r : rows)
    if (r.engine == "tumble")
      tumble_rate[{r.worlds, r.threads}] = r.rate.median;
  for (const Row& r : rows) {
    table << "| " << r.worlds << " | " << r.threads << " | " << r.engine << " | "
          << thousands(r.rate.median) << " (" << thousands(r.rate.min) << " / "
          << thousands(r.rate.max) << ") | " << fixed_digits(r.p50_ms, 3) << " | "
          << fixed_digits(r.p99_ms, 3) << " | "
          << (r.engine == "tumble" ? thousands(r.pairs_per_second) : "-") << " | "
          << fixed_digits(r.contacts, 1) << " | "
          << fixed_digits(tumble_rate[{r.worlds, r.threads}] / r.rate.median, 2) << " |\n";
  }
  std::cout << "Throughput and latency\n\n" << table.str() << "\n";

  // Memory, and the bandwidth if each step reads and writes a world's data once. Only tumble's
  // figure is a working set (the world's bodies, contact cache and solver arrays, and its rows of
  // the batch); MuJoCo's is the arena mj_makeData allocates, most of which a step of this scene
  // never touches, so no bandwidth is derived from it.
  std::ostringstream memory;
  memory << "| engine | bytes per world | bandwidth at the largest batch, 1 thread (GB/s) |\n"
         << "|---|---|---|\n";
  for (const std::string engine : {"tumble", "MuJoCo"}) {
    const Row* largest = nullptr;
    for (const Row& r : rows)
      if (r.engine == engine && r.threads == options.threads.front() &&
          (largest == nullptr || r.worlds > largest->worlds))
        largest = &r;
    if (largest == nullptr)
      continue;
    memory << "| " << engine << " | " << thousands(double(largest->bytes_per_world)) << " | "
           << (engine == std::string("tumble")
                   ? fixed_digits(double(largest->bytes_per_world) * largest->rate.median * 2 / 1e9,
                                  2)
                   : std::string("- (an arena, mostly untouched by a step)"))
           << " |\n";
  }
  std::cout << "Memory (Bullet's worlds are not measured)\n\n" << memory.str() << "\n";

  // The per-stage split of one batch step, at the largest world count up to 1024 on the first
  // thread count (a common size for RL: about a thousand worlds).
  std::pair<int, int> key{0, options.threads.front()};
  for (const int worlds : options.worlds)
    if (worlds <= 1024 && worlds > key.first)
      key.first = worlds;
  std::ostringstream stages;
  if (const auto it = tumble_runs.find(key); it != tumble_runs.end()) {
    const Runs& runs = it->second;
    const double per_step =
        1.0 / (double(runs.batch_step_seconds.size()));  // mean over batch steps
    double step_total = 0;
    for (const double t : runs.batch_step_seconds)
      step_total += t;
    const double threads = key.second;
    // Stage times are summed over worlds (CPU time); divided by the threads, the wall time of
    // a batch step they account for.
    const auto stage_ms = [&](std::initializer_list<Stage> list) {
      double s = 0;
      for (const Stage st : list)
        s += runs.stage_seconds[std::size_t(st)];
      return s * per_step / threads * 1e3;
    };
    const double broad = stage_ms({Stage::bounds, Stage::broad_phase});
    const double narrow = stage_ms({Stage::narrow_phase});
    const double solve = stage_ms({Stage::solve});
    const double step_ms = step_total * per_step * 1e3;
    const double other = step_ms - broad - narrow - solve;
    stages << "| stage | ms per batch step | share |\n|---|---|---|\n";
    const auto line = [&](const char* name, double v) {
      stages << "| " << name << " | " << fixed_digits(v, 3) << " | "
             << fixed_digits(100 * v / step_ms, 0) << "% |\n";
    };
    line("broad phase (bounds and pairs)", broad);
    line("narrow phase", narrow);
    line("contact solve", solve);
    line("other (integration, continuous collision, batch)", other);
    line("batch step", step_ms);
    std::cout << "Where a batch step goes: " << key.first << " worlds, " << key.second
              << " thread(s)\n\n"
              << stages.str() << "\n";
  }

  if (!options.output.empty()) {
    std::ostringstream csv;
    csv << "worlds,threads,engine,rate_median,rate_min,rate_max,p50_ms,p99_ms,pairs_per_second,"
           "contacts_per_world,bytes_per_world\n";
    for (const Row& r : rows)
      csv << r.worlds << ',' << r.threads << ',' << r.engine << ',' << r.rate.median << ','
          << r.rate.min << ',' << r.rate.max << ',' << r.p50_ms << ',' << r.p99_ms << ','
          << r.pairs_per_second << ',' << r.contacts << ',' << r.bytes_per_world << '\n';
    write_file_atomically(options.output, csv.str());
    std::cout << "wrote " << options.output.string() << "\n";
  }
  return 0;
}

}  // namespace tumble::app
