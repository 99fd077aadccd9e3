#include "apps/run_summary.hpp"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "apps/json_text.hpp"
#include "collision/broad_phase/broad_phase_factory.hpp"

namespace tumble::app {
namespace {

const char* solver_name(SolverType s) {
  return s == SolverType::impulse ? "impulse" : "penalty";
}
const char* ccd_name(CcdMode c) {
  switch (c) {
    case CcdMode::automatic:
      return "auto";
    case CcdMode::on:
      return "on";
    case CcdMode::off:
      return "off";
  }
  return "auto";
}

nlohmann::json vec(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

std::string hash_hex(std::uint64_t hash) {
  char buffer[19];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(hash));
  return buffer;
}

RunSummary::RunSummary(const Scene& scene, const Simulation& world,
                       const std::filesystem::path& scene_path, std::int64_t steps)
    : scene_(scene),
      scene_path_(scene_path),
      steps_(steps),
      broad_phase_used_(world.broad_phase_type()),
      world_threads_(world.threads()) {
  substeps_used_ =
      scene.world.solver == SolverType::penalty ? world.penalty_substeps() : scene.world.substeps;
  initial_kinetic_ = world.kinetic_energy();
  initial_potential_ = world.potential_energy();
}

void RunSummary::add_step(const StepStatistics& step) {
  totals_.accumulate(step);
  max_contact_points_ = std::max(max_contact_points_, step.contact_points);
}

void RunSummary::finish(const Simulation& world, double wall_seconds,
                        const std::filesystem::path& trajectory) {
  final_kinetic_ = world.kinetic_energy();
  final_potential_ = world.potential_energy();
  wall_seconds_ = wall_seconds;
  final_hash_ = state_hash(world.state());
  final_time_ = world.state().time;
  trajectory_ = trajectory;
}

std::string RunSummary::final_hash_hex() const {
  return hash_hex(final_hash_);
}

void RunSummary::set_trajectory_bodies(const Scene& scene, const std::vector<int>& bodies) {
  trajectory_bodies_.clear();
  for (const int i : bodies)
    trajectory_bodies_.push_back(scene.bodies[std::size_t(i)].name);
}

std::string RunSummary::to_json() const {
  return json_text(to_json_object(true), 2);
}

nlohmann::json RunSummary::to_json_object(bool timings) const {
  using nlohmann::json;
  const WorldSettings& w = scene_.world;
  json settings = {{"dt", w.dt},
                   {"steps", steps_},
                   {"substeps", w.substeps},
                   {"substeps_used", std::max(substeps_used_, totals_.max_substeps)},
                   {"sleeping", w.sleeping},
                   {"threads", world_threads_},
                   {"solver", solver_name(w.solver)},
                   {"iterations", w.iterations},
                   {"relax_iterations", w.relax_iterations},
                   {"broadphase", std::string(broad_phase_name(w.broadphase))},
                   {"broadphase_used", std::string(broad_phase_name(broad_phase_used_))},
                   {"ccd", ccd_name(w.ccd)},
                   {"gravity", vec(w.gravity)},
                   {"contact_recycling", w.contact_recycling},
                   {"contact_margin", w.contact_margin},
                   {"penetration_slop", w.penetration_slop},
                   {"contact_hertz", w.contact_hertz ? json(*w.contact_hertz) : json("auto")},
                   {"max_substeps", w.max_substeps},
                   {"sag_tolerance", w.sag_tolerance},
                   {"contact_damping_ratio", w.contact_damping_ratio},
                   {"max_push_velocity", w.max_push_velocity},
                   {"restitution_threshold", w.restitution_threshold}};
  json stages = json::object();
  double stage_total = 0;
  for (int i = 0; i < kStageCount; ++i) {
    stages[std::string(stage_name(static_cast<Stage>(i)))] = {{"ran", totals_.ran[i]},
                                                              {"seconds", totals_.seconds[i]}};
    stage_total += totals_.seconds[i];
  }
  // The solve stage split into its phases (they add up to its seconds).
  json phases = json::object();
  for (int i = 0; i < kSolvePhaseCount; ++i)
    phases[std::string(solve_phase_name(static_cast<SolvePhase>(i)))] =
        totals_.solve_phase_seconds[std::size_t(i)];
  stages[std::string(stage_name(Stage::solve))]["phases"] = phases;
  if (!timings) {
    for (int i = 0; i < kStageCount; ++i)
      stages[std::string(stage_name(static_cast<Stage>(i)))] = {{"ran", totals_.ran[i]}};
  }
  const double per_step = steps_ > 0 ? wall_seconds_ / static_cast<double>(steps_) : 0.0;
  json summary = {
      {"tumble_version", "0.1.0"},
      {"scene", scene_path_.string()},
      {"bodies", scene_.bodies.size()},
      {"settings", settings},
      {"simulated_seconds", final_time_},
      {"wall_seconds", wall_seconds_},
      {"wall_seconds_per_step", per_step},
      {"stages", stages},
      {"stage_seconds_total", stage_total},
      {"counts",
       {{"candidate_pairs", totals_.candidate_pairs},
        {"touching_pairs", totals_.touching_pairs},
        {"recycled_pairs", totals_.recycled_pairs},
        {"recomputed_pairs", totals_.recomputed_pairs},
        {"resting_pairs", totals_.resting_pairs},
        {"axis_cache_tries", totals_.axis_cache_tries},
        {"axis_cache_hits", totals_.axis_cache_hits},
        {"gjk_warm_starts", totals_.gjk_warm_starts},
        {"sdf_refinements", totals_.sdf_refinements},
        {"sdf_refinements_capped", totals_.sdf_refinements_capped},
        {"contact_points", totals_.contact_points},
        {"max_contact_points_in_a_step", max_contact_points_},
        {"solver_iterations", totals_.solver_iterations},
        {"ccd_swept_bodies", totals_.swept_bodies},
        {"ccd_stopped_bodies", totals_.stopped_bodies},
        {"ccd_impact_rounds", totals_.impact_rounds},
        {"ccd_candidate_pairs", totals_.ccd_candidate_pairs}}},
      {"energy",
       {{"initial",
         {{"kinetic", initial_kinetic_},
          {"potential", initial_potential_},
          {"total", initial_kinetic_ + initial_potential_}}},
        {"final",
         {{"kinetic", final_kinetic_},
          {"potential", final_potential_},
          {"total", final_kinetic_ + final_potential_}}}}},
      {"final_state_hash", final_hash_hex()},
      {"outputs",
       {{"trajectory", trajectory_.string()}, {"trajectory_bodies", trajectory_bodies_}}}};
  if (!timings) {
    for (const char* key : {"wall_seconds", "wall_seconds_per_step", "stage_seconds_total"})
      summary.erase(key);
  }
  return summary;
}

}  // namespace tumble::app
