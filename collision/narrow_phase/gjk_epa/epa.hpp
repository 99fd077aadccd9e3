// EPA, the expanding polytope algorithm: penetration depth and normal of two intersecting convex
// objects from GJK's final simplex. van den Bergen, "Proximity Queries and
// Penetration Depth Computation on 3D Game Objects", GDC 2001; Ericson, Real-Time Collision
// Detection, 2005, 9.5; the curved fallback's descent: Burke, Lewis and Overton, "A robust
// gradient sampling algorithm for nonsmooth, nonconvex optimization", SIAM J. Optim. 15(3), 2005.
//
// CONTRACT (shared with the triangle-mesh work): call with the same two ConvexSupports that
// gjk() was given and its result when the status is `intersecting`.
//   * depth >= 0 is the length of the shortest translation that separates the rounded objects;
//     normal is a unit vector from B to A (translating A by depth * normal separates them);
//     point_a / point_b are the deepest points of A inside B and of B inside A, with
//     point_a - point_b = -depth * normal.
//   * status: converged       -> upper and lower bounds on the depth agree within the tolerance
//                                (the curved tolerance when a core is a cylinder);
//             max_iterations  -> fallback: the smallest upper bound found (the support value
//             out_of_capacity    along the best normal tried, refined by a descent on curved
//                                cores), or the closest face when that is as good; finite,
//                                with a unit normal;
//             degenerate      -> the Minkowski difference has no volume (e.g. two coplanar
//                                triangles): depth = radii sum, normal = GJK's direction.
//   Never NaN: every division is by a quantity checked positive first.
//   * Degenerate GJK simplices (a point, segment or triangle touching the origin) are grown to
//     a tetrahedron by support queries along the axes / around the segment / along the
//     triangle's normal.
//   * Fixed-capacity buffers (kEpaMaxVertices, kEpaMaxFaces) on the stack: no heap.
#pragma once

#include <cstdint>

#include "collision/narrow_phase/gjk_epa/gjk.hpp"

namespace tumble {

enum class EpaStatus : std::uint8_t { converged, max_iterations, out_of_capacity, degenerate };

const char* epa_status_name(EpaStatus status);

inline constexpr int kEpaMaxVertices = 256;
inline constexpr int kEpaMaxFaces = 2 * kEpaMaxVertices;

struct EpaResult {
  EpaStatus status = EpaStatus::degenerate;
  Real depth = 0;               // >= 0 [m]
  Vec3 normal = Vec3::UnitZ();  // unit, from B to A
  Vec3 point_a = Vec3::Zero();
  Vec3 point_b = Vec3::Zero();
  int iterations = 0;
};

struct EpaSettings {
  // Stop when the support along the closest face's normal is within this fraction of the
  // polytope's size of the face's distance.
  Real relative_tolerance = Real(1e-12);
  // Curved cores (cylinders): the polytope closes in on a curved patch slowly and rounding in
  // its ever smaller faces stops it near 1e-10 of its size, so the loop also stops when the
  // closest face's distance (a lower bound on the depth) and the smallest support value along
  // a face normal tried (an upper bound) are within this fraction of the polytope's size, and
  // answers the upper bound. The error is then at most this times the size.
  Real curved_relative_tolerance = Real(1e-10);
  int max_iterations = kEpaMaxVertices - 4;
};

EpaResult epa(const ConvexSupport& a, const ConvexSupport& b, const GjkResult& gjk_result,
              const EpaSettings& settings = {});

}  // namespace tumble
