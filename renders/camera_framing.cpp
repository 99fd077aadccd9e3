#include "renders/camera_framing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tumble::render {

Aabb bounds_of_bodies(const Scene& scene, const State& state) {
  bool any = false;
  Aabb box;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const Shape& shape = scene.bodies[i].shape;
    if (!shape.is_bounded())
      continue;
    const BodyState& b = state.bodies[i];
    const Aabb body = world_aabb(shape, Transform{b.position, b.orientation});
    box = any ? Aabb{box.min.cwiseMin(body.min), box.max.cwiseMax(body.max)} : body;
    any = true;
  }
  if (!any)
    box = Aabb{Vec3::Constant(-1), Vec3::Constant(1)};
  return box;
}

Camera frame_bounds(const Aabb& bounds, double aspect, Real fov_degrees) {
  const Vec3 centre = Real(0.5) * (bounds.min + bounds.max);
  const Real radius = std::max(Real(0.5) * (bounds.max - bounds.min).norm(), Real(0.25));
  const Real half_vertical = fov_degrees * std::numbers::pi_v<Real> / 360;
  const Real half_horizontal = std::atan(std::tan(half_vertical) * aspect);
  const Real half_narrowest = std::min(half_vertical, half_horizontal);
  // Fits the sphere with a tenth to spare.
  const Real distance = Real(1.1) * radius / std::sin(half_narrowest);
  Camera camera;
  camera.target = centre;
  camera.position = centre + distance * Vec3(1, -1, Real(0.7)).normalized();
  camera.fov = fov_degrees;
  return camera;
}

Camera choose_camera(const Scene& scene, const State& state, double aspect) {
  if (scene.camera)
    return *scene.camera;
  return frame_bounds(bounds_of_bodies(scene, state), aspect);
}

}  // namespace tumble::render
