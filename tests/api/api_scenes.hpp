// Small scenes built in code through the public API, shared by the API tests.
#pragma once

#include <memory>

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

}  // namespace tumble::testing
