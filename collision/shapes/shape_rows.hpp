// The rows of the shape table (collision/shapes/shape_ops.hpp), one per file, and the geometry
// helpers several rows share. Private to collision/shapes.
#pragma once

#include "collision/shapes/shape_ops.hpp"

namespace tumble {

extern const ShapeOps kSphereOps;    // sphere_ops.cpp
extern const ShapeOps kBoxOps;       // box_ops.cpp
extern const ShapeOps kCapsuleOps;   // capsule_ops.cpp
extern const ShapeOps kPlaneOps;     // plane_ops.cpp
extern const ShapeOps kCylinderOps;  // cylinder_ops.cpp
extern const ShapeOps kHullOps;      // hull_ops.cpp
extern const ShapeOps kMeshOps;      // mesh_ops.cpp
extern const ShapeOps kCompoundOps;  // compound_ops.cpp
extern const ShapeOps kSdfOps;       // sdf_ops.cpp

namespace shape_geometry {

// Unit vector along `d`, or +z for a zero direction, so support maps never divide by zero.
inline Vec3 unit_or_z(const Vec3& d) {
  const Real n = d.norm();
  return n > 0 ? Vec3(d / n) : Vec3::UnitZ();
}

inline Real sign_or_plus(Real x) {
  return x < 0 ? Real(-1) : Real(1);
}

// First entering root of |o + t d|^2 = r^2 with t in [0, 1]; the ray starts outside.
bool sphere_hit(const Vec3& o, const Vec3& d, Real r, Real& t);

// The side of a disc of `radius` swept along z from -half_length to half_length, the part of
// the ray cast the cylinder and the capsule share: the entering fraction, or infinity when the
// ray misses the side (then `normal` is +z).
Real disc_side_hit(const Vec3& o, const Vec3& d, Real radius, Real half_length, Vec3& normal);

}  // namespace shape_geometry
}  // namespace tumble
