// The JSON summary of a run: settings used, stages run with their timings, contact counts,
// energy, and the final state hash.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/simulation.hpp"
#include "engine/step_statistics.hpp"
#include "tumble/scene.hpp"

namespace tumble::app {

class RunSummary {
 public:
  RunSummary(const Scene& scene, const Simulation& world, const std::filesystem::path& scene_path,
             std::int64_t steps);
  void add_step(const StepStatistics& step);
  void finish(const Simulation& world, double wall_seconds,
              const std::filesystem::path& trajectory);
  std::string to_json() const;
  // The summary as a JSON object. Without `timings` it holds no wall time (no wall_seconds, no
  // stage seconds): what remains depends on the inputs alone, byte for byte.
  nlohmann::json to_json_object(bool timings) const;
  std::string final_hash_hex() const;
  // The names of the bodies the trajectory lists, in its order (trajectory.npy's second axis).
  void set_trajectory_bodies(const Scene& scene, const std::vector<int>& bodies);

 private:
  const Scene& scene_;
  std::filesystem::path scene_path_;
  std::int64_t steps_ = 0;
  BroadPhaseType broad_phase_used_;
  int world_threads_ = 1;  // the threads the world stepped on
  // The penalty solver may raise the scene's substeps, and the impulse solver an island's: the
  // most used in any step.
  int substeps_used_ = 1;
  StepStatistics totals_;
  std::int64_t max_contact_points_ = 0;
  Real initial_kinetic_ = 0;
  Real initial_potential_ = 0;
  Real final_kinetic_ = 0;
  Real final_potential_ = 0;
  double wall_seconds_ = 0;
  std::uint64_t final_hash_ = 0;
  Real final_time_ = 0;
  std::filesystem::path trajectory_;
  std::vector<std::string> trajectory_bodies_;
};

std::string hash_hex(std::uint64_t hash);

}  // namespace tumble::app
