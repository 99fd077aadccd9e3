// Small scenes built in code through the public API, shared by the API tests.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tumble/tumble.hpp"

namespace tumble::testing {

// A world of `bodies` under `gravity`, at 60 Hz.
inline std::shared_ptr<Scene> scene_of(std::vector<BodyDesc> bodies,
                                       const Vec3& gravity = Vec3(0, 0, -9.81)) {
  auto scene = std::make_shared<Scene>();
  scene->source = "api test";
  scene->world.gravity = gravity;
  scene->bodies = std::move(bodies);
  return scene;
}

inline BodyDesc ground() {
  return static_body("ground", Shape::box(Vec3(20, 20, 0.5)));
}

inline BodyDesc box_at(std::string name, const Vec3& position, Real half = Real(0.5)) {
  BodyDesc b = dynamic_body(std::move(name), Shape::box(Vec3::Constant(half)));
  b.position = position;
  return b;
}

// Whether the randomized draw of `scene` for `seed` passes its check.
inline bool draw_passes(const Scene& scene, std::uint64_t seed) {
  try {
    randomized(scene, seed);
    return true;
  } catch (const Error&) {
    return false;
  }
}

// Two compound parts on the x axis: a box of half extents `half` centred at x = `box_x`, and a
// sphere of `radius` centred at x = `sphere_x`.
inline std::vector<CompoundPart> box_and_sphere(const Vec3& half, Real box_x, Real radius,
                                                Real sphere_x) {
  std::vector<CompoundPart> parts{{Shape::box(half), Transform{}},
                                  {Shape::sphere(radius), Transform{}}};
  parts[0].pose.translation = Vec3(box_x, 0, 0);
  parts[1].pose.translation = Vec3(sphere_x, 0, 0);
  return parts;
}

// A compound body of `parts` (their poses about `origin`), of `density`: the body sits at the
// parts' centre of mass, so that each part stays where it was placed.
inline BodyDesc compound_at(std::string name, const std::vector<CompoundPart>& parts, Real density,
                            const Vec3& origin) {
  Vec3 centre = Vec3::Zero();
  BodyDesc b = dynamic_body(std::move(name), compound_from_parts(parts, &centre), density);
  b.position = origin + centre;
  return b;
}

// Writes force(w, b) on every body b after the first (the ground) of every world w of a batch,
// for its next step.
template <class Force>
void write_batch_forces(BatchWorld& batch, const Force& force) {
  const int bodies = batch.body_count();
  std::span<Real> f = batch.forces();
  for (int w = 0; w < batch.size(); ++w)
    for (int b = 1; b < bodies; ++b) {
      const Vec3 push = force(w, b);
      for (int c = 0; c < 3; ++c)
        f[std::size_t((w * bodies + b) * 3 + c)] = push[c];
    }
}

}  // namespace tumble::testing
