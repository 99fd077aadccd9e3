// Golden state hashes: every scene in scenes/ under both solvers, stepped a few steps, must end in
// the state hash recorded in tests/data/golden_hashes.json (as Box2D's test_determinism checks
// its samples). A change that moves a hash on purpose regenerates the file in the same commit
// and says why:
//
//   TUMBLE_UPDATE_GOLDEN=1 build/release/tests/test_golden
//
// The steps per scene are few (30 for small scenes, down to 3 for the thousands-of-bodies
// benchmarks: the budget is about 3,000 body-steps a scene) so that the sanitizer run can afford
// them; divergence shows in the first steps anyway, since the hash covers every body's state and
// the contact cache. The solver is the scene's own and then the other one, with everything else
// as the file says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "collision/sdf/vdb_level_set.hpp"
#include "tests/property_scale.hpp"
#include "tumble/load_scene.hpp"
#include "tumble/world.hpp"

namespace tumble {
namespace {

namespace fs = std::filesystem;

const fs::path kGoldenFile = fs::path(TUMBLE_SOURCE_DIR) / "tests" / "data" / "golden_hashes.json";

std::vector<fs::path> every_scene() {
  std::vector<fs::path> out;
  const fs::path root = fs::path(TUMBLE_SOURCE_DIR) / "scenes";
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const fs::path& p = entry.path();
    // Sweep files describe runs of a scene, not a scene.
    if (p.extension() == ".yaml" && p.parent_path().filename() != "sweeps")
      out.push_back(p);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Scenes that need OpenVDB (a level set built or read by it) are measured only in builds with it.
bool needs_openvdb(const fs::path& scene) {
  std::ifstream in(scene);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return text.find("builder: openvdb") != std::string::npos ||
         text.find(".vdb") != std::string::npos;
}

std::string hex(std::uint64_t h) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

TEST(GoldenHashes, EverySceneUnderBothSolversEndsWhereRecorded) {
  // The instrumented run (TUMBLE_PROPERTY_SCALE < 1) leaves this to the optimised one: the same
  // code, ten times slower (two minutes here), and its memory checks are the other tests' job.
  if (property_scale() < 1)
    GTEST_SKIP() << "golden hashes are checked by the optimised build";
  const bool update = std::getenv("TUMBLE_UPDATE_GOLDEN") != nullptr;
  std::map<std::string, std::string> recorded;
  if (!update) {
    std::ifstream in(kGoldenFile);
    ASSERT_TRUE(in) << kGoldenFile << " is missing; create it with TUMBLE_UPDATE_GOLDEN=1";
    const nlohmann::json j = nlohmann::json::parse(in);
    for (const auto& [key, value] : j.items())
      recorded[key] = value.get<std::string>();
  }
  std::map<std::string, std::string> measured;
  const auto scenes = every_scene();
  ASSERT_GE(scenes.size(), 40u);
  std::vector<std::string> left_out;
  for (const fs::path& path : scenes) {
    if (needs_openvdb(path) && !VdbLevelSet::available()) {
      left_out.push_back(fs::relative(path, fs::path(TUMBLE_SOURCE_DIR)).string() + " ");
      continue;
    }
    const auto base = load_scene(path);
    const std::string name = fs::relative(path, fs::path(TUMBLE_SOURCE_DIR)).string();
    const int bodies = int(base->bodies.size());
    const int steps = std::clamp(3000 / std::max(bodies, 1), 3, 30);
    for (SolverType solver : {SolverType::impulse, SolverType::penalty}) {
      auto scene = std::make_shared<Scene>(*base);
      scene->world.solver = solver;
      World world(scene);
      world.step(steps);
      const std::string key = name + " " + (solver == SolverType::impulse ? "impulse" : "penalty") +
                              " " + std::to_string(steps);
      measured[key] = hex(world.state_hash());
    }
  }
  if (update) {
    nlohmann::json j(measured);
    std::ofstream out(kGoldenFile);
    out << j.dump(2) << "\n";
    GTEST_SKIP() << "wrote " << measured.size() << " hashes to " << kGoldenFile;
  }
  for (const auto& [key, hash] : measured) {
    const auto found = recorded.find(key);
    if (found == recorded.end()) {
      ADD_FAILURE() << key << ": no recorded hash (a new scene: regenerate the file)";
      continue;
    }
    EXPECT_EQ(hash, found->second) << key;
  }
  for (const auto& entry : recorded) {
    const std::string& key = entry.first;  // a named reference: clang 14 captures no bindings
    const bool skipped = std::any_of(left_out.begin(), left_out.end(),
                                     [&](const std::string& s) { return key.rfind(s, 0) == 0; });
    EXPECT_TRUE(skipped || measured.count(key)) << key << ": recorded but no longer measured";
  }
}

}  // namespace
}  // namespace tumble
