#include "apps/run_command.hpp"

#include "apps/scene_access.hpp"
#include "tumble/model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "apps/atomic_file.hpp"
#include "apps/contacts_writer.hpp"
#include "apps/npy_trajectory_writer.hpp"
#include "apps/run_summary.hpp"
#include "apps/trajectory_writer.hpp"
#include "engine/scene_limits.hpp"
#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble::app {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_interrupt(int) {
  g_interrupted = 1;
}

// Steps needed to cover `duration`: the quotient rounded up, except that a quotient within
// rounding of an integer counts as that integer (5 s at dt = 1/60 is 300 steps, not 301).
std::int64_t steps_for(double duration, double dt) {
  const double q = duration / dt;
  const double nearest = std::round(q);
  if (std::abs(q - nearest) <= 1e-9 * std::max(1.0, nearest)) {
    return static_cast<std::int64_t>(nearest);
  }
  return static_cast<std::int64_t>(std::ceil(q));
}

}  // namespace

int run_command(const RunOptions& options) {
  auto scene = std::make_shared<Scene>(load_scene_file(options.scene, {}, scene_load_options()));
  if (options.threads)
    scene->world.threads = *options.threads;
  if (options.dt)
    scene->world.dt = *options.dt;
  if (options.duration) {
    scene->world.duration = *options.duration;
    scene->world.steps.reset();
  }
  // The overrides pass the check the file passed (the same ranges, tumble/model.hpp), the steps
  // duration / dt makes included.
  try {
    check_scene(*scene);
  } catch (const SceneError& e) {
    if (e.field == "world.dt" && options.dt)
      throw SceneError(e.file, 0, 0, "--dt", e.reason);
    if (e.field == "world.threads" && options.threads)
      throw SceneError(e.file, 0, 0, "--threads", e.reason);
    if (e.field == "world.duration" && options.duration)
      throw SceneError(e.file, 0, 0, "--duration", e.reason);
    throw;
  }

  // `ccd: off` wins over `fast: true`: say so, since the user asked for both.
  const bool fast_body_unswept =
      scene->world.ccd == CcdMode::off &&
      std::any_of(scene->bodies.begin(), scene->bodies.end(),
                  [](const BodyDesc& b) { return b.fast && !b.is_static; });
  if (fast_body_unswept) {
    std::cerr << "tumble run: warning: " << options.scene.string()
              << " marks a body fast: true but sets ccd: off; no body is swept\n";
  }

  std::int64_t steps = 0;
  if (options.steps) {
    steps = *options.steps;
  } else if (options.duration) {
    steps = steps_for(*options.duration, scene->world.dt);
  } else if (scene->world.steps) {
    steps = *scene->world.steps;
  } else {
    steps = steps_for(scene->world.duration, scene->world.dt);
  }

  // The trajectory's size is known before the run: one past the limit is refused here, rather
  // than found when the disk is full.
  {
    using scene_limits::kMaxTrajectoryRows;
    const std::int64_t every = options.record_every;
    const std::int64_t records = 1 + steps / every + (steps % every != 0 ? 1 : 0);
    const auto bodies = static_cast<std::int64_t>(
        std::max<std::size_t>(1, trajectory_bodies(*scene, options.static_bodies).size()));
    if (records > kMaxTrajectoryRows / bodies) {
      const std::int64_t records_allowed = kMaxTrajectoryRows / bodies - 2;
      const std::int64_t suggestion =
          records_allowed > 0 ? (steps + records_allowed - 1) / records_allowed : steps;
      std::cerr << "tumble run: " << options.scene.string() << ": the trajectory would have "
                << records << " records of " << bodies
                << " bodies, more rows than the limit of 100,000,000 (about 30 GB of CSV); "
                   "write fewer records with --record-every "
                << std::max<std::int64_t>(suggestion, every + 1) << " or more\n";
      return 1;
    }
  }

  std::filesystem::path dir = options.output_dir;
  if (dir.empty())
    dir = std::filesystem::path("out") / options.scene.stem();
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    std::cerr << "tumble run: " << dir.string() << ": cannot create output directory ("
              << ec.message() << ")\n";
    return 1;
  }
  const bool csv = options.format == "csv" || options.format == "both";
  const bool npy = options.format == "npy" || options.format == "both";
  const std::filesystem::path trajectory_path = dir / (csv ? "trajectory.csv" : "trajectory.npy");
  const std::filesystem::path npy_path = dir / "trajectory.npy";
  const std::filesystem::path contacts_path = dir / "contacts.csv";
  const std::filesystem::path summary_path = dir / "summary.json";

  // Handlers first, so that an interrupt at any point from here on is an orderly stop.
  g_interrupted = 0;
  auto previous_int = std::signal(SIGINT, on_interrupt);
  auto previous_term = std::signal(SIGTERM, on_interrupt);
  auto previous_hup = std::signal(SIGHUP, on_interrupt);  // the terminal closed
  World api_world(scene);
  Simulation& world = api_world.simulation();
  RunSummary summary(*scene, world, options.scene, steps);
  std::optional<TrajectoryWriter> trajectory;
  std::optional<NpyTrajectoryWriter> trajectory_npy;
  std::optional<ContactsWriter> contacts;
  const std::vector<int> listed = trajectory_bodies(*scene, options.static_bodies);
  summary.set_trajectory_bodies(*scene, listed);
  if (csv)
    trajectory.emplace(dir / "trajectory.csv", *scene, listed);
  if (npy)
    trajectory_npy.emplace(npy_path, listed);
  if (options.contacts)
    contacts.emplace(contacts_path);
  const auto record = [&] {
    if (trajectory)
      trajectory->record(world.state());
    if (trajectory_npy)
      trajectory_npy->record(world.state());
  };
  // Renames the trajectory and contact files into place, complete.
  const auto commit_files = [&] {
    if (trajectory)
      trajectory->finish();
    if (trajectory_npy)
      trajectory_npy->finish();
    if (contacts)
      contacts->finish();
  };
  const auto restore_signals = [&] {
    std::signal(SIGINT, previous_int);
    std::signal(SIGTERM, previous_term);
    std::signal(SIGHUP, previous_hup);
  };
  const auto start = std::chrono::steady_clock::now();
  record();
  for (std::int64_t k = 1; k <= steps && !g_interrupted; ++k) {
    try {
      world.step();
    } catch (const NonFiniteStateError& e) {
      // The rows recorded so far are finite: keep them (under their final names), but no summary
      // of a state that is not a number.
      restore_signals();
      commit_files();
      std::cerr << "tumble run: " << options.scene.string() << ": stopped: " << e.what()
                << "\n  the trajectory up to the last recorded finite step is in "
                << trajectory_path.string() << "; no summary was written\n";
      return kExitNonFinite;
    }
    summary.add_step(world.last_step_statistics());
    if (k % options.record_every == 0 || k == steps) {
      record();
      if (contacts)
        contacts->record(api_world);
    }
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  restore_signals();
  if (g_interrupted) {
    // The temporary trajectory file is removed when `trajectory` goes out of scope; files from
    // an earlier complete run stay as they were.
    std::cerr << "tumble run: interrupted after " << world.state().step
              << " steps; no output written\n";
    return 130;
  }
  commit_files();
  summary.finish(world, wall, trajectory_path);
  write_file_atomically(summary_path, summary.to_json() + "\n");
  if (!options.quiet) {
    std::cout << "tumble run: " << scene->bodies.size() << " bodies, " << steps << " steps ("
              << world.state().time << " s simulated) in " << wall << " s\n"
              << "  trajectory: " << trajectory_path.string()
              << (csv && npy ? " and " + npy_path.string() : std::string()) << "\n"
              << (options.contacts ? "  contacts:   " + contacts_path.string() + "\n" : "")
              << "  summary:    " << summary_path.string() << "\n"
              << "  final state hash: " << summary.final_hash_hex() << "\n";
  }
  return 0;
}

}  // namespace tumble::app
