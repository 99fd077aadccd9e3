// Reads a scene from YAML and validates every field (docs/scene-format.md is the reference).
// The loader is strict on purpose: a scene that loads is one the engine can run, and a mistake
// is reported once, with file, line, column and the full path of the field, instead of turning
// into a NaN or a tunnelling body a thousand steps later.
//
// This header does not include yaml-cpp: scene_loader.cpp is the only code that does, so the
// YAML library stays a private detail of tumble_scenes.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "engine/scene.hpp"

namespace tumble {

// The one exception the loader throws. what() is the full one-line message:
//   FILE:LINE:COLUMN: field 'bodies[2].shape.radius': expected a positive number ..., got -1
// Where there is no position (a file that cannot be opened) it reads `FILE: reason`.
struct SceneError : std::runtime_error {
  SceneError(std::string file, int line, int column, std::string field, std::string reason);

  std::string file;    // the source name given to the loader (a path for files)
  int line = 0;        // 1-based; 0 when the error has no position in the text
  int column = 0;      // 1-based; 0 when the error has no position in the text
  std::string field;   // dotted path such as "bodies[2].shape.radius"; empty for syntax errors
  std::string reason;  // the message without the "FILE:LINE:COLUMN: field '...': " prefix
};

// Loads and validates the scene in `path`; Scene::source is set to the path as given.
// Throws SceneError, and nothing else, on any problem (including a missing file).
Scene load_scene_file(const std::filesystem::path& path);

// Loads and validates a scene from YAML text; `source_name` names it in messages and becomes
// Scene::source. Throws SceneError, and nothing else.
Scene load_scene_string(std::string_view yaml, std::string_view source_name);

}  // namespace tumble
