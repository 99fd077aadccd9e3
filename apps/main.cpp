// The `tumble` command line: one verb per job (the way MuJoCo's small sample programs each do
// one thing). Exit codes: 0 success, 1 a user error with a message, 2 an internal error.
#include <CLI/CLI.hpp>
#include <cmath>
#include <exception>
#include <iostream>

#include "apps/query_command.hpp"
#include "apps/run_command.hpp"
#include "apps/validate_command.hpp"
#include "scenes/scene_loader.hpp"

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

  tumble::app::RunOptions run;
  CLI::App* run_cmd =
      app.add_subcommand("run", "Step a scene and write its trajectory and summary");
  run_cmd->add_option("scene", run.scene, "Scene file (YAML)")->required();
  run_cmd->add_option("-o,--output", run.output_dir,
                      "Output directory (default out/<scene name>); gets trajectory.csv and "
                      "summary.json");
  auto* steps_opt =
      run_cmd->add_option("--steps", run.steps, "Number of steps (overrides the scene)")
          ->check(CLI::Range(std::int64_t{1}, std::int64_t{1000000000}));
  auto* duration_opt =
      run_cmd->add_option("--duration", run.duration, "Simulated time in s (overrides the scene)")
          ->check(kFinitePositive);
  steps_opt->excludes(duration_opt);
  run_cmd->add_option("--dt", run.dt, "Time step in s (overrides the scene)")
      ->check(kFinitePositive)
      ->check(CLI::Range(0.0, 1.0));
  run_cmd
      ->add_option("--record-every", run.record_every,
                   "Write every k-th step to the trajectory (the first and last always)")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{1000000000}));
  run_cmd->add_flag("-q,--quiet", run.quiet, "Print nothing on success");

  std::filesystem::path validate_scene;
  CLI::App* validate_cmd = app.add_subcommand("validate", "Check a scene file and report errors");
  validate_cmd->add_option("scene", validate_scene, "Scene file (YAML)")->required();

  // tumble query FILE.yaml: shape-pair queries, one JSON line each (apps/query_command.hpp).
  std::filesystem::path query_file;
  CLI::App* query_cmd = app.add_subcommand(
      "query", "Answer collision queries between pairs of shapes; one JSON line per query");
  query_cmd->add_option("file", query_file, "Query file (YAML): queries: [{name, a, b}]")
      ->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "tumble: " << e.what() << "\nRun with --help for usage.\n";
    return 1;
  }

  try {
    if (run_cmd->parsed())
      return tumble::app::run_command(run);
    if (validate_cmd->parsed())
      return tumble::app::validate_command(validate_scene);
    if (query_cmd->parsed())
      return tumble::app::query_command(query_file);
  } catch (const tumble::SceneError& e) {
    std::cerr << e.what() << "\n";
    return 1;
  } catch (const std::runtime_error& e) {
    // File-system and output errors name the path in their message.
    std::cerr << "tumble: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "tumble: internal error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
