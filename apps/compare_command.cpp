#include "apps/compare_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "apps/atomic_file.hpp"
#include "apps/json_text.hpp"
#include "apps/number_format.hpp"
#include "apps/oracle_metrics.hpp"
#include "apps/scene_access.hpp"
#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble::app {
namespace {

using Clock = std::chrono::steady_clock;

CompareSample sample_of(const Scene& scene, const Simulation& world, const BulletWorld& bullet,
                        std::int64_t tumble_contacts, const std::vector<BodyState>& bullet_bodies,
                        Real max_pos, Real max_rot) {
  CompareSample s;
  s.time = world.state().time;
  s.max_position_error = max_pos;
  s.max_orientation_error = max_rot;
  s.tumble_kinetic = world.kinetic_energy();
  s.tumble_potential = world.potential_energy();
  s.bullet_kinetic = bullet.kinetic_energy();
  s.bullet_potential = bullet.potential_energy();
  s.tumble_contacts = tumble_contacts;
  s.bullet_contacts = bullet.contact_points();
  const PileStatistics pt = pile_statistics(scene, world.state().bodies);
  const PileStatistics pb = pile_statistics(scene, bullet_bodies);
  s.tumble_com = pt.centre_of_mass;
  s.bullet_com = pb.centre_of_mass;
  s.tumble_pile_height = pt.pile_height;
  s.bullet_pile_height = pb.pile_height;
  s.tumble_at_rest = pt.bodies_at_rest;
  s.bullet_at_rest = pb.bodies_at_rest;
  return s;
}

// Points kept in tumble's manifolds after the step, speculative ones within the contact margin
// included; Bullet's count (BulletWorld::contact_points) likewise includes its points within the
// contact breaking threshold.
std::int64_t tumble_manifold_points(const Simulation& world) {
  std::int64_t n = 0;
  for (const CachedManifold& m : world.state().contacts)
    n += m.count;
  return n;
}

std::string mode_name(bool chaotic) {
  return chaotic ? "statistics" : "paths";
}

}  // namespace

std::int64_t scene_steps(const Scene& scene) {
  if (scene.world.steps)
    return *scene.world.steps;
  const double q = scene.world.duration / scene.world.dt;
  const double nearest = std::round(q);
  if (std::abs(q - nearest) <= 1e-9 * std::max(1.0, nearest))
    return static_cast<std::int64_t>(nearest);
  return static_cast<std::int64_t>(std::ceil(q));
}

CompareResult compare_scene(const std::shared_ptr<const Scene>& scene, std::int64_t steps,
                            CompareMode mode, std::int64_t samples,
                            const std::optional<BulletSettings>& bullet_settings) {
  CompareResult r;
  r.steps = steps;
  r.chaotic =
      mode == CompareMode::automatic ? scene_is_chaotic(*scene) : mode == CompareMode::statistics;
  r.scene_size = scene_size(*scene);
  Simulation world(scene);
  BulletWorld bullet(*scene, bullet_settings ? *bullet_settings : matching_bullet_settings(*scene));
  r.mismatches = bullet.mismatches();
  const std::size_t n = scene->bodies.size();
  const std::int64_t every = std::max<std::int64_t>(1, steps / std::max<std::int64_t>(1, samples));
  std::vector<BodyState> bb(n);
  Real max_displacement = 0;
  const auto record = [&](std::int64_t k) {
    Real max_pos = 0, max_rot = 0;
    const bool sampled = k % every == 0 || k == steps;
    for (std::size_t i = 0; i < n; ++i) {
      bb[i] = bullet.body(static_cast<int>(i));
      if (scene->bodies[i].is_static)
        continue;
      const BodyState& t = world.state().bodies[i];
      const Real dp = (t.position - bb[i].position).norm();
      const Real dq = orientation_error(t.orientation, bb[i].orientation);
      max_pos = std::max(max_pos, dp);
      max_rot = std::max(max_rot, dq);
      max_displacement =
          std::max(max_displacement, (bb[i].position - scene->bodies[i].position).norm());
      if (sampled)
        r.body_errors.push_back(
            {static_cast<std::int64_t>(r.samples.size()), static_cast<int>(i), dp, dq});
    }
    r.max_position_error = std::max(r.max_position_error, max_pos);
    r.max_orientation_error = std::max(r.max_orientation_error, max_rot);
    if (sampled) {
      r.samples.push_back(
          sample_of(*scene, world, bullet, tumble_manifold_points(world), bb, max_pos, max_rot));
      const CompareSample& s = r.samples.back();
      r.max_com_error = std::max(r.max_com_error, (s.tumble_com - s.bullet_com).norm());
    }
  };
  record(0);
  for (std::int64_t k = 1; k <= steps; ++k) {
    const auto t0 = Clock::now();
    world.step();
    const auto t1 = Clock::now();
    bullet.step();
    const auto t2 = Clock::now();
    r.tumble_seconds += std::chrono::duration<double>(t1 - t0).count();
    r.bullet_seconds += std::chrono::duration<double>(t2 - t1).count();
    record(k);
  }
  const CompareSample& last = r.samples.back();
  r.final_pile_height_error = std::abs(last.tumble_pile_height - last.bullet_pile_height);
  r.final_energy_error = std::abs((last.tumble_kinetic + last.tumble_potential) -
                                  (last.bullet_kinetic + last.bullet_potential));
  r.max_relative_position_error =
      max_displacement > 0 ? r.max_position_error / max_displacement : r.max_position_error;
  if (r.chaotic) {
    std::ostringstream v;
    v << "chaotic scene: compared by statistics, not paths; centre of mass within "
      << r.max_com_error << " m, final pile height within " << r.final_pile_height_error
      << " m, bodies at rest " << last.tumble_at_rest << " (tumble) vs " << last.bullet_at_rest
      << " (Bullet), final energy within " << r.final_energy_error << " J";
    r.verdict = v.str();
  } else {
    r.verdict = position_verdict(r.max_position_error, r.scene_size) +
                "; largest orientation difference " + std::to_string(r.max_orientation_error) +
                " rad";
  }
  return r;
}

int compare_command(const CompareOptions& options) {
  auto scene = std::make_shared<Scene>(load_scene_file(options.scene, {}, scene_load_options()));
  if (options.threads)
    scene->world.threads = *options.threads;
  if (!bullet_available()) {
    std::cerr << "tumble compare: this build has no Bullet (configure with "
                 "-DTUMBLE_WITH_BULLET=ON and the bullet-float64 package); nothing to compare "
                 "against\n";
    return 1;
  }
  const std::int64_t steps = options.steps ? *options.steps : scene_steps(*scene);
  std::filesystem::path dir = options.output_dir;
  if (dir.empty())
    dir = std::filesystem::path("out") / (options.scene.stem().string() + "-compare");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    std::cerr << "tumble compare: " << dir.string() << ": cannot create output directory ("
              << ec.message() << ")\n";
    return 1;
  }
  BulletSettings bullet = matching_bullet_settings(*scene);
  if (options.bullet_breaking_threshold)
    bullet.contact_breaking_threshold = *options.bullet_breaking_threshold;
  const CompareResult r = compare_scene(scene, steps, options.mode, options.samples, bullet);

  {
    AtomicFile f(dir / "errors.csv");
    auto& o = f.stream();
    o << "time,body,position_error,orientation_error\n";
    for (const auto& e : r.body_errors) {
      write_number(o, r.samples[e.sample].time);
      o << ',' << scene->bodies[e.body].name << ',';
      write_number(o, e.position);
      o << ',';
      write_number(o, e.orientation);
      o << '\n';
    }
    f.commit();
  }
  {
    AtomicFile f(dir / "timeline.csv");
    auto& o = f.stream();
    o << "time,max_position_error,max_orientation_error,tumble_kinetic,tumble_potential,"
         "bullet_kinetic,bullet_potential,tumble_contacts,bullet_contacts,tumble_com_x,"
         "tumble_com_y,tumble_com_z,bullet_com_x,bullet_com_y,bullet_com_z,tumble_pile_height,"
         "bullet_pile_height,tumble_at_rest,bullet_at_rest\n";
    for (const CompareSample& s : r.samples) {
      const Real values[] = {s.time,
                             s.max_position_error,
                             s.max_orientation_error,
                             s.tumble_kinetic,
                             s.tumble_potential,
                             s.bullet_kinetic,
                             s.bullet_potential};
      for (Real v : values) {
        write_number(o, v);
        o << ',';
      }
      o << s.tumble_contacts << ',' << s.bullet_contacts;
      for (const Vec3* c : {&s.tumble_com, &s.bullet_com}) {
        for (int a = 0; a < 3; ++a) {
          o << ',';
          write_number(o, (*c)[a]);
        }
      }
      o << ',';
      write_number(o, s.tumble_pile_height);
      o << ',';
      write_number(o, s.bullet_pile_height);
      o << ',' << s.tumble_at_rest << ',' << s.bullet_at_rest << '\n';
    }
    f.commit();
  }
  nlohmann::ordered_json j;
  j["scene"] = options.scene.string();
  j["mode"] = mode_name(r.chaotic);
  j["steps"] = r.steps;
  j["dt"] = scene->world.dt;
  j["max_position_error"] = r.max_position_error;
  j["max_orientation_error"] = r.max_orientation_error;
  j["max_relative_position_error"] = r.max_relative_position_error;
  j["max_centre_of_mass_error"] = r.max_com_error;
  j["final_pile_height_error"] = r.final_pile_height_error;
  j["final_energy_error"] = r.final_energy_error;
  const CompareSample& last = r.samples.back();
  j["final_bodies_at_rest"] = {{"tumble", last.tumble_at_rest}, {"bullet", last.bullet_at_rest}};
  j["final_contacts"] = {{"tumble", last.tumble_contacts}, {"bullet", last.bullet_contacts}};
  j["wall_seconds"] = {{"tumble", r.tumble_seconds}, {"bullet", r.bullet_seconds}};
  j["verdict"] = r.verdict;
  j["mismatches"] = r.mismatches;
  j["errors_csv"] = (dir / "errors.csv").string();
  j["timeline_csv"] = (dir / "timeline.csv").string();
  write_file_atomically(dir / "summary.json", json_text(j, 2) + "\n");
  std::cout << json_text(j, 2) << "\n";
  if (!options.quiet) {
    std::cerr << "tumble compare: " << r.verdict << "\n";
  }
  return 0;
}

}  // namespace tumble::app
