// Scenes from YAML (docs/scene-format.md is the reference of every field).
#pragma once

#include <filesystem>
#include <memory>
#include <string_view>

#include "tumble/error.hpp"
#include "tumble/scene.hpp"

namespace tumble {

struct SceneLoadOptions {
  // Files a scene names (meshes, hulls, grids, volumes, networks, a sweep's scene) must lie in
  // the scene file's folder or below it, symbolic links followed, so that a scene from elsewhere
  // cannot make tumble read any file on the machine. A scene given as text has the current
  // folder as its own. True lifts the rule (the command line's --allow-outside-files).
  bool allow_outside_files = false;
};

// Loads and checks the scene in `path`. Throws SceneError naming the file, line, column and field
// of the first mistake (or the file, when it cannot be read).
std::shared_ptr<const Scene> load_scene(const std::filesystem::path& path,
                                        const SceneLoadOptions& options = {});
// The same from YAML text; `source_name` names it in messages.
std::shared_ptr<const Scene> load_scene_text(std::string_view yaml,
                                             std::string_view source_name = "<text>",
                                             const SceneLoadOptions& options = {});

}  // namespace tumble
