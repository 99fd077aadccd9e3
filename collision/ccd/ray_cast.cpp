#include "collision/ccd/ray_cast.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tumble {
namespace {

// First entering root of |o + t d|^2 = r^2 with t in [0, 1]; the ray starts outside.
bool sphere_hit(const Vec3& o, const Vec3& d, Real r, Real& t) {
  const Real a = d.squaredNorm();
  const Real b = o.dot(d);
  const Real c = o.squaredNorm() - r * r;
  if (a == 0 || b >= 0)
    return false;  // still or moving away from the centre
  const Real disc = b * b - a * c;
  if (disc < 0)
    return false;
  // Entering root -(b + sqrt(disc)) / a written as c / q to avoid cancellation (b < 0).
  const Real q = -b + std::sqrt(disc);
  t = c / q;
  return t >= 0 && t <= 1;
}

RayHit local_ray(const Shape& shape, const Vec3& o, const Vec3& d) {
  RayHit out;
  switch (shape.type) {
    case ShapeType::sphere: {
      Real t = 0;
      if (sphere_hit(o, d, shape.radius, t)) {
        out = {true, t, (o + t * d) / shape.radius};
      }
      return out;
    }
    case ShapeType::plane: {
      if (d.z() < 0) {
        const Real t = -o.z() / d.z();
        if (t <= 1)
          out = {true, t, Vec3::UnitZ()};
      }
      return out;
    }
    case ShapeType::box: {
      Real enter = 0;
      Real exit = 1;
      int enter_axis = -1;
      Real enter_sign = 1;
      for (int k = 0; k < 3; ++k) {
        const Real h = shape.half_extents[k];
        if (d[k] == 0) {
          if (std::abs(o[k]) > h)
            return out;
          continue;
        }
        Real t0 = (-h - o[k]) / d[k];
        Real t1 = (h - o[k]) / d[k];
        Real sign = -1;  // entering through the -h face when moving in +k
        if (t0 > t1) {
          std::swap(t0, t1);
          sign = 1;
        }
        if (t0 > enter) {
          enter = t0;
          enter_axis = k;
          enter_sign = sign;
        }
        exit = std::min(exit, t1);
        if (enter > exit)
          return out;
      }
      if (enter_axis < 0)
        return out;  // starts inside: handled by the caller
      out.hit = true;
      out.fraction = enter;
      out.normal = Vec3::Zero();
      out.normal[enter_axis] = enter_sign;
      return out;
    }
    case ShapeType::capsule: {
      const Real r = shape.radius;
      const Real hl = shape.half_length;
      Real best = std::numeric_limits<Real>::infinity();
      Vec3 normal = Vec3::UnitZ();
      // Side: |o_xy + t d_xy| = r, entering root, with z inside the core's span.
      const Vec3 oxy(o.x(), o.y(), 0);
      const Vec3 dxy(d.x(), d.y(), 0);
      Real t = 0;
      if (sphere_hit(oxy, dxy, r, t)) {
        const Real z = o.z() + t * d.z();
        if (z >= -hl && z <= hl) {
          best = t;
          normal = (oxy + t * dxy) / r;
        }
      }
      for (Real end : {-hl, hl}) {
        const Vec3 centre(0, 0, end);
        if (sphere_hit(o - centre, d, r, t) && t < best) {
          best = t;
          normal = (o + t * d - centre) / r;
        }
      }
      if (best <= 1)
        out = {true, best, normal};
      return out;
    }
  }
  return out;
}

}  // namespace

Real signed_distance(const Shape& shape, const Transform& pose, const Vec3& point) {
  const Vec3 p = pose.apply_inverse(point);
  switch (shape.type) {
    case ShapeType::sphere:
      return p.norm() - shape.radius;
    case ShapeType::plane:
      return p.z();
    case ShapeType::box: {
      const Vec3 q = p.cwiseAbs() - shape.half_extents;
      return q.cwiseMax(Real(0)).norm() + std::min(q.maxCoeff(), Real(0));
    }
    case ShapeType::capsule: {
      const Real z = std::clamp(p.z(), -shape.half_length, shape.half_length);
      return (p - Vec3(0, 0, z)).norm() - shape.radius;
    }
  }
  return 0;
}

RayHit ray_cast(const Shape& shape, const Transform& pose, const Vec3& origin, const Vec3& delta) {
  RayHit out;
  if (!origin.allFinite() || !delta.allFinite())
    return out;
  if (signed_distance(shape, pose, origin) <= 0) {
    out.hit = true;
    out.fraction = 0;
    const Real length = delta.norm();
    out.normal = length > 0 ? Vec3(-delta / length) : Vec3::UnitZ();
    return out;
  }
  const Vec3 o = pose.apply_inverse(origin);
  const Vec3 d = pose.rotate_inverse(delta);
  out = local_ray(shape, o, d);
  if (out.hit)
    out.normal = pose.rotate(out.normal);
  return out;
}

}  // namespace tumble
