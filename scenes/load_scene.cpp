// The public entry points of the YAML loader (include/tumble/load_scene.hpp).
#include "tumble/load_scene.hpp"

#include <memory>

#include "scenes/scene_loader.hpp"

namespace tumble {

std::shared_ptr<const Scene> load_scene(const std::filesystem::path& path,
                                        const SceneLoadOptions& options) {
  return std::make_shared<const Scene>(load_scene_file(path, {}, options));
}

std::shared_ptr<const Scene> load_scene_text(std::string_view yaml, std::string_view source_name,
                                             const SceneLoadOptions& options) {
  return std::make_shared<const Scene>(load_scene_string(yaml, source_name, {}, options));
}

}  // namespace tumble
