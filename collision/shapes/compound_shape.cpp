#include "collision/shapes/compound_shape.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "collision/shapes/shape.hpp"

namespace tumble {

CompoundShape CompoundShape::build(std::vector<CompoundPart> parts, Vec3* centre_of_mass,
                                   bool recentre) {
  if (parts.empty())
    throw CompoundError("a compound needs at least one part");
  if (int(parts.size()) > kMaxParts)
    throw CompoundError("a compound has at most " + std::to_string(kMaxParts) + " parts, got " +
                        std::to_string(parts.size()));
  Real total = 0;
  Vec3 moment = Vec3::Zero();
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const CompoundPart& p = parts[i];
    const std::string name = "part " + std::to_string(i);
    if (!p.shape.is_bounded() || p.shape.type == ShapeType::mesh ||
        p.shape.type == ShapeType::compound)
      throw CompoundError(name + " is a " + std::string(shape_type_name(p.shape.type)) +
                          "; parts must be bounded convex shapes");
    // Every size positive and finite, and a hull part with its hull: a negative extent would pass
    // the volume test below when two are negative.
    const Shape& ps = p.shape;
    const bool sizes_ok = ps.type == ShapeType::box
                              ? (ps.half_extents.array() > 0).all() && ps.half_extents.allFinite()
                          : ps.type == ShapeType::hull ? ps.hull != nullptr
                          : ps.type == ShapeType::sphere
                              ? ps.radius > 0 && std::isfinite(ps.radius)
                              : ps.radius > 0 && std::isfinite(ps.radius) && ps.half_length >= 0 &&
                                    std::isfinite(ps.half_length);
    if (!sizes_ok)
      throw CompoundError(name + " (a " + std::string(shape_type_name(ps.type)) +
                          ") has a size that is not positive and finite, or no hull");
    if (!p.pose.translation.allFinite() || !p.pose.rotation.coeffs().allFinite() ||
        std::abs(p.pose.rotation.norm() - 1) > Real(1e-6))
      throw CompoundError(name + " has a non-finite position or a non-unit orientation");
    const Real v = tumble::volume(p.shape);
    if (!(v > 0) || !std::isfinite(v))
      throw CompoundError(name + " has no positive finite volume");
    total += v;
    moment += v * p.pose.translation;
  }
  const Vec3 com = moment / total;
  CompoundShape c;
  c.parts_ = std::move(parts);
  c.volume_ = total;
  Mat3 inertia = Mat3::Zero();  // per unit total mass
  const Vec3 shift = recentre ? com : Vec3::Zero();
  for (CompoundPart& p : c.parts_) {
    p.pose.translation -= shift;
    const Real w = tumble::volume(p.shape) / total;  // mass fraction
    const Mat3 r = p.pose.rotation.toRotationMatrix();
    const Vec3& d = p.pose.translation;
    inertia += w * (r * tumble::unit_inertia(p.shape) * r.transpose() +
                    (d.squaredNorm() * Mat3::Identity() - d * d.transpose()));
    c.bounding_radius_ = std::max(c.bounding_radius_, d.norm() + tumble::bounding_radius(p.shape));
  }
  c.unit_inertia_ = (inertia + inertia.transpose()) * Real(0.5);
  if (centre_of_mass != nullptr)
    *centre_of_mass = com;
  return c;
}

Vec3 CompoundShape::support(const Vec3& direction) const {
  Vec3 best = Vec3::Zero();
  Real best_dot = -std::numeric_limits<Real>::infinity();
  for (const CompoundPart& p : parts_) {
    const Vec3 s = p.pose.apply(tumble::support(p.shape, p.pose.rotate_inverse(direction)));
    if (s.dot(direction) > best_dot) {
      best_dot = s.dot(direction);
      best = s;
    }
  }
  return best;
}

Aabb CompoundShape::world_aabb(const Transform& pose) const {
  Aabb box;
  for (const CompoundPart& p : parts_)
    box.grow(tumble::world_aabb(p.shape, compose(pose, p.pose)));
  return box;
}

}  // namespace tumble
