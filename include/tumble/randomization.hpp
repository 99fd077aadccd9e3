// Domain randomization: what a scene's `randomize:` block draws for each world, and the draw
// itself. A randomized world is an ordinary scene made from the original and a 64-bit seed, so
// the same seed gives the same world on any machine with the same build (docs/scene-format.md,
// "randomize").
#pragma once

#include <cstdint>
#include <optional>

#include "tumble/math.hpp"

namespace tumble {

struct Scene;

// A closed interval [low, high] a value is drawn from, uniformly.
struct Interval {
  Real low = 0;
  Real high = 0;
};

// Unset fields draw nothing. Each quantity draws from its own stream of the seed, so turning one
// on does not change what another draws.
struct Randomization {
  // Per material: its friction and restitution (then mixed per pair by the scene's rules).
  std::optional<Interval> friction;
  std::optional<Interval> restitution;
  // Per dynamic body: a factor on its mass and inertia.
  std::optional<Interval> mass_scale;
  // Per dimension of each dynamic or kinematic body's shape (a box's three half extents, a
  // radius, a half length, a hull's extent along each of its axes, each compound part's own):
  // a factor 1 + n with n ~ Normal(0, size_noise), cut at three standard deviations. A dynamic
  // body keeps its density, so its mass and inertia follow the new shape.
  Real size_noise = 0;
  // Per dynamic body: its initial position moves by Normal(0, position_noise) on each axis [m],
  // and its orientation turns by a rotation vector of Normal(0, orientation_noise) components
  // [rad].
  Real position_noise = 0;
  Real orientation_noise = 0;
  // Per world: each gravity component uniform in [gravity_low, gravity_high] [m/s^2].
  std::optional<Vec3> gravity_low;
  std::optional<Vec3> gravity_high;

  bool any() const {
    return friction || restitution || mass_scale || size_noise > 0 || position_noise > 0 ||
           orientation_noise > 0 || gravity_low;
  }
};

// The scene with its `randomize` draws for `seed` applied (and its randomization cleared, so the
// result can be drawn from again only on purpose). Throws SceneError if `scene` fails its check.
Scene randomized(const Scene& scene, std::uint64_t seed);

}  // namespace tumble
