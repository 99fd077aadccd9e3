#include "apps/oracle_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "collision/shapes/shape.hpp"

namespace tumble::app {

Real orientation_error(const Quat& a, const Quat& b) {
  // |<a, b>| = cos(angle / 2); the sine form keeps precision for tiny angles.
  const Quat d = a.conjugate() * b;
  const Real s = d.vec().norm();
  return 2 * std::atan2(s, std::abs(d.w()));
}

PileStatistics pile_statistics(const Scene& scene, const std::vector<BodyState>& bodies) {
  PileStatistics p;
  Real total_mass = 0;
  const Vec3 up =
      scene.world.gravity.norm() > 0 ? Vec3(-scene.world.gravity.normalized()) : Vec3(0, 0, 1);
  bool any = false;
  p.pile_height = 0;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDesc& d = scene.bodies[i];
    if (d.is_static)
      continue;
    const BodyState& b = bodies[i];
    p.centre_of_mass += d.mass * b.position;
    total_mass += d.mass;
    const Real top = b.position.dot(up) + bounding_radius(d.shape);
    p.pile_height = any ? std::max(p.pile_height, top) : top;
    any = true;
    if (b.velocity.norm() < Real(0.05) && b.angular_velocity.norm() < Real(0.1))
      ++p.bodies_at_rest;
  }
  if (total_mass > 0)
    p.centre_of_mass /= total_mass;
  return p;
}

bool scene_is_chaotic(const Scene& scene) {
  int moving = 0;
  bool spinning = false;
  for (const BodyDesc& d : scene.bodies) {
    if (d.is_static)
      continue;
    ++moving;
    spinning = spinning || d.angular_velocity.norm() > 0;
  }
  return moving > 10 || (moving > 1 && spinning);
}

Real scene_size(const Scene& scene) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity());
  Vec3 hi = -lo;
  for (const BodyDesc& d : scene.bodies) {
    if (d.is_static)
      continue;
    lo = lo.cwiseMin(d.position);
    hi = hi.cwiseMax(d.position);
  }
  if (!(lo.array() <= hi.array()).all())
    return 1;
  return (hi - lo).norm() + 1;
}

std::string position_verdict(Real max_position_error, Real size) {
  const Real relative = max_position_error / size;
  char amount[96];
  std::snprintf(amount, sizeof amount, "max position error %.3g m, %.3g of the scene size",
                max_position_error, relative);
  if (relative <= Real(1e-9))
    return std::string("paths identical to rounding (") + amount + ")";
  if (relative <= Real(1e-3))
    return std::string("paths agree closely (") + amount + ", below 0.1%)";
  if (relative <= Real(5e-2))
    return std::string("paths agree roughly (") + amount + ", below 5%)";
  return std::string("paths differ (") + amount + ", above 5%)";
}

}  // namespace tumble::app
