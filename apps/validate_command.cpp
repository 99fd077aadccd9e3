#include "apps/validate_command.hpp"

#include <iostream>

#include "apps/scene_access.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble::app {

int validate_command(const std::filesystem::path& path) {
  const Scene scene = load_scene_file(path, {}, scene_load_options());
  int static_count = 0;
  for (const BodyDesc& b : scene.bodies)
    static_count += b.is_static ? 1 : 0;
  std::cout << path.string() << ": valid scene, " << scene.bodies.size() << " bodies ("
            << static_count << " static), " << scene.materials.size() << " materials, dt "
            << scene.world.dt << " s\n";
  return 0;
}

}  // namespace tumble::app
