#include "apps/sweep_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "apps/atomic_file.hpp"
#include "apps/compare_command.hpp"
#include "apps/csv_field.hpp"
#include "apps/json_text.hpp"
#include "apps/number_format.hpp"
#include "apps/run_summary.hpp"
#include "apps/scene_access.hpp"
#include "apps/trajectory_writer.hpp"
#include "apps/work_pool.hpp"
#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"
#include "scenes/sweep_file.hpp"
#include "tumble/randomization.hpp"
#include "tumble/world.hpp"

namespace tumble::app {
namespace {

// The check phase's problem when it ran out of memory: reported as such, with exit code 4.
constexpr const char* kOutOfMemory = "out of memory";

using nlohmann::json;

constexpr int kCheckpoints = 10;  // positions kept per run for the error against the reference

// One run of the sweep: a reference run, or a combination of the axes' values and a seed.
struct PlannedRun {
  std::string name;                 // its directory under DIR: runs/0007 or references/0001
  std::vector<std::size_t> values;  // index of each axis' value (empty for a reference)
  std::optional<std::uint64_t> seed;
  std::vector<FieldOverride> overrides;
  std::optional<std::size_t> reference;  // the run its error is measured against
};

struct Plan {
  std::vector<PlannedRun> runs;  // the references first, then the combinations in row order
  std::size_t first_row = 0;     // index of the first combination
};

std::string padded(std::size_t i, std::size_t count) {
  std::string digits = std::to_string(i);
  const std::size_t width = std::max<std::size_t>(4, std::to_string(count).size());
  return std::string(width - std::min(width, digits.size()), '0') + digits;
}

// The runs a spec makes, the same on every rank: the product of the axes (the last varies
// fastest), times the seeds; then, when the spec names a reference, each run's reference: its
// own values with the reference's fields put over them (shared by the runs that agree once those
// are replaced, so a sweep of dt and substeps has one reference per material and seed).
Plan plan_runs(const SweepSpec& spec) {
  std::vector<PlannedRun> rows;
  std::vector<std::size_t> at(spec.axes.size(), 0);
  const std::vector<std::optional<std::uint64_t>> seeds = [&] {
    std::vector<std::optional<std::uint64_t>> s;
    for (const std::uint64_t seed : spec.seeds)
      s.emplace_back(seed);
    if (s.empty())
      s.emplace_back();
    return s;
  }();
  for (bool more = true; more;) {
    for (const auto& seed : seeds) {
      PlannedRun r;
      r.values = at;
      r.seed = seed;
      for (std::size_t a = 0; a < spec.axes.size(); ++a)
        r.overrides.push_back({spec.axes[a].field, spec.axes[a].values[at[a]]});
      rows.push_back(std::move(r));
    }
    more = false;
    for (std::size_t a = spec.axes.size(); a-- > 0;) {
      if (++at[a] < spec.axes[a].values.size()) {
        more = true;
        break;
      }
      at[a] = 0;
    }
  }
  Plan plan;
  if (!spec.reference.empty()) {
    std::map<std::string, std::size_t> known;
    for (PlannedRun& row : rows) {
      PlannedRun ref;
      ref.seed = row.seed;
      ref.overrides = row.overrides;
      for (const FieldOverride& f : spec.reference) {
        const auto same = std::find_if(ref.overrides.begin(), ref.overrides.end(),
                                       [&](const FieldOverride& o) { return o.field == f.field; });
        if (same != ref.overrides.end())
          same->value = f.value;
        else
          ref.overrides.push_back(f);
      }
      std::string key = row.seed ? std::to_string(*row.seed) : "-";
      for (const FieldOverride& o : ref.overrides)
        key += "\n" + o.field + "=" + o.value;
      const auto [it, added] = known.emplace(key, plan.runs.size());
      if (added)
        plan.runs.push_back(std::move(ref));
      row.reference = it->second;
    }
    for (std::size_t i = 0; i < plan.runs.size(); ++i)
      plan.runs[i].name = "references/" + padded(i, plan.runs.size());
  }
  plan.first_row = plan.runs.size();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    rows[i].name = "runs/" + padded(i, rows.size());
    plan.runs.push_back(std::move(rows[i]));
  }
  return plan;
}

// FNV-1a of the scene file's bytes, so that a run of an edited scene is not taken for a run of
// the old one. (Files the scene names, meshes and hulls, are not part of it.)
std::string scene_digest(const SweepSpec& spec) {
  std::ifstream in(spec.scene, std::ios::binary);
  std::uint64_t h = 1469598103934665603ull;
  for (char c; in.get(c);) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return hash_hex(h);
}

// The inputs a run's outputs depend on; a run directory whose summary records other inputs
// (an earlier sweep into the same directory, or the same sweep of an edited scene) is run again.
json identity(const SweepSpec& spec, const std::string& digest, const PlannedRun& run,
              int threads) {
  json overrides = json::array();
  for (const FieldOverride& o : run.overrides)
    overrides.push_back({o.field, o.value});
  return {{"run", run.name},
          {"scene", spec.scene.string()},
          {"scene_digest", digest},
          {"overrides", overrides},
          {"seed", run.seed ? json(*run.seed) : json(nullptr)},
          {"duration", spec.duration ? json(*spec.duration) : json(nullptr)},
          {"threads", threads},
          {"trajectory", spec.trajectory}};
}

// The scene of one run, checked as `tumble run` checks its overrides.
std::shared_ptr<const Scene> scene_of(const SweepSpec& spec, const PlannedRun& run, int threads) {
  Scene scene = load_scene_file(spec.scene, run.overrides, scene_load_options());
  if (run.seed)
    scene = randomized(scene, *run.seed);
  scene.world.threads = threads;
  if (spec.duration) {
    scene.world.duration = *spec.duration;
    scene.world.steps.reset();
  }
  check_scene(scene);
  return std::make_shared<const Scene>(std::move(scene));
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::optional<json> read_json(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return std::nullopt;
  try {
    return json::parse(read_text(path));
  } catch (const json::exception&) {
    return std::nullopt;
  }
}

bool is_complete(const std::filesystem::path& dir, const json& expected) {
  const std::optional<json> summary = read_json(dir / "summary.json");
  std::error_code ec;
  return summary && summary->contains("sweep") && (*summary)["sweep"] == expected &&
         std::filesystem::is_regular_file(dir / "checkpoints.csv", ec);
}

// Temporary files of a run killed while writing (AtomicFile names them NAME.tmp.PID).
void remove_leftovers(const std::filesystem::path& dir) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    if (entry.path().filename().string().find(".tmp.") != std::string::npos)
      std::filesystem::remove(entry.path(), ec);
  }
}

// Runs one planned run into its directory; returns its wall time in seconds.
double execute(const SweepSpec& spec, const std::string& digest, const PlannedRun& run,
               const std::filesystem::path& out, int threads, int rank) {
  const std::filesystem::path dir = out / run.name;
  std::filesystem::create_directories(dir);
  // The summary goes first: until this run writes its own, the directory holds no complete run
  // (an older sweep's summary beside this run's new checkpoints would pass for one).
  std::filesystem::remove(dir / "summary.json");
  remove_leftovers(dir);
  const std::shared_ptr<const Scene> scene = scene_of(spec, run, threads);
  const std::int64_t steps = scene_steps(*scene);
  World api_world(scene);
  Simulation& world = api_world.simulation();
  RunSummary summary(*scene, world, spec.scene, steps);
  const std::vector<int> listed = trajectory_bodies(*scene, false);
  summary.set_trajectory_bodies(*scene, listed);
  std::optional<TrajectoryWriter> trajectory;
  if (spec.trajectory)
    trajectory.emplace(dir / "trajectory.csv", *scene, listed);
  AtomicFile checkpoints(dir / "checkpoints.csv");
  checkpoints.stream() << "checkpoint,time,body,px,py,pz\n";
  std::vector<std::int64_t> marks;
  for (int k = 1; k <= kCheckpoints; ++k) {
    marks.push_back(std::clamp<std::int64_t>(
        std::llround(static_cast<double>(k) * static_cast<double>(steps) / kCheckpoints), 1,
        steps));
  }
  const auto record_checkpoint = [&](int k) {
    for (const int i : listed) {
      const Vec3& p = world.state().bodies[std::size_t(i)].position;
      std::ostream& o = checkpoints.stream();
      o << k << ',';
      write_number(o, world.state().time);
      o << ',' << i << ',';
      write_number(o, p.x());
      o << ',';
      write_number(o, p.y());
      o << ',';
      write_number(o, p.z());
      o << '\n';
    }
  };
  json result = {{"sweep", identity(spec, digest, run, threads)}};
  const auto start = std::chrono::steady_clock::now();
  if (trajectory)
    trajectory->record(world.state());
  std::size_t next_mark = 0;
  std::int64_t done = 0;
  try {
    for (std::int64_t k = 1; k <= steps; ++k) {
      world.step();
      done = k;
      summary.add_step(world.last_step_statistics());
      if (trajectory)
        trajectory->record(world.state());
      while (next_mark < marks.size() && marks[next_mark] == k)
        record_checkpoint(static_cast<int>(++next_mark));
    }
    summary.finish(world, 0, spec.trajectory ? "trajectory.csv" : "");
    result["status"] = "ok";
    result["summary"] = summary.to_json_object(false);
  } catch (const NonFiniteStateError& e) {
    // A blown-up run is a result of the study, not a failure of the sweep.
    result["status"] = "non_finite";
    result["message"] = e.what();
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (trajectory)
    trajectory->finish();
  checkpoints.commit();
  write_file_atomically(
      dir / "timing.json",
      json({{"rank", rank},
            {"wall_seconds", wall},
            {"seconds_per_step", wall / static_cast<double>(std::max<std::int64_t>(done, 1))}})
              .dump(2) +
          "\n");
  // Last: the summary marks the run complete.
  write_file_atomically(dir / "summary.json", json_text(result, 2) + "\n");
  return wall;
}

using Checkpoints = std::map<std::pair<int, int>, Vec3>;  // (checkpoint, body) -> position

Checkpoints read_checkpoints(const std::filesystem::path& path) {
  Checkpoints c;
  std::istringstream in(read_text(path));
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    int k = 0;
    int body = 0;
    double t = 0;
    double x = 0;
    double y = 0;
    double z = 0;
    if (std::sscanf(line.c_str(), "%d,%lf,%d,%lf,%lf,%lf", &k, &t, &body, &x, &y, &z) == 6)
      c[{k, body}] = Vec3(x, y, z);
  }
  return c;
}

// Largest distance between the positions of a body at the same checkpoint; NaN when the two
// runs did not record the same checkpoints (one of them blew up).
double track_error(const Checkpoints& a, const Checkpoints& b) {
  if (a.size() != b.size() || a.empty())
    return std::nan("");
  double e = 0;
  for (const auto& [key, p] : a) {
    const auto other = b.find(key);
    if (other == b.end())
      return std::nan("");
    e = std::max(e, (p - other->second).norm());
  }
  return e;
}

std::string number_text(const json& value) {
  if (!value.is_number())
    return "";
  return format_number(value.get<double>());
}

// sweep.csv and timings.csv from the run directories.
void write_tables(const SweepSpec& spec, const Plan& plan, const std::filesystem::path& out) {
  std::ostringstream rows;
  std::ostringstream times;
  rows << "run";
  for (const SweepAxis& axis : spec.axes) {
    rows << ',';
    write_csv_field(rows, axis.field);
  }
  if (!spec.seeds.empty())
    rows << ",seed";
  rows << ",status,steps,simulated_seconds,energy_initial,energy_final,energy_drift,"
          "final_state_hash";
  if (!spec.reference.empty())
    rows << ",reference,error_m";
  rows << '\n';
  times << "run,rank,wall_seconds,seconds_per_step\n";
  std::map<std::size_t, Checkpoints> reference_tracks;
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    const PlannedRun& run = plan.runs[i];
    const std::filesystem::path dir = out / run.name;
    const json summary = read_json(dir / "summary.json").value_or(json::object());
    const json timing = read_json(dir / "timing.json").value_or(json::object());
    times << run.name << ',' << timing.value("rank", -1) << ','
          << number_text(timing.value("wall_seconds", json())) << ','
          << number_text(timing.value("seconds_per_step", json())) << '\n';
    if (i < plan.first_row) {
      reference_tracks[i] = read_checkpoints(dir / "checkpoints.csv");
      continue;
    }
    rows << run.name;
    for (std::size_t a = 0; a < spec.axes.size(); ++a) {
      rows << ',';
      write_csv_field(rows, spec.axes[a].values[run.values[a]]);
    }
    if (run.seed)
      rows << ',' << *run.seed;
    const std::string status = summary.value("status", "missing");
    rows << ',' << status;
    if (status == "ok") {
      const json& s = summary["summary"];
      const double e0 = s["energy"]["initial"]["total"].get<double>();
      const double e1 = s["energy"]["final"]["total"].get<double>();
      rows << ',' << s["settings"]["steps"].get<std::int64_t>() << ','
           << number_text(s["simulated_seconds"]) << ',' << format_number(e0) << ','
           << format_number(e1) << ',' << format_number(e1 - e0) << ','
           << s["final_state_hash"].get<std::string>();
    } else {
      rows << ",,,,,,";
    }
    if (run.reference) {
      const double error = track_error(read_checkpoints(dir / "checkpoints.csv"),
                                       reference_tracks.at(*run.reference));
      rows << ',' << plan.runs[*run.reference].name << ','
           << (std::isnan(error) ? std::string() : format_number(error));
    }
    rows << '\n';
  }
  write_file_atomically(out / "sweep.csv", rows.str());
  write_file_atomically(out / "timings.csv", times.str());
}

// Everything that can be found wrong before a run starts: the output directory, the base
// scene, each axis value alone (blamed on the line that gives it), then every run's scene.
// Returns the estimated cost of each run (steps x substeps x bodies) for the hand-out order.
std::vector<double> check_sweep(const SweepSpec& spec, const Plan& plan,
                                const std::filesystem::path& out, int threads) {
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) {
    throw std::runtime_error(out.string() + ": cannot create the output directory (" +
                             ec.message() + ")");
  }
  try {
    AtomicFile probe(out / "sweep.csv");  // removed unread: only whether it can be written
  } catch (const std::exception& e) {
    throw std::runtime_error(out.string() + ": cannot write in the output directory (" + e.what() +
                             ")");
  }
  (void)load_scene_file(spec.scene, {}, scene_load_options());
  for (const SweepAxis& axis : spec.axes) {
    for (std::size_t v = 0; v < axis.values.size(); ++v) {
      const FieldOverride one{axis.field, axis.values[v]};
      try {
        Scene scene = load_scene_file(spec.scene, std::span(&one, 1), scene_load_options());
        scene.world.threads = threads;
        check_scene(scene);
      } catch (const SceneError& e) {
        throw SceneError(
            spec.source.string(), axis.places[v].line, axis.places[v].column, "vary." + axis.field,
            "the value " + axis.values[v] + " does not make a valid scene: " + e.what());
      }
    }
  }
  std::vector<double> cost;
  for (const PlannedRun& run : plan.runs) {
    try {
      const auto scene = scene_of(spec, run, threads);
      cost.push_back(static_cast<double>(scene_steps(*scene)) * std::max(1, scene->world.substeps) *
                     static_cast<double>(scene->bodies.size()));
    } catch (const SceneError& e) {
      std::string values;
      for (const FieldOverride& o : run.overrides)
        values += (values.empty() ? "" : ", ") + o.field + ": " + o.value;
      // A reference's fields are written on the `reference` line; a run's combination on no
      // one line (each of its values alone was checked above).
      const bool reference = run.values.empty();
      throw SceneError(spec.source.string(), reference ? spec.reference_place.line : 0,
                       reference ? spec.reference_place.column : 0, run.name,
                       "the run {" + values + "} does not make a valid scene: " + e.what());
    }
  }
  return cost;
}

}  // namespace

int sweep_command(const SweepOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto seconds_since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  const auto started = Clock::now();
  std::unique_ptr<WorkPool> pool = make_work_pool();
  std::optional<SweepSpec> spec;
  std::optional<Plan> plan;
  std::string digest;
  std::vector<std::size_t> order;
  std::size_t complete = 0;
  if (pool->is_coordinator()) {
    // Checked here before any rank starts work; the others wait for the verdict.
    std::string problem;
    try {
      spec = load_sweep_file(options.spec);
      plan = plan_runs(*spec);
      const std::vector<double> cost =
          check_sweep(*spec, *plan, options.output_dir, options.threads);
      digest = scene_digest(*spec);
      for (std::size_t i = 0; i < plan->runs.size(); ++i) {
        const PlannedRun& run = plan->runs[i];
        if (is_complete(options.output_dir / run.name,
                        identity(*spec, digest, run, options.threads)))
          ++complete;
        else
          order.push_back(i);
      }
      // Longest first, ties in run order: the hand-out order is the same on every start.
      std::stable_sort(order.begin(), order.end(),
                       [&](std::size_t a, std::size_t b) { return cost[a] > cost[b]; });
    } catch (const std::bad_alloc&) {
      problem = kOutOfMemory;
    } catch (const std::exception& e) {
      problem = e.what();
    }
    if (!pool->agree(problem).empty()) {
      std::cerr << "tumble sweep: " << problem << "\n";
      return problem == kOutOfMemory ? 4 : 1;
    }
    if (!options.quiet) {
      std::cout << "tumble sweep: checked in " << fixed_digits(seconds_since(started), 3) << " s; "
                << plan->runs.size() - plan->first_row << " runs"
                << (plan->first_row > 0 ? " and " + std::to_string(plan->first_row) + " references"
                                        : std::string())
                << "; " << complete << " already complete, " << order.size() << " to run on "
                << std::max(1, pool->ranks() - 1) << (pool->ranks() > 2 ? " ranks" : " rank")
                << std::endl;
    }
  } else if (!pool->agree("").empty()) {
    return 1;
  }
  const auto task = [&](std::size_t i) -> std::string {
    if (!spec) {
      // A worker reads the spec itself, on the first run it is handed: a rank on a node where
      // the file cannot be read says so (the coordinator names the rank).
      spec = load_sweep_file(options.spec);
      plan = plan_runs(*spec);
      digest = scene_digest(*spec);
    }
    const double wall =
        execute(*spec, digest, plan->runs.at(i), options.output_dir, options.threads, pool->rank());
    return format_number(wall);
  };
  const auto running = Clock::now();
  try {
    pool->run(order, task);
  } catch (const WorkError& e) {
    std::cerr << "tumble sweep: " << e.what() << "\n  the runs completed so far are kept; run "
              << "the same command again to do the rest\n";
    return 1;
  }
  if (!pool->is_coordinator())
    return 0;
  const double run_seconds = seconds_since(running);
  const auto tabling = Clock::now();
  write_tables(*spec, *plan, options.output_dir);
  if (!options.quiet) {
    std::cout << "  ran " << order.size() << " in " << fixed_digits(run_seconds, 3)
              << " s; tables in " << fixed_digits(seconds_since(tabling), 3) << " s\n"
              << "  results: " << (options.output_dir / "sweep.csv").string() << "\n"
              << "  timings: " << (options.output_dir / "timings.csv").string() << "\n";
  }
  return 0;
}

}  // namespace tumble::app
