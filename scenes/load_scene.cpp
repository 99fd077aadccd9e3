// The public entry points of the YAML loader (include/tumble/load_scene.hpp).
#include "tumble/load_scene.hpp"

#include <memory>

#include "scenes/scene_loader.hpp"

namespace tumble {

std::shared_ptr<const Scene> load_scene(const std::filesystem::path& path) {
  return std::make_shared<const Scene>(load_scene_file(path));
}

std::shared_ptr<const Scene> load_scene_text(std::string_view yaml, std::string_view source_name) {
  return std::make_shared<const Scene>(load_scene_string(yaml, source_name));
}

}  // namespace tumble
