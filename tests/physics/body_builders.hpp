// Bodies for scenes built in code by the physics tests.
#pragma once

#include <string>

#include "tumble/scene.hpp"

namespace tumble::test {

// A dynamic body of uniform density: mass [kg], inertia from the shape.
inline BodyDesc dynamic_body(const std::string& name, const Shape& shape, const Vec3& position,
                             const Vec3& velocity, Real mass) {
  BodyDesc b;
  b.name = name;
  b.shape = shape;
  b.position = position;
  b.velocity = velocity;
  b.mass = mass;
  b.inertia = b.mass * unit_inertia(shape);
  return b;
}

inline BodyDesc static_body(const std::string& name, const Shape& shape, const Vec3& position) {
  BodyDesc b;
  b.name = name;
  b.shape = shape;
  b.position = position;
  b.is_static = true;
  return b;
}

// An empty world without gravity whose one material is frictionless with `restitution`, and
// continuous collision on `auto`: for impacts whose outcome has a closed form.
inline Scene frictionless_space(const std::string& source, Real restitution) {
  Scene s;
  s.source = source;
  s.world.gravity = Vec3::Zero();
  s.world.ccd = CcdMode::automatic;
  s.materials.push_back(Material{"default", 0.0, restitution});
  return s;
}

}  // namespace tumble::test
