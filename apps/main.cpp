// The `tumble` command line: one verb per job (the way MuJoCo's small sample programs each do
// one thing). Exit codes: 0 success, 1 a user error with a message, 2 an internal error, 3 a
// non-finite state (run), 4 out of memory.
#include <CLI/CLI.hpp>
#include <cmath>
#include <exception>
#include <iostream>
#include <map>
#include <new>

#include "apps/bench_batch_command.hpp"
#include "apps/bench_command.hpp"
#include "apps/ccd_command.hpp"
#include "apps/compare_command.hpp"
#include "apps/query_command.hpp"
#include "apps/render_command.hpp"
#include "apps/report_command.hpp"
#include "apps/run_command.hpp"
#include "apps/scene_access.hpp"
#include "apps/sim2real_command.hpp"
#include "apps/sweep_command.hpp"
#include "apps/validate_command.hpp"
#include "scenes/scene_loader.hpp"
#include "tumble/version.hpp"

namespace {

// CLI11 validators for finite positive numbers (it has PositiveNumber, but that lets inf pass).
const auto kFinitePositive = CLI::Validator(
    [](std::string& text) -> std::string {
      try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used != text.size() || !std::isfinite(v) || v <= 0) {
          return "expected a finite number > 0, got '" + text + "'";
        }
      } catch (const std::exception&) {
        return "expected a finite number > 0, got '" + text + "'";
      }
      return {};
    },
    "POSITIVE");

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tumble: a rigid-body physics engine centred on collision detection"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("tumble ") + tumble::kVersion);
  // Given before or after the command: every command's files follow the same rule.
  app.fallthrough();
  app.add_flag("--allow-outside-files", tumble::app::scene_load_options().allow_outside_files,
               "Let scene, query and sweep files name files outside their own folder (off by "
               "default: a scene from elsewhere cannot make tumble read any file on the machine)");

  tumble::app::RunOptions run;
  CLI::App* run_cmd =
      app.add_subcommand("run", "Step a scene and write its trajectory and summary");
  run_cmd->add_option("scene", run.scene, "Scene file (YAML)")->required();
  run_cmd
      ->add_option("--threads", run.threads,
                   "Threads per step, 1 to 1024 (default: the scene's world.threads; results do "
                   "not change)")
      ->check(CLI::Range(1, 1024));
  run_cmd->add_option("-o,--output", run.output_dir,
                      "Output directory (default out/<scene name>); gets trajectory.csv and "
                      "summary.json");
  auto* steps_opt =
      run_cmd->add_option("--steps", run.steps, "Number of steps (default: the scene's)")
          ->check(CLI::Range(std::int64_t{1}, std::int64_t{1000000000}));
  auto* duration_opt =
      run_cmd->add_option("--duration", run.duration, "Simulated time in s (default: the scene's)")
          ->check(kFinitePositive);
  steps_opt->excludes(duration_opt);
  // The range is the scene's (1e-9 to 1 s), checked with the scene (check_scene).
  run_cmd->add_option("--dt", run.dt, "Time step in s (default: the scene's)")
      ->check(kFinitePositive);
  run_cmd
      ->add_option("--record-every", run.record_every,
                   "Write every k-th step to the trajectory, the first and last always (default 1)")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{1000000000}));
  run_cmd->add_flag("-q,--quiet", run.quiet, "Print nothing on success");
  run_cmd
      ->add_option("--format", run.format,
                   "Trajectory file: csv (trajectory.csv), npy (trajectory.npy: float64 "
                   "[records, bodies, 13]) or both (default csv)")
      ->check(CLI::IsMember({"csv", "npy", "both"}));
  run_cmd->add_flag("--static-bodies", run.static_bodies,
                    "Also write static bodies in the trajectory (left out: they never move)");
  run_cmd->add_flag("--contacts", run.contacts,
                    "Also write contacts.csv: every contact point of every recorded step");

  std::filesystem::path validate_scene;
  CLI::App* validate_cmd = app.add_subcommand("validate", "Check a scene file and report errors");
  validate_cmd->add_option("scene", validate_scene, "Scene file (YAML)")->required();

  tumble::app::CcdOptions ccd;
  CLI::App* ccd_cmd = app.add_subcommand(
      "ccd", "Run vertex-face or edge-edge CCD on a query file (CCD benchmark CSV) and score it");
  ccd_cmd->add_option("file", ccd.file, "Query file (CSV, 8 rows per query)")->required();
  ccd_cmd->add_option("--kind", ccd.kind, "vf (vertex-face) or ee (edge-edge)")
      ->required()
      ->check(CLI::IsMember({"vf", "ee"}));
  ccd_cmd->add_flag("--reverse-faces", ccd.reverse_faces,
                    "vf: reverse the triangle's vertex order");
  ccd_cmd->add_option("--tolerance", ccd.tolerance, "Contact tolerance in m (default 1e-6)")
      ->check(kFinitePositive);

  // Bullet as oracle (apps/bullet_bridge.hpp): compare, report, bench.
  tumble::app::CompareOptions compare;
  CLI::App* compare_cmd = app.add_subcommand(
      "compare", "Run a scene in tumble and in Bullet side by side and write their differences");
  compare_cmd->add_option("scene", compare.scene, "Scene file (YAML)")->required();
  compare_cmd
      ->add_option("--threads", compare.threads,
                   "Threads per step, 1 to 1024 (default: the scene's world.threads; results do "
                   "not change)")
      ->check(CLI::Range(1, 1024));
  compare_cmd->add_option("-o,--output", compare.output_dir,
                          "Output directory (default out/<scene name>-compare)");
  compare_cmd
      ->add_option("--mode", compare.mode,
                   "paths (per-body errors), statistics (chaotic scenes) or auto (default auto: "
                   "statistics for chaotic scenes, paths otherwise)")
      ->transform(CLI::CheckedTransformer(
                      std::map<std::string, tumble::app::CompareMode>{
                          {"auto", tumble::app::CompareMode::automatic},
                          {"paths", tumble::app::CompareMode::paths},
                          {"statistics", tumble::app::CompareMode::statistics}},
                      CLI::ignore_case)
                      .description("{auto,paths,statistics}"))
      ->type_name("TEXT");
  compare_cmd->add_option("--steps", compare.steps, "Number of steps (default: the scene's)")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{100000000}));
  compare_cmd->add_flag("-q,--quiet", compare.quiet, "Print only the JSON summary");
  compare_cmd
      ->add_option("--bullet-breaking-threshold", compare.bullet_breaking_threshold,
                   "Bullet's gContactBreakingThreshold factor (default 0.02)")
      ->check(kFinitePositive);

  tumble::app::ReportOptions report;
  CLI::App* report_cmd = app.add_subcommand(
      "report",
      "Sweep time step, substeps, iterations and solver in tumble and Bullet; write "
      "error against run time (CSV, Markdown, PNG)");
  report_cmd->add_option("scene", report.scene, "Scene file (YAML)")->required();
  report_cmd
      ->add_option("--threads", report.threads,
                   "Threads per step of tumble's runs, 1 to 1024 (default 1, so that run time "
                   "compares with Bullet's one thread; results do not change)")
      ->check(CLI::Range(1, 1024));
  report_cmd->add_option("-o,--output", report.output_dir,
                         "Output directory (default out/<scene name>-report)");
  report_cmd->add_option("--duration", report.duration, "Simulated time in s (default: scene)")
      ->check(kFinitePositive);
  report_cmd->add_flag("--no-plot", report.no_plot, "Skip the gnuplot PNG");
  report_cmd->add_flag("--tumble-only", report.tumble_only, "Sweep tumble alone");

  tumble::app::BenchOptions bench;
  CLI::App* bench_cmd = app.add_subcommand(
      "bench", "Time scenes in tumble and Bullet, alternating, with sleeping off and on");
  bench_cmd->add_option("scenes", bench.scenes, "Scene files (default: scenes/bench/*.yaml)");
  bench_cmd->add_option("-o,--output", bench.output_dir,
                        "Directory for the CSV files (default out/bench)");
  bench_cmd
      ->add_option("--repetitions", bench.repetitions, "Runs of each engine per scene (default 3)")
      ->check(CLI::Range(1, 1000));
  bench_cmd->add_option("--steps", bench.steps, "Steps per run (default: the scene's)")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{100000000}));
  bench_cmd
      ->add_option("--threads", bench.threads,
                   "tumble's thread counts, comma-separated (default 1,2; speed-ups are "
                   "against the first)")
      ->delimiter(',')
      ->check(CLI::Range(1, 1024));
  tumble::app::BenchBatchOptions bench_batch;
  CLI::App* bench_batch_cmd = app.add_subcommand(
      "bench-batch",
      "Time batches of worlds (RL metrics: throughput, latency, scaling, memory, stages) "
      "against MuJoCo and Bullet");
  bench_batch_cmd->add_option("scene", bench_batch.scene,
                              "Scene file (default scenes/rl/boxes20.yaml)");
  bench_batch_cmd
      ->add_option("--worlds", bench_batch.worlds,
                   "World counts, comma-separated (default 1,16,256,1024,4096)")
      ->delimiter(',')
      ->check(CLI::Range(1, 1000000));
  bench_batch_cmd
      ->add_option("--threads", bench_batch.threads, "Thread counts, comma-separated (default 1,2)")
      ->delimiter(',')
      ->check(CLI::Range(1, 1024));
  bench_batch_cmd->add_option("--steps", bench_batch.steps, "Batch steps per run (default 60)")
      ->check(CLI::Range(1, 1000000));
  bench_batch_cmd
      ->add_option("--repetitions", bench_batch.repetitions, "Runs per engine (default 3)")
      ->check(CLI::Range(1, 1000));
  bench_batch_cmd
      ->add_option("--peers", bench_batch.peers,
                   "Peers, comma-separated: mujoco, bullet, none (default mujoco,bullet)")
      ->delimiter(',')
      ->check(CLI::IsMember({"mujoco", "bullet", "none"}));
  bench_batch_cmd
      ->add_option("--peer-max-worlds", bench_batch.peer_max_worlds,
                   "Largest world count the peers run (default 1024)")
      ->check(CLI::Range(1, 1000000));
  bench_batch_cmd->add_option("-o,--output", bench_batch.output,
                              "CSV file to write (default: none, the table is printed)");
  tumble::app::Sim2RealOptions sim2real;
  CLI::App* sim2real_cmd =
      app.add_subcommand("sim2real",
                         "Randomized worlds in training against deployment geometry: step times, "
                         "trajectory gap, and whether the size noise covers it");
  sim2real_cmd->add_option("scene", sim2real.scene, "Scene file with train_shape bodies")
      ->required();
  sim2real_cmd->add_option("--worlds", sim2real.worlds, "Randomized worlds (default 64)")
      ->check(CLI::Range(1, 1000000));
  sim2real_cmd->add_option("--steps", sim2real.steps, "Steps (default: the scene's duration)")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{100000000}));
  sim2real_cmd->add_option("--threads", sim2real.threads, "Threads (default: the cores)")
      ->check(CLI::Range(1, 1024));
  sim2real_cmd->add_option("--seed", sim2real.seed, "The batches' seed (default 0)");
  sim2real_cmd->add_option("-o,--output", sim2real.output,
                           "Directory for sim2real.csv, sim2real.md and sim2real.png (default: "
                           "none, the table is printed)");
  tumble::app::SweepOptions sweep;
  CLI::App* sweep_cmd = app.add_subcommand(
      "sweep",
      "Run every combination of a sweep file's values (in one process, or over MPI ranks under "
      "mpirun); write each run, sweep.csv and timings.csv");
  sweep_cmd->add_option("spec", sweep.spec, "Sweep file (YAML): scene, vary, seeds, reference")
      ->required();
  sweep_cmd->add_option("-o,--output", sweep.output_dir, "Output directory")->required();
  sweep_cmd->add_option("--threads", sweep.threads, "Threads per run, 1 to 1024 (default 1)")
      ->check(CLI::Range(1, 1024));
  sweep_cmd->add_flag("-q,--quiet", sweep.quiet, "Print errors only");
  tumble::app::RenderOptions render;
  CLI::App* render_cmd = app.add_subcommand(
      "render", "Simulate a scene and render it off-screen to an MP4 video and/or PNG frames");
  render_cmd->add_option("scene", render.scene, "Scene file (YAML)")->required();
  render_cmd
      ->add_option("--threads", render.threads,
                   "Threads per step, 1 to 1024 (default: the scene's world.threads; results do "
                   "not change)")
      ->check(CLI::Range(1, 1024));
  render_cmd->add_option("-o,--output", render.output,
                         "Video file, H.264 MP4 (default out/<scene>/<scene>.mp4 unless "
                         "--frames is given)");
  render_cmd->add_option("--frames", render.frames_dir,
                         "Also write every frame as DIR/frame_NNNNNN.png (default: no frames)");
  // At least one frame a second: a video's frame rate below that is not one ffmpeg writes.
  render_cmd
      ->add_option("--fps", render.fps,
                   "Frames per second of simulated time, 1 to 1000 (default 60)")
      ->check(kFinitePositive)
      ->check(CLI::Range(1.0, 1000.0));
  render_cmd->add_option("--size", render.size, "Image size WIDTHxHEIGHT (default 1280x720)");
  render_cmd
      ->add_option(
          "--overlay", render.overlays,
          "Debug overlays, comma-separated: aabb, pairs, contacts, stage, rest (default: none)")
      ->delimiter(',');
  render_cmd
      ->add_option("--duration", render.duration, "Simulated time in s (default: the scene's)")
      ->check(kFinitePositive);
  render_cmd
      ->add_option("--supersample", render.supersample,
                   "Anti-aliasing: render at N times the size and filter down, 1 to 4 (default 2)")
      ->check(CLI::Range(1, 4));
  render_cmd->add_flag_callback(
      "--no-shadows", [&render] { render.shadows = false; }, "Do not draw shadows on the floor");
  render_cmd->add_flag("-q,--quiet", render.quiet, "No progress bar, no summary");
  // tumble query FILE.yaml: shape-pair queries, one JSON line each (apps/query_command.hpp).
  std::filesystem::path query_file;
  CLI::App* query_cmd = app.add_subcommand(
      "query", "Answer collision queries between pairs of shapes; one JSON line per query");
  query_cmd->add_option("file", query_file, "Query file (YAML): queries: [{name, a, b}]")
      ->required();

  // A first word that is no command (a typo) is named, not reported as a missing command.
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    std::string commands;
    for (const CLI::App* sub : app.get_subcommands({})) {
      known = known || sub->get_name() == argv[1];
      commands += (commands.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::cerr << "tumble: unknown command '" << argv[1] << "'; the commands are " << commands
                << "\nRun with --help for usage.\n";
      return 1;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "tumble: " << e.what() << "\nRun with --help for usage.\n";
    return 1;
  }

  try {
    if (run_cmd->parsed())
      return tumble::app::run_command(run);
    if (render_cmd->parsed())
      return tumble::app::render_command(render);
    if (validate_cmd->parsed())
      return tumble::app::validate_command(validate_scene);
    if (ccd_cmd->parsed())
      return tumble::app::ccd_command(ccd);
    if (compare_cmd->parsed())
      return tumble::app::compare_command(compare);
    if (report_cmd->parsed())
      return tumble::app::report_command(report);
    if (bench_cmd->parsed())
      return tumble::app::bench_command(bench);
    if (sweep_cmd->parsed())
      return tumble::app::sweep_command(sweep);
    if (sim2real_cmd->parsed())
      return tumble::app::sim2real_command(sim2real);
    if (bench_batch_cmd->parsed())
      return tumble::app::bench_batch_command(bench_batch);
    if (query_cmd->parsed())
      return tumble::app::query_command(query_file);
  } catch (const tumble::SceneError& e) {
    std::cerr << e.what() << "\n";
    return 1;
  } catch (const std::runtime_error& e) {
    // File-system and output errors name the path in their message.
    std::cerr << "tumble: " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "tumble: out of memory (the scene, its meshes or its contacts need more than "
                 "this machine can give)\n";
    return 4;
  } catch (const std::exception& e) {
    std::cerr << "tumble: internal error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
