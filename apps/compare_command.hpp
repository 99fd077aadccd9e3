// `tumble compare SCENE.yaml [-o DIR]`: runs the scene in tumble and in Bullet (apps/
// bullet_bridge.hpp) in one process, step by step, and writes per-body position and
// orientation errors over time, both engines' energies and contact counts, and a verdict.
// Chaotic scenes (oracle_metrics.hpp) are judged by statistics instead of paths.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "apps/bullet_bridge.hpp"
#include "tumble/scene.hpp"

namespace tumble::app {

enum class CompareMode { automatic, paths, statistics };

struct CompareOptions {
  std::optional<int> threads;  // overrides the scene's world.threads
  std::filesystem::path scene;
  std::filesystem::path output_dir;  // default out/<scene stem>-compare
  CompareMode mode = CompareMode::automatic;
  std::optional<std::int64_t> steps;
  std::int64_t samples = 200;  // rows of the time series (about)
  bool quiet = false;
  std::optional<double> bullet_breaking_threshold;  // gContactBreakingThreshold, default 0.02
};

// One sample of the comparison.
struct CompareSample {
  Real time = 0;
  Real max_position_error = 0;     // m, over bodies
  Real max_orientation_error = 0;  // rad, over bodies
  Real tumble_kinetic = 0, tumble_potential = 0, bullet_kinetic = 0, bullet_potential = 0;  // J
  std::int64_t tumble_contacts = 0, bullet_contacts = 0;
  Vec3 tumble_com = Vec3::Zero(), bullet_com = Vec3::Zero();  // m
  Real tumble_pile_height = 0, bullet_pile_height = 0;        // m
  int tumble_at_rest = 0, bullet_at_rest = 0;
};

struct CompareResult {
  bool chaotic = false;  // judged by statistics
  std::int64_t steps = 0;
  Real max_position_error = 0;           // m, over bodies and the whole run
  Real max_orientation_error = 0;        // rad
  Real max_relative_position_error = 0;  // max |dx| / max(|x_bullet - x_0|, 1e-300) per body
  Real max_com_error = 0;                // m
  Real final_pile_height_error = 0;      // m
  Real final_energy_error = 0;           // J, total energy
  Real scene_size = 1;                   // m
  double tumble_seconds = 0, bullet_seconds = 0;
  std::vector<CompareSample> samples;
  // Per-body errors at the sampled steps: rows of (sample index, body, position, orientation).
  struct BodyError {
    std::int64_t sample;
    int body;
    Real position, orientation;
  };
  std::vector<BodyError> body_errors;
  std::vector<std::string> mismatches;
  std::string verdict;
};

// Runs the comparison (no files). `bullet` defaults to matching_bullet_settings(scene).
CompareResult compare_scene(const std::shared_ptr<const Scene>& scene, std::int64_t steps,
                            CompareMode mode, std::int64_t samples,
                            const std::optional<BulletSettings>& bullet = std::nullopt);

// Steps a scene runs for: the scene's `steps`, else ceil(duration / dt).
std::int64_t scene_steps(const Scene& scene);

int compare_command(const CompareOptions& options);

}  // namespace tumble::app
