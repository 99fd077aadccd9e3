// GJK distance query between two convex objects given by support maps.
//
// Sources: Gilbert, Johnson and Keerthi, "A fast procedure for computing the distance between
// complex objects in three-dimensional space", IEEE J. Robotics and Automation 4(2), 1988;
// van den Bergen, "A Fast and Robust GJK Implementation for Collision Detection of Convex
// Objects", JGT 4(2), 1999 (termination tests, relative tolerances); Montanari, Petrinic and
// Barbieri, "Improving the GJK algorithm for faster and more reliable distance queries between
// convex objects", ACM TOG 36(3), 2017 (the sub-simplex search by signed volumes, i.e. by signs
// of barycentric coordinates, that never divides by a tiny determinant).
//
// CONTRACT (shared with the triangle-mesh work):
//   * A convex object is a ConvexSupport: either a Shape (sphere, box, capsule, cylinder, hull)
//     or a small point set (a triangle: 3 points), placed by `pose` in the pair-local frame, with
//     a `radius` of rounding around its core. Spheres and capsules are passed as their core (a
//     point, a segment) plus radius, so the rounded part is exact: GJK measures the core distance
//     and the radii are subtracted at the end.
//   * GjkResult.normal is a unit vector from B to A; point_a / point_b are the witness points on
//     the surfaces (rounded surfaces included); distance is signed.
//   * status: separated    -> the cores are apart; distance, witnesses and normal are exact up
//                             to the tolerances. The distance is negative when the rounded
//                             parts overlap (e.g. two spheres), and is then the exact depth.
//                             One exception, found by fuzzing: where a sliver of
//                             near-coincident vertices (4e-6 m apart on a 1 m set) touches the
//                             other set exactly, the search may stop short of the touch, at up
//                             to 1e-5 of the problem's size (2.4e-6 the worst found; the lower
//                             bound v.w is then near zero and the simplex too thin to progress).
//                             tests/fuzz/fuzz_gjk_epa.cpp bounds it.
//             intersecting -> the cores overlap or touch (|v| below the touching tolerance);
//                             distance = 0, normal = the last search direction (unit) or +z;
//                             run EPA (collision/narrow_phase/gjk_epa/epa.hpp) on result.simplex
//                             for the depth.
//             max_iterations / degenerate -> the best estimate so far is returned (finite,
//                             unit normal); callers treat it like `separated` with that
//                             distance (it is an upper bound on the core distance).
//   * No heap allocation; queries should run in a pair-local frame (poses relative to one body).
#pragma once

#include <array>
#include <cstdint>

#include "collision/math.hpp"
#include "collision/shapes/shape.hpp"

namespace tumble {

enum class GjkStatus : std::uint8_t { separated, intersecting, max_iterations, degenerate };

const char* gjk_status_name(GjkStatus status);

// A convex object for GJK/EPA: a shape's core or a point set, under a pose, plus a radius.
struct ConvexSupport {
  const Shape* shape = nullptr;  // when set: the shape's core support
  const Vec3* points = nullptr;  // otherwise: the convex hull of these points (local frame)
  int point_count = 0;
  Real radius = 0;  // rounding added around the core [m]
  Transform pose;   // local -> pair frame

  // A shape under a pose: spheres and capsules as core + radius, the others with radius 0.
  // Planes, meshes and compounds are not convex objects and must not be passed.
  static ConvexSupport of(const Shape& shape, const Transform& pose);
  // A point set (e.g. a triangle's three vertices) with optional rounding.
  static ConvexSupport of_points(const Vec3* points, int count, const Transform& pose,
                                 Real radius = 0);

  // Support point of the core in the pair frame along `direction` (pair frame); `index`
  // receives a feature index (hull vertex / point index / box corner) and is used as the
  // starting vertex for hill climbing on big hulls.
  Vec3 core_support(const Vec3& direction, int& index) const;
};

// One vertex of the Minkowski difference A - B with the two support points that made it.
struct SimplexVertex {
  Vec3 w = Vec3::Zero();  // a - b
  Vec3 a = Vec3::Zero();
  Vec3 b = Vec3::Zero();
  int index_a = 0;
  int index_b = 0;
};

struct GjkSimplex {
  std::array<SimplexVertex, 4> vertex{};
  int count = 0;
};

struct GjkResult {
  GjkStatus status = GjkStatus::degenerate;
  Real distance = 0;  // signed, rounded surfaces included [m]
  Vec3 point_a = Vec3::Zero();
  Vec3 point_b = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // unit, from B to A
  int iterations = 0;
  GjkSimplex simplex;  // final simplex of the core query, in A's local frame (input to EPA)
};

// Warm-start data kept per pair between steps (docs/narrow-phase.md, "GJK"): last step's
// separating axis in the frame of A (so it survives the pair moving as a whole) and the support
// vertices it ended on.
struct GjkCache {
  Vec3 axis_in_a = Vec3::Zero();
  int index_a = 0;
  int index_b = 0;
  bool valid = false;
  void reset() { *this = GjkCache{}; }
};

struct GjkSettings {
  // The loop stops when the lower bound on the distance is within this fraction of the upper
  // bound (van den Bergen's relative test): ||v||^2 - v.w <= kRelative^2 ||v||^2.
  Real relative_tolerance = Real(1e-10);
  // Cores closer than this fraction of the simplex's size count as touching (intersecting).
  Real touching_tolerance = Real(1e-12);
  int max_iterations = 64;
};

GjkResult gjk(const ConvexSupport& a, const ConvexSupport& b, GjkCache* cache = nullptr,
              const GjkSettings& settings = {});

}  // namespace tumble
