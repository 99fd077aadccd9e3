// Loads a shipped scene from scenes/ into a Simulation: the same files users run are the ones the
// acceptance tests check (one scene, several uses).
#pragma once

#include <memory>
#include <string>

#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble::test {

inline std::shared_ptr<const Scene> shipped_scene(const std::string& name) {
  return std::make_shared<const Scene>(
      load_scene_file(std::string(TUMBLE_SOURCE_DIR) + "/scenes/" + name));
}

inline int body_index(const Scene& scene, const std::string& name) {
  const int i = scene.find_body(name);
  if (i < 0)
    throw std::runtime_error("no body named " + name);
  return i;
}

}  // namespace tumble::test
