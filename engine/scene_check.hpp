// The check of one body description against a scene (include/tumble/model.hpp has check_scene):
// for bodies a world adds between steps.
#pragma once

#include <cstddef>
#include <string>

#include "tumble/model.hpp"

namespace tumble {

// Throws SceneError naming the field "bodies[slot]...." as check_scene would.
void check_body(const Scene& scene, const BodyDesc& body, std::size_t slot);

// check_scene for a randomized draw of a scene that passed it (engine/checked_draw.hpp): only
// what a draw can change (the world's settings, the materials, the bodies that are not static),
// since the rest is the checked scene's. Throws as check_scene would.
void check_drawn_scene(const Scene& draw);

// Why a principal moment is impossible for a body of `mass` within a bounding radius `radius` of
// its centre of mass (no particle is farther than R from an axis through the centre, so no
// moment exceeds m R^2), or empty when it is possible. check_scene refuses such a body; the scene
// loader asks first, to name the line.
std::string impossible_moment(Real mass, Real largest_moment, Real radius);

}  // namespace tumble
