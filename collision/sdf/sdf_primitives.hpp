// Signed distances of the primitive solids with their exact gradients, each in the solid's own
// frame (negative inside). The distance functions are the standard exact ones (Hart, "Sphere
// tracing", The Visual Computer 12, 1996, section 3; Quilez, "Distance functions", for the box
// and the torus); the gradients are their derivatives, written out here. Where the distance is
// not differentiable (the centre of a sphere, the core of a capsule or torus, the medial planes
// of a box inside), the gradient is one of the one-sided ones, of unit length, so that
// x - phi grad phi still lands on the surface.
#pragma once

#include <algorithm>
#include <cmath>

#include "collision/math.hpp"

namespace tumble::sdf {

struct Sample {
  Real distance = 0;              // m, negative inside
  Vec3 gradient = Vec3::UnitZ();  // d distance / d point
};

inline Real sign_of(Real v) {
  return v < 0 ? Real(-1) : Real(1);
}

inline Sample sphere(const Vec3& p, Real radius) {
  const Real n = p.norm();
  return {n - radius, n > 0 ? Vec3(p / n) : Vec3::UnitZ()};
}

// Each *_distance below is its solid's distance alone, by the same operations as the Sample's
// (so the same bits): what a caller that needs no gradient asks (culling a surface's points
// against a partner field), at about half the work of a composite field's sample.
inline Real sphere_distance(const Vec3& p, Real radius) {
  return p.norm() - radius;
}

// Exact inside and outside: outside, the distance to the nearest point of the box; inside, to
// the nearest face.
inline Sample box(const Vec3& p, const Vec3& half_extents) {
  const Vec3 q = p.cwiseAbs() - half_extents;
  const Vec3 out = q.cwiseMax(Real(0));
  const Real outside = out.norm();
  if (outside > 0) {
    Vec3 g = out / outside;
    for (int k = 0; k < 3; ++k)
      g[k] *= sign_of(p[k]);
    return {outside, g};
  }
  int axis = 0;
  q.maxCoeff(&axis);
  Vec3 g = Vec3::Zero();
  g[axis] = sign_of(p[axis]);
  return {q[axis], g};
}

inline Real box_distance(const Vec3& p, const Vec3& half_extents) {
  const Vec3 q = p.cwiseAbs() - half_extents;
  const Real outside = q.cwiseMax(Real(0)).norm();
  if (outside > 0)
    return outside;
  int axis = 0;
  q.maxCoeff(&axis);
  return q[axis];
}

// The segment from (0, 0, -half_length) to (0, 0, half_length), swept by a sphere.
inline Sample capsule(const Vec3& p, Real radius, Real half_length) {
  const Vec3 v(p.x(), p.y(), p.z() - std::clamp(p.z(), -half_length, half_length));
  const Real n = v.norm();
  return {n - radius, n > 0 ? Vec3(v / n) : Vec3::UnitX()};
}

inline Real capsule_distance(const Vec3& p, Real radius, Real half_length) {
  const Vec3 v(p.x(), p.y(), p.z() - std::clamp(p.z(), -half_length, half_length));
  return v.norm() - radius;
}

// Axis z, from -half_length to half_length.
inline Sample cylinder(const Vec3& p, Real radius, Real half_length) {
  const Real rho = std::sqrt(p.x() * p.x() + p.y() * p.y());
  const Vec3 radial = rho > 0 ? Vec3(p.x() / rho, p.y() / rho, 0) : Vec3::UnitX();
  const Vec3 axial(0, 0, sign_of(p.z()));
  const Real dr = rho - radius;
  const Real dz = std::abs(p.z()) - half_length;
  if (dr > 0 && dz > 0) {
    const Real d = std::sqrt(dr * dr + dz * dz);
    return {d, (dr * radial + dz * axial) / d};
  }
  return dr >= dz ? Sample{dr, radial} : Sample{dz, axial};
}

inline Real cylinder_distance(const Vec3& p, Real radius, Real half_length) {
  const Real rho = std::sqrt(p.x() * p.x() + p.y() * p.y());
  const Real dr = rho - radius;
  const Real dz = std::abs(p.z()) - half_length;
  if (dr > 0 && dz > 0)
    return std::sqrt(dr * dr + dz * dz);
  return dr >= dz ? dr : dz;
}

// A ring torus about the z axis: the circle of `major_radius` in the xy plane, swept by a
// sphere of `minor_radius`.
inline Sample torus(const Vec3& p, Real major_radius, Real minor_radius) {
  const Real rho = std::sqrt(p.x() * p.x() + p.y() * p.y());
  const Vec3 radial = rho > 0 ? Vec3(p.x() / rho, p.y() / rho, 0) : Vec3::UnitX();
  const Real a = rho - major_radius;
  const Real n = std::sqrt(a * a + p.z() * p.z());
  return {n - minor_radius, n > 0 ? Vec3(a / n * radial + Vec3(0, 0, p.z() / n)) : radial};
}

inline Real torus_distance(const Vec3& p, Real major_radius, Real minor_radius) {
  const Real rho = std::sqrt(p.x() * p.x() + p.y() * p.y());
  const Real a = rho - major_radius;
  return std::sqrt(a * a + p.z() * p.z()) - minor_radius;
}

// The half-space z <= 0.
inline Sample plane(const Vec3& p) {
  return {p.z(), Vec3::UnitZ()};
}

}  // namespace tumble::sdf
