// Shared helpers of the Bullet oracle tests: shipped scenes, and stepping tumble and Bullet in
// lockstep while a callback looks at both.
#pragma once

#include <memory>
#include <string>

#include "apps/bullet_bridge.hpp"
#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble::test {

inline std::shared_ptr<const Scene> oracle_scene(const std::string& name) {
  return std::make_shared<const Scene>(
      load_scene_file(std::string(TUMBLE_SOURCE_DIR) + "/scenes/" + name));
}

// Steps both engines `steps` times with the matching Bullet settings; after every step calls
// visit(step, world, bullet).
template <class Visit>
void lockstep(const std::shared_ptr<const Scene>& scene, std::int64_t steps, Visit&& visit,
              const app::BulletSettings* settings = nullptr) {
  Simulation world(scene);
  app::BulletWorld bullet(*scene, settings ? *settings : app::matching_bullet_settings(*scene));
  for (std::int64_t k = 1; k <= steps; ++k) {
    world.step();
    bullet.step();
    visit(k, world, bullet);
  }
}

}  // namespace tumble::test
