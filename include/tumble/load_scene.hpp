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

// One shape written as a scene writes a body's `shape` (docs/scene-format.md), for example
//   {type: sdf, sdf: {difference: [{box: {half_extents: [1, 1, 0.5]}},
//                                  {sphere: {radius: 0.9}, position: [0, 0, 0.6]}]}}
// This builds what the Shape factories do not: signed distance fields of every kind (analytic,
// CSG, grids from OBJ meshes, OpenVDB volumes, networks; docs/sdf.md), meshes and hulls read from
// files. Files are found as for a scene given as text. `centre_of_mass`, when given, receives
// where the shape's centre of mass lies in the frame it was written in (hulls, compounds and
// fields are re-centred there; zero otherwise). Throws SceneError naming the line and field.
Shape load_shape_text(std::string_view yaml, std::string_view source_name = "<shape>",
                      Vec3* centre_of_mass = nullptr, const SceneLoadOptions& options = {});

}  // namespace tumble
