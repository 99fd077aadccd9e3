// Scenes from YAML (docs/scene-format.md is the reference of every field).
#pragma once

#include <filesystem>
#include <memory>
#include <string_view>

#include "tumble/error.hpp"
#include "tumble/scene.hpp"

namespace tumble {

// Loads and checks the scene in `path`. Throws SceneError naming the file, line, column and field
// of the first mistake (or the file, when it cannot be read).
std::shared_ptr<const Scene> load_scene(const std::filesystem::path& path);
// The same from YAML text; `source_name` names it in messages.
std::shared_ptr<const Scene> load_scene_text(std::string_view yaml,
                                             std::string_view source_name = "<text>");

}  // namespace tumble
