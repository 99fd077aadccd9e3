// The point of a triangle closest to a point (Ericson, Real-Time Collision Detection, 2005,
// 5.1.5): the Voronoi region of the point among the triangle's vertices, edges and face, found
// from barycentric dot products without a square root. Shared by the mesh's distance query
// (collision/shapes/mesh_ops.cpp) and the grid SDF's build (collision/sdf/sdf_grid.cpp).
#pragma once

#include "collision/math.hpp"

namespace tumble {

inline Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0)
    return a;
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  const Real vc = d1 * d4 - d3 * d2;
  const Real vb = d5 * d2 - d1 * d6;
  const Real va = d3 * d6 - d5 * d4;
  if (d3 >= 0 && d4 <= d3)
    return b;
  if (vc <= 0 && d1 >= 0 && d3 <= 0)
    return a + ab * (d1 / (d1 - d3));
  if (d6 >= 0 && d5 <= d6)
    return c;
  if (vb <= 0 && d2 >= 0 && d6 <= 0)
    return a + ac * (d2 / (d2 - d6));
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  return a + ab * (vb / (va + vb + vc)) + ac * (vc / (va + vb + vc));
}

}  // namespace tumble
