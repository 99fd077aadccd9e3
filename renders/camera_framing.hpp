// Where the renderer looks from: the scene's `camera:` when it has one, else a camera framed
// automatically around the bounded bodies.
#pragma once

#include "engine/state.hpp"
#include "tumble/scene.hpp"

namespace tumble::render {

// Simulation-space box around every bounded body in `state` (planes excluded). Empty scenes and
// plane-only scenes get a unit box around the origin.
Aabb bounds_of_bodies(const Scene& scene, const State& state);

// A camera looking at the centre of `bounds` from the front-right and above (the direction the
// shipped scenes use, +x -y +z), far enough that the bounding sphere fits the narrower of the
// vertical and horizontal fields of view.
Camera frame_bounds(const Aabb& bounds, double aspect, Real fov_degrees = 45);

// The scene's camera, or frame_bounds around the bodies in `state`.
Camera choose_camera(const Scene& scene, const State& state, double aspect);

}  // namespace tumble::render
