// A randomized draw of a scene already checked (a compiled model's description), for a batch's
// resets: randomized() checks the scene it is given, then the draw, and compile() checks the draw
// again; a batch's reset needs only the draw's check.
#pragma once

#include <cstdint>
#include <memory>

#include "tumble/model.hpp"
#include "tumble/scene.hpp"

namespace tumble {

// randomized(scene, seed) for a scene that passed check_scene: the same draw, checked.
Scene randomized_from_checked(const Scene& checked, std::uint64_t seed);

// The model of that draw, built without checking it a third time.
std::shared_ptr<const Model> compile_draw(const Scene& checked, std::uint64_t seed);

}  // namespace tumble
