// Bodies built in code with mass properties from their shape (include/tumble/scene.hpp).
#include <cmath>
#include <string>
#include <utility>

#include "collision/shapes/shape.hpp"
#include "engine/number_text.hpp"
#include "tumble/error.hpp"
#include "tumble/scene.hpp"

namespace tumble {
namespace {

void require_bounded(const Shape& shape, const std::string& name, const char* kind) {
  if (!shape.is_bounded() || shape.type == ShapeType::mesh)
    throw Error("body '" + name + "': a " + std::string(shape_type_name(shape.type)) +
                " cannot be " + kind + "; only static");
}

}  // namespace

BodyDesc dynamic_body(std::string name, Shape shape, std::optional<Real> given_density) {
  require_bounded(shape, name, "dynamic");
  // As in a scene file (docs/scene-format.md): a field's mass is not assumed.
  if (!given_density && shape.type == ShapeType::sdf)
    throw Error("body '" + name +
                "': a dynamic signed distance field needs a density (its volume is integrated "
                "over its cells)");
  const Real density = given_density.value_or(Real(1000));
  if (!(std::isfinite(density) && density > 0))
    throw Error("body '" + name + "': density must be positive and finite, got " +
                number_text(density));
  BodyDesc d;
  d.name = std::move(name);
  d.mass = density * volume(shape);
  d.inertia = d.mass * unit_inertia(shape);
  d.shape = std::move(shape);
  return d;
}

BodyDesc static_body(std::string name, Shape shape) {
  BodyDesc d;
  d.name = std::move(name);
  d.shape = std::move(shape);
  d.is_static = true;
  return d;
}

BodyDesc kinematic_body(std::string name, Shape shape) {
  require_bounded(shape, name, "kinematic");
  BodyDesc d;
  d.name = std::move(name);
  d.shape = std::move(shape);
  d.kinematic = true;
  return d;
}

}  // namespace tumble
