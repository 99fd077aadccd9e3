// Reads a scene from YAML and validates every field (docs/scene-format.md is the reference).
// The loader is strict on purpose: a scene that loads is one the engine can run, and a mistake
// is reported once, with file, line, column and the full path of the field, instead of turning
// into a NaN or a tunnelling body a thousand steps later.
//
// This header does not include yaml-cpp: scene_loader.cpp is the only code that does, so the
// YAML library stays a private detail of tumble_scenes.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "tumble/error.hpp"
#include "tumble/load_scene.hpp"
#include "tumble/scene.hpp"

namespace tumble {

// Loads and validates the scene in `path`; Scene::source is set to the path as given.
// Throws SceneError, and nothing else, on any problem (including a missing file).
Scene load_scene_file(const std::filesystem::path& path);

// A field of the scene set to another value before it is read: `field` is its dotted path
// (`world.dt`, `materials.default.friction`, `bodies.2.mass` or `bodies.crate.mass` by name) and
// `value` the YAML of the new value (`0.005`, `[0, 0, -1.62]`, `penalty`). A field the file leaves
// out is added; the scene is then read and checked as if the file said so, and a bad value gets
// the loader's own message (with no line: it is not in the file). A list item shared through a
// YAML alias is copied, so only the path named changes.
struct FieldOverride {
  std::string field;
  std::string value;
};

// Loads and validates the scene in `path` with `overrides` applied in order.
Scene load_scene_file(const std::filesystem::path& path, std::span<const FieldOverride> overrides,
                      const SceneLoadOptions& options = {});

// Loads and validates a scene from YAML text; `source_name` names it in messages and becomes
// Scene::source. Throws SceneError, and nothing else.
Scene load_scene_string(std::string_view yaml, std::string_view source_name);
Scene load_scene_string(std::string_view yaml, std::string_view source_name,
                        std::span<const FieldOverride> overrides,
                        const SceneLoadOptions& options = {});

}  // namespace tumble
