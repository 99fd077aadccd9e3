// Axis-aligned bounding box, the currency of the broad phase (docs/broad-phase.md).
#pragma once

#include <limits>

#include "collision/math.hpp"

namespace tumble {

struct Aabb {
  Vec3 min = Vec3::Constant(std::numeric_limits<Real>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<Real>::infinity());

  // Closed intervals: boxes that exactly touch overlap, so resting contacts are never missed.
  bool overlaps(const Aabb& o) const {
    return min.x() <= o.max.x() && o.min.x() <= max.x() && min.y() <= o.max.y() &&
           o.min.y() <= max.y() && min.z() <= o.max.z() && o.min.z() <= max.z();
  }
  bool contains(const Vec3& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  void grow(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void grow(const Aabb& o) {
    min = min.cwiseMin(o.min);
    max = max.cwiseMax(o.max);
  }
  Aabb inflated(Real margin) const { return {min.array() - margin, max.array() + margin}; }
  // The box holding this (finite) box carried by `pose`: its centre carried, its half extents
  // spread by the absolute rotation matrix (the box of its eight corners, without the corners).
  Aabb placed(const Transform& pose) const {
    const Vec3 centre = pose.apply((min + max) / 2);
    const Vec3 extent = pose.rotation.toRotationMatrix().cwiseAbs() * ((max - min) / 2);
    return {centre - extent, centre + extent};
  }
};

}  // namespace tumble
