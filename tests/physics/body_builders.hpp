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

}  // namespace tumble::test
