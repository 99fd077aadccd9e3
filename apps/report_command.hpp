// `tumble report SCENE.yaml [-o DIR]`: error against run time. Sweeps the time step, the
// substeps and the solver iterations, for every solver of tumble and of Bullet, and measures
// for each run the wall time per simulated second and the error against a reference: the
// analytic answer where one exists (a single body with nothing to hit follows the parabola
// x0 + v0 t + g t^2 / 2), else a converged run at 1/16 of the scene's step, made by both engines
// and checked between them. Writes report.csv, report.md and report.png (gnuplot, log-log).
#pragma once

#include <filesystem>
#include <optional>

namespace tumble::app {

struct ReportOptions {
  std::optional<int> threads;  // overrides the scene's world.threads
  std::filesystem::path scene;
  std::filesystem::path output_dir;  // default out/<scene stem>-report
  std::optional<double> duration;    // s, default the scene's
  bool no_plot = false;
  bool tumble_only = false;
};

int report_command(const ReportOptions& options);

}  // namespace tumble::app
