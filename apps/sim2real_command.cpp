// `tumble sim2real` (apps/sim2real_command.hpp). Three batches of the same randomized worlds
// (the same seeds, so the same friction, mass, pose and gravity draws):
//   deploy   every body with its detailed shape (the stand-in for the real system);
//   train    bodies with a train_shape collide with it, with its size noise;
//   nominal  train geometry with the size noise off.
// The gap is |train - deploy| per dynamic body and world; the spread is |train - nominal|, what
// the size noise alone moves a training world. Where the spread is at least the gap, the noise
// the policy trained under already spans the difference between its geometry and the real one.
#include "apps/sim2real_command.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>

#include "apps/atomic_file.hpp"
#include "apps/number_format.hpp"
#include "apps/plot_quote.hpp"
#include "apps/scene_access.hpp"
#include "apps/spread.hpp"
#include "tumble/batch_world.hpp"
#include "tumble/error.hpp"
#include "tumble/load_scene.hpp"

namespace tumble::app {
namespace {

using Clock = std::chrono::steady_clock;

struct Sample {
  double time = 0;
  double gap_mean = 0, gap_p95 = 0, spread_mean = 0, spread_p95 = 0;
};

// Distances between the positions of the dynamic bodies of every world of two batches.
std::vector<double> distances(const BatchWorld& a, const BatchWorld& b,
                              const std::vector<int>& bodies) {
  std::vector<double> out;
  const std::span<const Real> x = a.observations(), y = b.observations();
  for (int w = 0; w < a.size(); ++w)
    for (const int i : bodies) {
      const std::size_t at = std::size_t(w * a.body_count() + i) * BatchWorld::kObservationWidth;
      const Vec3 d(x[at] - y[at], x[at + 1] - y[at + 1], x[at + 2] - y[at + 2]);
      out.push_back(d.norm());
    }
  return out;
}

}  // namespace

int sim2real_command(const Sim2RealOptions& options) {
  const std::shared_ptr<const Scene> loaded = load_scene(options.scene, scene_load_options());
  std::vector<int> trained_bodies, dynamic_bodies;
  for (std::size_t i = 0; i < loaded->bodies.size(); ++i) {
    const BodyDesc& b = loaded->bodies[i];
    if (b.train_shape)
      trained_bodies.push_back(int(i));
    if (!b.is_static && !b.kinematic)
      dynamic_bodies.push_back(int(i));
  }
  if (trained_bodies.empty())
    throw Error("tumble sim2real: " + options.scene.string() +
                ": no body has a train_shape, so training and deployment are the same "
                "(docs/scene-format.md, \"train_shape\")");
  auto with = [&](Geometry geometry, bool size_noise) {
    auto s = std::make_shared<Scene>(*loaded);
    s->world.geometry = geometry;
    if (!size_noise)
      s->randomize.size_noise = 0;
    return std::shared_ptr<const Scene>(std::move(s));
  };
  const std::int64_t steps =
      options.steps > 0 ? options.steps
                        : std::int64_t(std::ceil(loaded->world.duration / loaded->world.dt));
  BatchWorld deploy(with(Geometry::deploy, true), options.worlds, options.threads, options.seed);
  BatchWorld train(with(Geometry::train, true), options.worlds, options.threads, options.seed);
  BatchWorld nominal(with(Geometry::train, false), options.worlds, options.threads, options.seed);

  std::vector<double> deploy_seconds, train_seconds;
  std::vector<Sample> samples;
  const auto sample = [&](double time) {
    const std::vector<double> gap = distances(train, deploy, dynamic_bodies);
    const std::vector<double> spread = distances(train, nominal, dynamic_bodies);
    samples.push_back({time, spread_of(gap).mean, quantile(gap, 0.95), spread_of(spread).mean,
                       quantile(spread, 0.95)});
  };
  sample(0);
  for (std::int64_t s = 1; s <= steps; ++s) {
    Clock::time_point start = Clock::now();
    deploy.step();
    deploy_seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count());
    start = Clock::now();
    train.step();
    train_seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count());
    nominal.step();
    sample(double(s) * loaded->world.dt);
  }

  const Spread d = spread_of(deploy_seconds), t = spread_of(train_seconds);
  std::ostringstream out;
  out << "tumble sim2real " << options.scene.string() << ": " << options.worlds
      << " randomized worlds, " << steps << " steps, seed " << options.seed << "; "
      << trained_bodies.size() << " bodies with a train_shape\n\n"
      << "| geometry | batch step ms, median (min / max) | per world-step us |\n|---|---|---|\n"
      << "| deploy | " << fixed_digits(d.median * 1e3, 3) << " (" << fixed_digits(d.min * 1e3, 3)
      << " / " << fixed_digits(d.max * 1e3, 3) << ") | "
      << fixed_digits(d.median * 1e6 / options.worlds, 2) << " |\n"
      << "| train | " << fixed_digits(t.median * 1e3, 3) << " (" << fixed_digits(t.min * 1e3, 3)
      << " / " << fixed_digits(t.max * 1e3, 3) << ") | "
      << fixed_digits(t.median * 1e6 / options.worlds, 2) << " |\n\n"
      << "train / deploy step time: " << fixed_digits(t.median / d.median, 2) << "\n\n"
      << "| time s | gap mean m | gap p95 m | noise spread mean m | noise spread p95 m | "
         "spread / gap (p95) |\n|---|---|---|---|---|---|\n";
  const std::size_t every = std::max<std::size_t>(1, (samples.size() - 1) / 10);
  for (std::size_t k = every; k < samples.size(); k += every) {
    const Sample& s = samples[k];
    out << "| " << fixed_digits(s.time, 3) << " | " << fixed_digits(s.gap_mean, 4) << " | "
        << fixed_digits(s.gap_p95, 4) << " | " << fixed_digits(s.spread_mean, 4) << " | "
        << fixed_digits(s.spread_p95, 4) << " | "
        << (s.gap_p95 > 0 ? fixed_digits(s.spread_p95 / s.gap_p95, 2) : std::string("-")) << " |\n";
  }
  const Sample& last = samples.back();
  out << "\nAt the end the size noise moves training worlds " << fixed_digits(last.spread_p95, 4)
      << " m (p95) and the training geometry is " << fixed_digits(last.gap_p95, 4)
      << " m (p95) from the deployed one: the noise "
      << (last.spread_p95 >= last.gap_p95 ? "covers" : "does not cover") << " the gap ("
      << (last.gap_p95 > 0 ? fixed_digits(last.spread_p95 / last.gap_p95, 2) : std::string("-"))
      << ").\n";
  std::cout << out.str();

  if (!options.output.empty()) {
    std::filesystem::create_directories(options.output);
    std::ostringstream csv;
    csv << "time,gap_mean,gap_p95,spread_mean,spread_p95\n";
    for (const Sample& s : samples)
      csv << s.time << ',' << s.gap_mean << ',' << s.gap_p95 << ',' << s.spread_mean << ','
          << s.spread_p95 << '\n';
    const std::filesystem::path dir = options.output;
    write_file_atomically(dir / "sim2real.csv", csv.str());
    write_file_atomically(dir / "sim2real.md", out.str());
    // The plot goes to a temporary name and is renamed onto sim2real.png once complete.
    const std::filesystem::path png = dir / "sim2real.png";
    const std::filesystem::path partial = dir / ".sim2real.png.partial";
    std::ostringstream gp;
    gp << "set terminal pngcairo noenhanced size 900,560\nset output "
       << gnuplot_quote(partial.string())
       << "\nset datafile separator ','\nset key autotitle columnhead top left\nset grid\n"
       << "set xlabel 'time [s]'\nset ylabel 'position error [m]'\nset title "
       << gnuplot_quote("train against deploy geometry: " + options.scene.filename().string())
       << "\nplot for [c=2:5] " << gnuplot_quote((dir / "sim2real.csv").string())
       << " using 1:c with lines lw 2\n";
    write_file_atomically(dir / "sim2real.gnuplot", gp.str());
    const std::string command =
        "gnuplot " + shell_quote((dir / "sim2real.gnuplot").string()) + " 2>&1";
    if (std::system(command.c_str()) == 0 && std::filesystem::exists(partial)) {
      std::filesystem::rename(partial, png);
      std::cout << "wrote " << (dir / "sim2real.csv").string() << ", sim2real.md, sim2real.png\n";
    } else {
      std::filesystem::remove(partial);
      std::cerr << "tumble sim2real: gnuplot failed or is missing; the CSV and table are "
                   "written, the plot is not (install gnuplot-nox)\n";
    }
  }
  return 0;
}

}  // namespace tumble::app
