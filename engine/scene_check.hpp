// The check of one body description against a scene (include/tumble/model.hpp has check_scene):
// for bodies a world adds between steps.
#pragma once

#include <cstddef>

#include "tumble/model.hpp"

namespace tumble {

// Throws SceneError naming the field "bodies[slot]...." as check_scene would.
void check_body(const Scene& scene, const BodyDesc& body, std::size_t slot);

}  // namespace tumble
