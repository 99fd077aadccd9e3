// The options every command loads its scene, query and sweep files with: one value for the
// whole run, set from the command line (--allow-outside-files) before a command starts.
#pragma once

#include "tumble/load_scene.hpp"

namespace tumble::app {

SceneLoadOptions& scene_load_options();

}  // namespace tumble::app
