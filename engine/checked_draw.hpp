// A randomized draw of a scene already checked (a compiled model's description), for a batch's
// resets: randomized() checks the scene it is given, then the draw, and compile() checks the draw
// again; a batch's reset needs only the draw's check.
#pragma once

#include <cstdint>

#include "tumble/scene.hpp"

namespace tumble {

// randomized(scene, seed) for a scene that passed check_scene: the same draw, checked.
Scene randomized_from_checked(const Scene& checked, std::uint64_t seed);

// The same draw written over `out` (its vectors and strings keep their storage: a scene of the
// same shape allocates nothing). If the draw fails its check, `out` holds the failed draw.
// `out_drawn_from_checked`: `out` holds an earlier draw of `checked` (passed or failed), so only
// the fields a draw writes are written, each from `checked`'s own value.
void randomized_from_checked_into(const Scene& checked, std::uint64_t seed, Scene& out,
                                  bool out_drawn_from_checked = false);

}  // namespace tumble
