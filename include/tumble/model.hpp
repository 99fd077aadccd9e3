// A scene compiled once for the engine (MuJoCo's model): the scene checked field by field, and
// what every world of it derives from it (masses, inertias, bounding radii, combined materials).
// A model is immutable; any number of worlds may share one.
#pragma once

#include <memory>

#include "tumble/scene.hpp"

namespace tumble {

class Model;  // engine/model.hpp; opaque to users

// Checks every field of `scene` against the ranges docs/scene-format.md states (the YAML loader
// applies the same rules) and throws SceneError naming the first bad field and its value:
//   SOURCE: field 'bodies[2].mass': expected a positive mass in kilograms (1e-12 to 1e15), got -1
void check_scene(const Scene& scene);

// check_scene, then the model. Throws SceneError.
std::shared_ptr<const Model> compile(std::shared_ptr<const Scene> scene);

// The scene a model was compiled from.
const Scene& scene_of(const Model& model);

}  // namespace tumble
