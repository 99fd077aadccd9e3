// Internal to GJK and EPA: both run in the local frame of A, with B placed relative to A by one
// rotation matrix and translation computed once per query, so a support call on A costs no
// rotation and one on B costs two matrix-vector products.
#pragma once

#include <span>

#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/shapes/convex_hull.hpp"

namespace tumble::detail {

// Core support of `s` in its own local frame; `index` is the hill-climbing hint in and the
// feature index out.
inline Vec3 local_core_support(const ConvexSupport& s, const Vec3& d, int& index) {
  if (s.shape == nullptr) {
    int best = 0;
    Real best_value = s.points[0].dot(d);
    for (int i = 1; i < s.point_count; ++i) {
      const Real value = s.points[i].dot(d);
      if (value > best_value) {
        best_value = value;
        best = i;
      }
    }
    index = best;
    return s.points[best];
  }
  const Shape& shape = *s.shape;
  switch (shape.type) {
    case ShapeType::sphere:
      index = 0;
      return Vec3::Zero();
    case ShapeType::capsule:
      index = d.z() < 0 ? 0 : 1;
      return Vec3(0, 0, d.z() < 0 ? -shape.half_length : shape.half_length);
    case ShapeType::box: {
      // Branch-free: the signs of a GJK direction are random, so branches mispredict. A
      // component that is zero (also -0) picks the positive corner.
      const Vec3& h = shape.half_extents;
      const int nx = int(d.x() < 0);
      const int ny = int(d.y() < 0);
      const int nz = int(d.z() < 0);
      index = (1 - nx) | (1 - ny) << 1 | (1 - nz) << 2;
      return {h.x() * Real(1 - 2 * nx), h.y() * Real(1 - 2 * ny), h.z() * Real(1 - 2 * nz)};
    }
    case ShapeType::cylinder: {
      const Real radial2 = d.x() * d.x() + d.y() * d.y();
      const Real z = d.z() < 0 ? -shape.half_length : shape.half_length;
      index = d.z() < 0 ? 0 : 1;
      if (radial2 > 0) {
        const Real scale = shape.radius / std::sqrt(radial2);
        return {d.x() * scale, d.y() * scale, z};
      }
      return {0, 0, z};
    }
    case ShapeType::hull: {
      index = shape.hull->support_index(d, index);
      return shape.hull->vertex(index);
    }
    case ShapeType::plane:
    case ShapeType::mesh:
    case ShapeType::compound:
    case ShapeType::sdf:
      break;
  }
  index = 0;
  return Vec3::Zero();
}

// A and B in A's local frame.
struct PairInA {
  const ConvexSupport* a;
  const ConvexSupport* b;
  Mat3 rotation_b;  // B local -> A local
  Vec3 translation_b;
  int hint_a = 0;
  int hint_b = 0;
  // Small hulls' vertices for the SIMD scan (hull_support_scan.hpp), null for other shapes:
  // when both shapes are small hulls, a support call scans both in one call. B's are in B's
  // frame, or in A's once EPA has placed them there (b_placed: EPA makes about 15 support calls
  // per query, which repay transforming every vertex once).
  HullScanArrays a_scan{};
  HullScanArrays b_scan{};
  bool b_placed = false;

  PairInA(const ConvexSupport& sa, const ConvexSupport& sb) : a(&sa), b(&sb) {
    const Quat q = sa.pose.rotation.conjugate() * sb.pose.rotation;
    rotation_b = q.toRotationMatrix();
    translation_b = sa.pose.rotation.conjugate() * (sb.pose.translation - sa.pose.translation);
    a_scan = small_hull_scan(sa);
    b_scan = small_hull_scan(sb);
  }

  static HullScanArrays small_hull_scan(const ConvexSupport& s) {
    if (s.shape == nullptr || s.shape->type != ShapeType::hull)
      return {};
    return s.shape->hull->scan_arrays();
  }

  static Vec3 scanned_vertex(const HullScanArrays& h, int i) {
    const std::size_t k = std::size_t(i);
    return {h.x[k], h.y[k], h.z[k]};
  }

  // Vertex of A - B farthest along `d` (A's frame).
  SimplexVertex support(const Vec3& d) {
    SimplexVertex v;
    if (a_scan.x != nullptr && b_scan.x != nullptr) {
      const Vec3 d_b = b_placed ? Vec3(-d) : Vec3(rotation_b.transpose() * (-d));
      const SupportPair i = scan_support_pair(a_scan, d, b_scan, d_b);
      hint_a = i.a;
      hint_b = i.b;
      v.a = scanned_vertex(a_scan, i.a);
      const Vec3 b_vertex = scanned_vertex(b_scan, i.b);
      v.b = b_placed ? b_vertex : Vec3(rotation_b * b_vertex + translation_b);
    } else {
      v.a = local_core_support(*a, d, hint_a);
      const Vec3 d_b = rotation_b.transpose() * (-d);
      v.b = rotation_b * local_core_support(*b, d_b, hint_b) + translation_b;
    }
    v.index_a = hint_a;
    v.index_b = hint_b;
    v.w = v.a - v.b;
    return v;
  }
};

}  // namespace tumble::detail
