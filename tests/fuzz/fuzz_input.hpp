// Structured values for the fuzz targets, drawn from libFuzzer's bytes (LLVM's
// FuzzedDataProvider): lengths, poses and shapes within the ranges the API documents, with the
// edge values (tiny, huge, equal, flat) drawn often, since that is where geometry code breaks.
#pragma once

#include <fuzzer/FuzzedDataProvider.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <vector>

#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/shape.hpp"
#include "tumble/error.hpp"
#include "tumble/shape.hpp"

namespace tumble::fuzz {

// A positive length [m]: an ordinary size most of the time, else one of the extremes a valid
// shape may have.
inline Real length(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange<int>(0, 7)) {
    case 0:
      return Real(1e-4);
    case 1:
      return Real(1e3);
    case 2:
      return Real(0.5);
    default:
      return in.ConsumeFloatingPointInRange<Real>(Real(1e-3), Real(10));
  }
}

// A coordinate [m]: on a coarse lattice half of the time (so that points coincide, line up and
// lie in planes exactly), otherwise anywhere in [-spread, spread].
inline Real coordinate(FuzzedDataProvider& in, Real spread) {
  if (in.ConsumeBool())
    return Real(in.ConsumeIntegralInRange<int>(-4, 4)) * spread / 4;
  return in.ConsumeFloatingPointInRange<Real>(-spread, spread);
}

inline Vec3 point(FuzzedDataProvider& in, Real spread) {
  const Real x = coordinate(in, spread);
  const Real y = coordinate(in, spread);
  return {x, y, coordinate(in, spread)};
}

// A unit quaternion: the identity, a quarter turn about an axis, or any rotation.
inline Quat orientation(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange<int>(0, 3)) {
    case 0:
      return Quat::Identity();
    case 1: {
      const int axis = in.ConsumeIntegralInRange<int>(0, 2);
      Vec3 a = Vec3::Zero();
      a[axis] = 1;
      return Quat(Eigen::AngleAxis<Real>(Real(M_PI / 2), a));
    }
    default: {
      Quat q(
          in.ConsumeFloatingPointInRange<Real>(-1, 1), in.ConsumeFloatingPointInRange<Real>(-1, 1),
          in.ConsumeFloatingPointInRange<Real>(-1, 1), in.ConsumeFloatingPointInRange<Real>(-1, 1));
      if (!(q.norm() > Real(1e-3)))
        return Quat::Identity();
      return q.normalized();
    }
  }
}

inline Transform pose(FuzzedDataProvider& in, Real spread) {
  Transform t;
  t.translation = point(in, spread);
  t.rotation = orientation(in);
  return t;
}

// Points for a hull: few, on a lattice or not, often coplanar or repeated. hull_from_points
// refuses the flat and the too few with tumble::Error.
inline std::vector<Vec3> hull_points(FuzzedDataProvider& in) {
  const int count = in.ConsumeIntegralInRange<int>(1, 16);
  const Real size = length(in);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i)
    points.push_back(point(in, size));
  return points;
}

// A few prebuilt fields (an SDF shape integrates its mass on a grid: too slow to build per
// input): a torus, a box less a sphere, a smooth union, at 12 cells along the longest side (a
// few hundred surface points each: the paths of the default 48, a sixteenth of the work per
// pair).
inline const Shape& field_shape(int which) {
  static const std::array<Shape, 3> fields = [] {
    const SdfNode bowl = SdfNode::combine(
        SdfKind::difference_of,
        {SdfNode::box({1, 1, Real(0.5)}),
         SdfNode::sphere(Real(0.9)).placed(Transform{Vec3(0, 0, Real(0.6)), Quat::Identity()})});
    const SdfNode blend =
        SdfNode::combine(SdfKind::smooth_union_of,
                         {SdfNode::sphere(Real(0.5)), SdfNode::capsule(Real(0.2), Real(0.6))}, 8);
    constexpr int kCells = 12;
    return std::array<Shape, 3>{sdf_shape(SdfNode::torus(1, Real(0.25)), nullptr, kCells),
                                sdf_shape(bowl, nullptr, kCells),
                                sdf_shape(blend, nullptr, kCells)};
  }();
  return fields[static_cast<std::size_t>(which) % fields.size()];
}

// Any shape of the API, with valid parameters; nothing when the drawn data make none (a flat
// hull). `bounded_only` leaves out the plane (a dynamic body's shape).
inline std::optional<Shape> shape(FuzzedDataProvider& in, bool bounded_only = false) {
  const int type = in.ConsumeIntegralInRange<int>(0, kShapeTypeCount - 1);
  try {
    switch (static_cast<ShapeType>(type)) {
      case ShapeType::sphere:
        return Shape::sphere(length(in));
      case ShapeType::box: {
        const Real x = length(in);
        const Real y = in.ConsumeBool() ? x : length(in);
        return Shape::box({x, y, in.ConsumeBool() ? x : length(in)});
      }
      case ShapeType::capsule: {
        const Real r = length(in);
        return Shape::capsule(r, in.ConsumeBool() ? Real(0) : length(in));
      }
      case ShapeType::plane:
        if (bounded_only)
          return Shape::sphere(length(in));
        return Shape::plane();
      case ShapeType::cylinder: {
        const Real r = length(in);
        return Shape::cylinder(r, length(in));
      }
      case ShapeType::hull: {
        const std::vector<Vec3> points = hull_points(in);
        return hull_from_points(points);
      }
      case ShapeType::mesh: {
        const int triangles = in.ConsumeIntegralInRange<int>(1, 6);
        const Real size = length(in);
        std::vector<Vec3> vertices;
        std::vector<std::array<std::int32_t, 3>> faces;
        for (int t = 0; t < triangles; ++t) {
          const auto base = static_cast<std::int32_t>(vertices.size());
          for (int k = 0; k < 3; ++k)
            vertices.push_back(point(in, size));
          faces.push_back({base, base + 1, base + 2});
        }
        return mesh_from_triangles(std::move(vertices), std::move(faces));
      }
      case ShapeType::compound: {
        const int count = in.ConsumeIntegralInRange<int>(1, 3);
        std::vector<CompoundPart> parts;
        for (int i = 0; i < count; ++i) {
          Shape part = in.ConsumeBool() ? Shape::box({length(in), length(in), length(in)})
                                        : Shape::sphere(length(in));
          parts.push_back({part, pose(in, 1)});
        }
        return compound_from_parts(std::move(parts));
      }
      case ShapeType::sdf:
        return field_shape(in.ConsumeIntegralInRange<int>(0, 2));
    }
  } catch (const Error&) {
    return std::nullopt;  // refused with a clear error: not what this target looks for
  }
  return std::nullopt;
}

// A broken property: said on stderr, then abort(), which libFuzzer reports as a crash and keeps the
// input of.
[[noreturn]] inline void finding(const char* target, const char* what) {
  std::fprintf(stderr, "%s: %s\n", target, what);
  std::abort();
}

}  // namespace tumble::fuzz
