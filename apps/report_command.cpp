#include "apps/report_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "apps/atomic_file.hpp"
#include "apps/bullet_bridge.hpp"
#include "apps/compare_command.hpp"
#include "apps/number_format.hpp"
#include "apps/oracle_metrics.hpp"
#include "apps/plot_quote.hpp"
#include "apps/scene_access.hpp"
#include "apps/work_pool.hpp"
#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble::app {
namespace {

using Clock = std::chrono::steady_clock;

// The sweep is data. Step multipliers are powers of two relative to the scene's dt, so that the
// checkpoints (multiples of the coarsest step) fall on a step of every run.
constexpr int kCoarsestMultiplier = 4;                  // dt x 4 is the coarsest step swept
constexpr int kReferenceDivisor = 16;                   // the converged reference runs at dt / 16
const std::vector<int> kStepDivisors{-4, -2, 1, 2, 4};  // negative: dt x |k|; positive: dt / k
const std::vector<int> kSubsteps{1, 2, 4, 8, 16};
const std::vector<int> kTumbleIterations{1, 2, 4, 8};
const std::vector<int> kBulletIterations{1, 2, 5, 10, 20, 40};
// Both of tumble's solvers are swept, each against the same references.
const std::vector<std::pair<std::string, SolverType>> kTumbleSolvers{
    {"impulse", SolverType::impulse}, {"penalty", SolverType::penalty}};
const std::vector<BulletSolver> kBulletSolvers{BulletSolver::sequential_impulse,
                                               BulletSolver::sequential_impulse_no_split};
constexpr int kCheckpoints = 10;

struct Config {
  std::string engine;  // tumble | bullet
  std::string solver;
  std::string family;  // dt | substeps | iterations
  int step_divisor = 1;
  int substeps = 1;
  int iterations = 1;
  SolverType tumble_solver = SolverType::impulse;
  BulletSolver bullet_solver = BulletSolver::sequential_impulse;
};

// Positions of every body at each checkpoint.
using Track = std::vector<std::vector<Vec3>>;

struct RunResult {
  Track track;
  std::vector<std::vector<Quat>> turns;  // orientation of every body at each checkpoint
  std::vector<Vec3> com;                 // centre of mass per checkpoint
  double wall = 0;
  Real dt = 0;
};

// Steps of this run per coarse step: dt_coarse / dt.
std::int64_t steps_per_coarse(int divisor) {
  return divisor > 0 ? kCoarsestMultiplier * divisor : kCoarsestMultiplier / -divisor;
}

Real step_of(Real dt0, int divisor) {
  return divisor > 0 ? dt0 / divisor : dt0 * -divisor;
}

RunResult run(const Scene& base, const Config& c, const std::vector<std::int64_t>& coarse_marks) {
  RunResult r;
  auto scene = std::make_shared<Scene>(base);
  scene->world.dt = step_of(base.world.dt, c.step_divisor);
  scene->world.substeps = c.substeps;
  scene->world.iterations = c.iterations;
  scene->world.solver = c.tumble_solver;
  r.dt = scene->world.dt;
  const std::int64_t per = steps_per_coarse(c.step_divisor);
  const std::size_t n = scene->bodies.size();
  std::vector<BodyState> bodies(n);
  const auto take = [&](auto&& body_of) {
    for (std::size_t i = 0; i < n; ++i)
      bodies[i] = body_of(static_cast<int>(i));
    std::vector<Vec3> p(n);
    for (std::size_t i = 0; i < n; ++i)
      p[i] = bodies[i].position;
    r.track.push_back(std::move(p));
    std::vector<Quat> q(n);
    for (std::size_t i = 0; i < n; ++i)
      q[i] = bodies[i].orientation;
    r.turns.push_back(std::move(q));
    r.com.push_back(pile_statistics(*scene, bodies).centre_of_mass);
  };
  const std::int64_t last = coarse_marks.back() * per;
  if (c.engine == "tumble") {
    Simulation world(scene);
    std::size_t mark = 0;
    const auto t0 = Clock::now();
    for (std::int64_t k = 1; k <= last; ++k) {
      world.step();
      if (k == coarse_marks[mark] * per) {
        const auto pause = Clock::now();
        take([&](int i) { return world.state().bodies[i]; });
        ++mark;
        r.wall -= std::chrono::duration<double>(Clock::now() - pause).count();
      }
    }
    r.wall += std::chrono::duration<double>(Clock::now() - t0).count();
  } else {
    // The contact thresholds that let Bullet model the scene's physics (bullet_bridge.hpp),
    // with the swept step, substeps, iterations and solver.
    BulletSettings s = matching_bullet_settings(base);
    s.dt = scene->world.dt;
    s.substeps = c.substeps;
    s.iterations = c.iterations;
    s.solver = c.bullet_solver;
    BulletWorld bullet(*scene, s);
    std::size_t mark = 0;
    const auto t0 = Clock::now();
    for (std::int64_t k = 1; k <= last; ++k) {
      bullet.step();
      if (k == coarse_marks[mark] * per) {
        const auto pause = Clock::now();
        take([&](int i) { return bullet.body(i); });
        ++mark;
        r.wall -= std::chrono::duration<double>(Clock::now() - pause).count();
      }
    }
    r.wall += std::chrono::duration<double>(Clock::now() - t0).count();
  }
  return r;
}

// Largest distance between two tracks over checkpoints and dynamic bodies (paths), or between
// their centres of mass (chaotic scenes).
Real track_error(const Scene& scene, bool chaotic, const RunResult& a, const RunResult& b) {
  Real e = 0;
  for (std::size_t k = 0; k < a.track.size(); ++k) {
    if (chaotic) {
      e = std::max(e, (a.com[k] - b.com[k]).norm());
      continue;
    }
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      if (!scene.bodies[i].is_static)
        e = std::max(e, (a.track[k][i] - b.track[k][i]).norm());
    }
  }
  return e;
}

// Largest orientation angle between two runs over checkpoints and dynamic bodies [rad].
Real turn_error(const Scene& scene, const RunResult& a, const RunResult& b) {
  Real e = 0;
  for (std::size_t k = 0; k < a.turns.size() && k < b.turns.size(); ++k) {
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      if (!scene.bodies[i].is_static)
        e = std::max(e, orientation_error(a.turns[k][i], b.turns[k][i]));
    }
  }
  return e;
}

// The analytic answer for a scene of one body with nothing to hit, else nothing.
bool analytic_reference(const Scene& scene, Real coarse_dt, const std::vector<std::int64_t>& marks,
                        RunResult& out) {
  if (scene.bodies.size() != 1 || scene.bodies[0].is_static)
    return false;
  const BodyDesc& b = scene.bodies[0];
  for (std::int64_t m : marks) {
    const Real t = static_cast<Real>(m) * coarse_dt;
    const Vec3 x = b.position + t * b.velocity + Real(0.5) * t * t * scene.world.gravity;
    out.track.push_back({x});
    out.com.push_back(x);
  }
  return true;
}

std::string label(const Config& c) {
  return c.engine + " " + c.solver + " " + c.family;
}

// A run's result as bytes, to travel from the rank that ran it to rank 0 (apps/work_pool.hpp):
// the checkpoints' positions, orientations and centres of mass, the wall time and the step.
void put(std::string& bytes, double v) {
  bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
}

std::string serialised(const RunResult& r) {
  std::string bytes;
  put(bytes, static_cast<double>(r.track.size()));
  put(bytes, static_cast<double>(r.track.empty() ? 0 : r.track[0].size()));
  put(bytes, static_cast<double>(r.turns.size()));
  for (const auto& frame : r.track)
    for (const Vec3& p : frame)
      for (int k = 0; k < 3; ++k)
        put(bytes, p[k]);
  for (const auto& frame : r.turns)
    for (const Quat& q : frame)
      for (const double v : {q.w(), q.x(), q.y(), q.z()})
        put(bytes, v);
  for (const Vec3& c : r.com)
    for (int k = 0; k < 3; ++k)
      put(bytes, c[k]);
  put(bytes, r.wall);
  put(bytes, r.dt);
  return bytes;
}

RunResult deserialised(const std::string& bytes) {
  std::size_t at = 0;
  const auto get = [&] {
    double v = 0;
    if (at + sizeof v > bytes.size())
      throw std::runtime_error("tumble report: a run's result arrived truncated");
    std::memcpy(&v, bytes.data() + at, sizeof v);
    at += sizeof v;
    return v;
  };
  RunResult r;
  const auto frames = static_cast<std::size_t>(get());
  const auto bodies = static_cast<std::size_t>(get());
  const auto turn_frames = static_cast<std::size_t>(get());
  r.track.assign(frames, std::vector<Vec3>(bodies));
  for (auto& frame : r.track)
    for (Vec3& p : frame)
      for (int k = 0; k < 3; ++k)
        p[k] = get();
  r.turns.assign(turn_frames, std::vector<Quat>(bodies));
  for (auto& frame : r.turns)
    for (Quat& q : frame) {
      q.w() = get();
      q.x() = get();
      q.y() = get();
      q.z() = get();
    }
  r.com.resize(frames);
  for (Vec3& c : r.com)
    for (int k = 0; k < 3; ++k)
      c[k] = get();
  r.wall = get();
  r.dt = get();
  return r;
}

}  // namespace

int report_command(const ReportOptions& options) {
  // Under mpirun the runs spread over the ranks (apps/work_pool.hpp); rank 0 writes the report.
  std::unique_ptr<WorkPool> pool = make_work_pool();
  std::string problem;
  std::optional<Scene> loaded;
  try {
    loaded = load_scene_file(options.scene, {}, scene_load_options());
    loaded->world.threads = options.threads ? *options.threads : 1;
  } catch (const SceneError& e) {
    problem = e.what();
  }
  std::filesystem::path dir = options.output_dir;
  if (dir.empty())
    dir = std::filesystem::path("out") / (options.scene.stem().string() + "-report");
  if (pool->is_coordinator() && problem.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
      problem = "tumble report: " + dir.string() + ": cannot create output directory (" +
                ec.message() + ")";
  }
  const std::string agreed = pool->agree(problem);
  if (!agreed.empty()) {
    if (pool->is_coordinator())
      std::cerr << agreed << "\n";
    return 1;
  }
  if (!loaded) {
    // This rank alone cannot read the scene (a node that does not see the file): every run it
    // is handed fails with the reason, which rank 0 reports with this rank's number.
    pool->run({}, [&](std::size_t) -> std::string { throw std::runtime_error(problem); });
    return 1;
  }
  const Scene& base = *loaded;
  const bool with_bullet = bullet_available() && !options.tumble_only;
  if (!bullet_available() && !options.tumble_only && pool->is_coordinator()) {
    std::cerr << "tumble report: this build has no Bullet (configure with "
                 "-DTUMBLE_WITH_BULLET=ON and the bullet-float64 package); sweeping tumble "
                 "alone\n";
  }

  const Real dt0 = base.world.dt;
  const Real coarse_dt = dt0 * kCoarsestMultiplier;
  const Real duration =
      options.duration ? Real(*options.duration) : static_cast<Real>(scene_steps(base)) * dt0;
  const std::int64_t coarse_steps =
      std::max<std::int64_t>(kCheckpoints, std::llround(duration / coarse_dt));
  std::vector<std::int64_t> marks;
  for (int k = 1; k <= kCheckpoints; ++k)
    marks.push_back(std::max<std::int64_t>(1, coarse_steps * k / kCheckpoints));
  marks.erase(std::unique(marks.begin(), marks.end()), marks.end());
  const bool chaotic = scene_is_chaotic(base);
  const int scene_iterations = std::max(1, base.world.iterations);
  const int scene_substeps = std::max(1, base.world.substeps);

  // Every run of the sweep.
  std::vector<Config> configs;
  for (const auto& [name, type] : kTumbleSolvers) {
    Config c{"tumble", name, "dt", 1, scene_substeps, scene_iterations, type};
    for (int d : kStepDivisors) {
      c.step_divisor = d;
      configs.push_back(c);
    }
    c.family = "substeps";
    c.step_divisor = 1;
    for (int s : kSubsteps) {
      c.substeps = s;
      configs.push_back(c);
    }
    c.family = "iterations";
    c.substeps = scene_substeps;
    for (int it : kTumbleIterations) {
      c.iterations = it;
      configs.push_back(c);
    }
  }
  if (with_bullet) {
    for (BulletSolver solver : kBulletSolvers) {
      Config c{"bullet", bullet_solver_name(solver), "dt", 1, 1, 10};
      c.bullet_solver = solver;
      for (int d : kStepDivisors) {
        c.step_divisor = d;
        configs.push_back(c);
      }
      c.family = "substeps";
      c.step_divisor = 1;
      for (int s : kSubsteps) {
        c.substeps = s;
        configs.push_back(c);
      }
      c.family = "iterations";
      c.substeps = 1;
      for (int it : kBulletIterations) {
        c.iterations = it;
        configs.push_back(c);
      }
    }
  }

  // References: the analytic answer where one exists; converged runs of both engines always.
  RunResult analytic;
  const bool has_analytic = analytic_reference(base, coarse_dt, marks, analytic);
  Config tumble_ref{"tumble",          "impulse",      "reference",
                    kReferenceDivisor, scene_substeps, scene_iterations};
  Config bullet_ref{"bullet",          "bullet_si",    "reference",
                    kReferenceDivisor, scene_substeps, matching_bullet_settings(base).iterations};
  // Task 0 is tumble's converged run, 1 Bullet's (when swept), 2 + k the k-th configuration.
  // Short runs are repeated (up to 5 times, while under 0.2 s in all) and the fastest wall
  // time kept, so that a scheduler hiccup does not pass for a setting's cost.
  const auto task = [&](std::size_t i) {
    if (i < 2)
      return serialised(run(base, i == 0 ? tumble_ref : bullet_ref, marks));
    const Config& c = configs[i - 2];
    RunResult r = run(base, c, marks);
    double spent = r.wall;
    for (int repeat = 1; repeat < 5 && spent < 0.2; ++repeat) {
      const double wall = run(base, c, marks).wall;
      spent += wall;
      r.wall = std::min(r.wall, wall);
    }
    return serialised(r);
  };
  // Longest first (the most steps, then the most substeps and passes), so that no rank is left
  // with a long run at the end.
  std::vector<std::size_t> order;
  std::vector<double> cost(configs.size() + 2, 0);
  cost[0] = cost[1] =
      static_cast<double>(steps_per_coarse(kReferenceDivisor)) * scene_substeps * scene_iterations;
  order.push_back(0);
  if (with_bullet)
    order.push_back(1);
  for (std::size_t k = 0; k < configs.size(); ++k) {
    const Config& c = configs[k];
    cost[k + 2] = static_cast<double>(steps_per_coarse(c.step_divisor)) * c.substeps * c.iterations;
    order.push_back(k + 2);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return cost[a] > cost[b]; });
  std::vector<std::string> results;
  try {
    results = pool->run(order, task);
  } catch (const WorkError& e) {
    std::cerr << "tumble report: " << e.what() << "\n";
    return 1;
  }
  if (!pool->is_coordinator())
    return 0;
  std::vector<RunResult> by_task(configs.size() + 2);
  for (std::size_t k = 0; k < order.size(); ++k)
    by_task[order[k]] = deserialised(results[k]);
  const RunResult& tumble_fine = by_task[0];
  const RunResult& bullet_fine = by_task[1];
  const RunResult& shared = has_analytic ? analytic : tumble_fine;
  Real reference_gap = with_bullet ? track_error(base, chaotic, tumble_fine, bullet_fine) : 0;

  struct Row {
    Config c;
    Real dt;
    double wall_per_second;
    Real error;            // against the shared reference
    Real self_error;       // against the same engine's converged run
    Real turn_error;       // orientation against tumble's converged run [rad]
    Real turn_self_error;  // orientation against the same engine's converged run [rad]
  };
  std::vector<Row> rows;
  const Real simulated = static_cast<Real>(marks.back()) * coarse_dt;
  for (std::size_t k = 0; k < configs.size(); ++k) {
    const Config& c = configs[k];
    const RunResult& r = by_task[k + 2];
    const RunResult& own = c.engine == "tumble" ? tumble_fine : bullet_fine;
    rows.push_back({c, r.dt, r.wall / simulated, track_error(base, chaotic, r, shared),
                    track_error(base, chaotic, r, own), turn_error(base, r, tumble_fine),
                    turn_error(base, r, own)});
    std::cerr << "  " << label(c) << " dt " << r.dt << " substeps " << c.substeps << " iterations "
              << c.iterations << ": error " << rows.back().error << " m, "
              << rows.back().wall_per_second << " s per simulated s\n";
  }

  // A scene whose bodies only turn (a free spinning box) is judged by orientation instead.
  const bool rotation_only =
      !chaotic && std::all_of(rows.begin(), rows.end(), [](const Row& r) { return r.error == 0; });
  if (rotation_only) {
    reference_gap = with_bullet ? turn_error(base, tumble_fine, bullet_fine) : 0;
    for (Row& r : rows) {
      r.error = r.turn_error;
      r.self_error = r.turn_self_error;
    }
  }
  const std::string metric = rotation_only
                                 ? "largest body orientation angle over 10 checkpoints [rad] "
                                   "(positions agree exactly: the bodies only turn)"
                             : chaotic ? "largest centre-of-mass distance over 10 checkpoints [m]"
                                       : "largest body position distance over 10 checkpoints [m]";
  const std::string reference = rotation_only ? "tumble's converged run at dt / 16"
                                : has_analytic
                                    ? "the analytic parabola (a single body with nothing to hit)"
                                    : "tumble's converged run at dt / 16";
  const std::string unit = rotation_only ? "[rad]" : "[m]";
  // CSV.
  {
    AtomicFile f(dir / "report.csv");
    auto& o = f.stream();
    o << "engine,solver,family,dt,substeps,iterations,wall_per_simulated_second,error,"
         "self_error,orientation_error\n";
    for (const Row& r : rows) {
      o << r.c.engine << ',' << r.c.solver << ',' << r.c.family << ',';
      write_number(o, r.dt);
      o << ',' << r.c.substeps << ',' << r.c.iterations << ',';
      write_number(o, r.wall_per_second);
      o << ',';
      write_number(o, r.error);
      o << ',';
      write_number(o, r.self_error);
      o << ',';
      write_number(o, r.turn_error);
      o << '\n';
    }
    f.commit();
  }
  // Gnuplot data: one block per curve.
  std::map<std::string, std::vector<const Row*>> curves;
  for (const Row& r : rows)
    curves[label(r.c)].push_back(&r);
  {
    AtomicFile f(dir / "report.dat");
    auto& o = f.stream();
    for (const auto& [name, points] : curves) {
      o << "# " << name << "\n";
      for (const Row* r : points) {
        write_number(o, r->wall_per_second);
        o << ' ';
        write_number(o, std::max(r->error, Real(1e-16)));
        o << '\n';
      }
      o << "\n\n";
    }
    f.commit();
  }
  // Markdown.
  std::ostringstream md;
  md << "# Error against run time: " << options.scene.filename().string() << "\n\n"
     << "Generated by `tumble report " << options.scene.string() << "`. Scene step dt = " << dt0
     << " s, " << simulated << " s simulated, " << base.bodies.size() << " bodies.\n\n"
     << "- Error: " << metric << (chaotic ? " (a chaotic scene: paths are not comparable)" : "")
     << ", against " << reference << ".\n"
     << "- `self_error`: against the same engine's own converged run at dt / 16 (tumble: the "
        "scene's substeps and iterations; Bullet: the same substeps, iterations + relax "
        "iterations, "
        "split impulse). tumble's penalty solver is measured against the impulse solver's "
        "converged run: the springs converge to the same rigid answer as they stiffen.\n";
  if (with_bullet) {
    md << "- The two converged runs differ by " << reference_gap
       << " (same metric): the floor below which the engines' models, not their step "
          "sizes, decide the answer.\n";
  }
  md << "- Run time: wall-clock seconds per simulated second, one thread (tumble's "
        "`--threads` raises it).\n\n"
     << "![error against run time](report.png)\n\n"
     << "| engine | solver | family | dt [s] | substeps | iterations | wall / sim s | error "
     << unit << " | self_error " << unit << " |\n|---|---|---|---|---|---|---|---|---|\n";
  char buffer[256];
  for (const Row& r : rows) {
    std::snprintf(buffer, sizeof buffer, "| %s | %s | %s | %.6g | %d | %d | %.3g | %.3g | %.3g |\n",
                  r.c.engine.c_str(), r.c.solver.c_str(), r.c.family.c_str(), r.dt, r.c.substeps,
                  r.c.iterations, r.wall_per_second, r.error, r.self_error);
    md << buffer;
  }
  if (with_bullet) {
    BulletWorld probe(base, matching_bullet_settings(base));
    md << "\n## Settings Bullet cannot match\n\n";
    for (const std::string& m : probe.mismatches())
      md << "- " << m << "\n";
  }
  write_file_atomically(dir / "report.md", md.str());

  // Plot.
  if (!options.no_plot) {
    std::ostringstream gp;
    gp << "set terminal pngcairo noenhanced size 1100,700\nset output "
       << gnuplot_quote((dir / "report.png").string())
       << "\nset logscale xy\nset grid\nset key outside right\nset format x '%.0e'\n"
       << "set format y '%.0e'\n"
       << "set xlabel 'wall time per simulated second [s]'\nset ylabel 'error " << unit << "'\n"
       << "set title "
       << gnuplot_quote("error against run time: " + options.scene.filename().string())
       << "\nplot ";
    int index = 0;
    for (const auto& [name, points] : curves) {
      gp << (index > 0 ? ", " : "") << gnuplot_quote((dir / "report.dat").string()) << " index "
         << index << " with linespoints title " << gnuplot_quote(name);
      ++index;
    }
    gp << "\n";
    write_file_atomically(dir / "report.gnuplot", gp.str());
    const std::string command =
        "gnuplot " + shell_quote((dir / "report.gnuplot").string()) + " 2>&1";
    if (std::system(command.c_str()) != 0) {
      std::cerr << "tumble report: gnuplot failed or is missing; report.csv and report.md are "
                   "written, the plot is not (install gnuplot-nox)\n";
    }
  }
  std::cout << "tumble report: " << rows.size() << " runs; " << (dir / "report.md").string()
            << "\n";
  return 0;
}

}  // namespace tumble::app
