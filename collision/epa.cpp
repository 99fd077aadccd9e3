// EPA: see epa.hpp for the sources and the contract.
//
// The polytope is a list of triangles oriented outward with respect to an interior point (the
// centroid of the first tetrahedron, which stays inside as the polytope only grows). Each
// iteration takes the face closest to the origin, asks for the support point along its normal,
// and stops when that point is no farther than the face (within the tolerance). Otherwise the
// faces the new point sees are removed, and the horizon (edges of removed faces whose twin was
// not removed) is joined to the new point.
//
// Why faces are oriented against the interior point rather than by winding: after rounding, a
// nearly coplanar neighbour can end up on the wrong side of a horizon edge; the interior test
// keeps every normal outward regardless, so a distance is never taken on an inward normal
// ("origin outside the polytope" in other engines comes from such flips).
#include "collision/epa.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "collision/gjk_internal.hpp"

namespace tumble {

const char* epa_status_name(EpaStatus status) {
  switch (status) {
    case EpaStatus::converged:
      return "converged";
    case EpaStatus::max_iterations:
      return "max_iterations";
    case EpaStatus::out_of_capacity:
      return "out_of_capacity";
    case EpaStatus::degenerate:
      return "degenerate";
  }
  return "unknown";
}

namespace {

constexpr Real kGrowTolerance = Real(1e-10);  // relative: a new vertex must add this much

struct Face {
  std::array<int, 3> v{};
  Vec3 normal = Vec3::Zero();
  Real distance = 0;
  bool live = false;
};

struct Edge {
  int from;
  int to;
};

struct Polytope {
  std::array<SimplexVertex, kEpaMaxVertices> vertex;
  int vertex_count = 0;
  std::array<Face, kEpaMaxFaces> face;
  int face_count = 0;
  Vec3 interior = Vec3::Zero();

  // Appends face (i, j, k) oriented outward; returns false when out of room.
  bool add_face(int i, int j, int k) {
    if (face_count >= kEpaMaxFaces)
      return false;
    Face& f = face[std::size_t(face_count++)];
    const Vec3& a = vertex[std::size_t(i)].w;
    Vec3 n = (vertex[std::size_t(j)].w - a).cross(vertex[std::size_t(k)].w - a);
    const Real length = n.norm();
    f.v = {i, j, k};
    f.live = true;
    if (!(length > 0)) {
      // A sliver: it can never be the closest face, and it is never seen from outside.
      f.normal = Vec3::Zero();
      f.distance = std::numeric_limits<Real>::infinity();
      return true;
    }
    n /= length;
    if (n.dot(a - interior) < 0) {
      n = -n;
      std::swap(f.v[1], f.v[2]);
    }
    f.normal = n;
    f.distance = n.dot(a);
    return true;
  }
};

Real distance_to_line(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const Real len = ab.norm();
  if (!(len > 0))
    return (p - a).norm();
  return (p - a).cross(ab).norm() / len;
}

// Grows the simplex to a tetrahedron with volume. Returns false when the Minkowski difference
// is flat along every direction tried.
bool grow_to_tetrahedron(detail::PairInA& pair, Polytope& poly, Real scale) {
  const Real eps = kGrowTolerance * scale;
  if (poly.vertex_count == 4) {
    const Vec3 a = poly.vertex[0].w;
    const Real v6 = (poly.vertex[1].w - a).dot((poly.vertex[2].w - a).cross(poly.vertex[3].w - a));
    if (std::abs(v6) > eps * scale * scale)
      return true;
    poly.vertex_count = 3;  // flat: regrow from its first triangle
    // Keep the triangle with the largest area among the four.
    constexpr int kFaces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
    int best = 0;
    Real best_area = -1;
    for (int f = 0; f < 4; ++f) {
      const Vec3& p = poly.vertex[std::size_t(kFaces[f][0])].w;
      const Real area = (poly.vertex[std::size_t(kFaces[f][1])].w - p)
                            .cross(poly.vertex[std::size_t(kFaces[f][2])].w - p)
                            .norm();
      if (area > best_area) {
        best_area = area;
        best = f;
      }
    }
    const std::array<SimplexVertex, 3> kept = {poly.vertex[std::size_t(kFaces[best][0])],
                                               poly.vertex[std::size_t(kFaces[best][1])],
                                               poly.vertex[std::size_t(kFaces[best][2])]};
    for (int i = 0; i < 3; ++i)
      poly.vertex[std::size_t(i)] = kept[std::size_t(i)];
  }
  if (poly.vertex_count == 3) {
    const Vec3& a = poly.vertex[0].w;
    const Real area = (poly.vertex[1].w - a).cross(poly.vertex[2].w - a).norm();
    if (!(area > eps * scale))
      poly.vertex_count = 2;  // a needle triangle: regrow from its longest edge
    if (poly.vertex_count == 2 && (poly.vertex[2].w - a).norm() > (poly.vertex[1].w - a).norm())
      poly.vertex[1] = poly.vertex[2];
  }
  if (poly.vertex_count == 2 && !((poly.vertex[1].w - poly.vertex[0].w).norm() > eps))
    poly.vertex_count = 1;
  if (poly.vertex_count == 1) {
    for (int k = 0; k < 6 && poly.vertex_count == 1; ++k) {
      const Vec3 d = Vec3::Unit(k / 2) * (k % 2 == 0 ? Real(1) : Real(-1));
      const SimplexVertex w = pair.support(d);
      if ((w.w - poly.vertex[0].w).norm() > eps)
        poly.vertex[std::size_t(poly.vertex_count++)] = w;
    }
    if (poly.vertex_count == 1)
      return false;
  }
  if (poly.vertex_count == 2) {
    const Vec3 e = (poly.vertex[1].w - poly.vertex[0].w).normalized();
    Vec3 t1;
    Vec3 t2;
    orthonormal_basis(e, t1, t2);
    // Six directions around the segment, 60 degrees apart.
    for (int k = 0; k < 6 && poly.vertex_count == 2; ++k) {
      const Real angle = Real(k) * Real(1.0471975511965976);
      const Vec3 d = std::cos(angle) * t1 + std::sin(angle) * t2;
      const SimplexVertex w = pair.support(d);
      if (distance_to_line(w.w, poly.vertex[0].w, poly.vertex[1].w) > eps)
        poly.vertex[std::size_t(poly.vertex_count++)] = w;
    }
    if (poly.vertex_count == 2)
      return false;
  }
  // Triangle: add the support point farther from its plane, on either side.
  const Vec3& a = poly.vertex[0].w;
  const Vec3 n = (poly.vertex[1].w - a).cross(poly.vertex[2].w - a).normalized();
  const SimplexVertex up = pair.support(n);
  const SimplexVertex down = pair.support(-n);
  const Real up_distance = std::abs(n.dot(up.w - a));
  const Real down_distance = std::abs(n.dot(down.w - a));
  const SimplexVertex& w = up_distance >= down_distance ? up : down;
  if (!(std::max(up_distance, down_distance) > eps))
    return false;
  poly.vertex[3] = w;
  poly.vertex_count = 4;
  return true;
}

// Barycentric coordinates of p's projection in the plane of triangle (a, b, c) (Ericson 3.4).
std::array<Real, 3> barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a;
  const Vec3 v1 = c - a;
  const Vec3 v2 = p - a;
  const Real d00 = v0.dot(v0);
  const Real d01 = v0.dot(v1);
  const Real d11 = v1.dot(v1);
  const Real d20 = v2.dot(v0);
  const Real d21 = v2.dot(v1);
  const Real denom = d00 * d11 - d01 * d01;
  if (!(denom > 0))
    return {1, 0, 0};
  const Real v = (d11 * d20 - d01 * d21) / denom;
  const Real w = (d00 * d21 - d01 * d20) / denom;
  const Real u = 1 - v - w;
  // The projection may fall just outside the closest triangle when a coplanar neighbour ties
  // with it (the two halves of a box face): the affine extension is then still exact, since
  // both triangles lie on one face of the Minkowski difference where the support points vary
  // affinely. Far outside means a sliver; clamp into the triangle.
  if (u >= -1 && v >= -1 && w >= -1 && u <= 2 && v <= 2 && w <= 2)
    return {u, v, w};
  const Real cu = std::max(u, Real(0));
  const Real cv = std::max(v, Real(0));
  const Real cw = std::max(w, Real(0));
  const Real sum = cu + cv + cw;
  if (!(sum > 0))
    return {1, 0, 0};
  return {cu / sum, cv / sum, cw / sum};
}

}  // namespace

EpaResult epa(const ConvexSupport& a, const ConvexSupport& b, const GjkResult& gjk_result,
              const EpaSettings& settings) {
  detail::PairInA pair(a, b);
  EpaResult result;
  const Real radii = a.radius + b.radius;
  Polytope poly;
  poly.vertex_count = std::max(1, gjk_result.simplex.count);
  if (gjk_result.simplex.count == 0)
    poly.vertex[0] = pair.support(Vec3::UnitX());
  for (int i = 0; i < gjk_result.simplex.count; ++i)
    poly.vertex[std::size_t(i)] = gjk_result.simplex.vertex[std::size_t(i)];
  // The polytope's size, for relative tolerances: the extent of A - B along the axes.
  Real scale = 0;
  for (int k = 0; k < 3; ++k)
    scale =
        std::max(scale, (pair.support(Vec3::Unit(k)).w - pair.support(-Vec3::Unit(k)).w).norm());
  if (!(scale > 0) || !std::isfinite(scale))
    scale = 1;

  if (!grow_to_tetrahedron(pair, poly, scale)) {
    result.status = EpaStatus::degenerate;
    result.depth = radii;
    result.normal = gjk_result.normal;
    const Vec3 core = a.pose.apply(poly.vertex[0].a);
    result.point_a = core - result.normal * a.radius;
    result.point_b = core + result.normal * b.radius;
    return result;
  }
  poly.interior =
      (poly.vertex[0].w + poly.vertex[1].w + poly.vertex[2].w + poly.vertex[3].w) * Real(0.25);
  poly.add_face(0, 1, 2);
  poly.add_face(0, 1, 3);
  poly.add_face(0, 2, 3);
  poly.add_face(1, 2, 3);

  const Real tolerance = settings.relative_tolerance * scale;
  result.status = EpaStatus::max_iterations;
  int closest = -1;
  int iteration = 0;
  std::array<Edge, kEpaMaxFaces> horizon;
  // The smallest upper bound seen: the support value along a face normal is the length of a
  // translation along that normal that separates the objects, so it is a feasible answer.
  Real best_upper = std::numeric_limits<Real>::infinity();
  Vec3 best_upper_normal = Vec3::UnitZ();
  SimplexVertex best_upper_vertex;
  for (; iteration < settings.max_iterations; ++iteration) {
    closest = -1;
    for (int f = 0; f < poly.face_count; ++f) {
      const Face& face = poly.face[std::size_t(f)];
      if (face.live && (closest < 0 || face.distance < poly.face[std::size_t(closest)].distance))
        closest = f;
    }
    if (closest < 0 || !std::isfinite(poly.face[std::size_t(closest)].distance)) {
      closest = -1;
      break;
    }
    const Face& best = poly.face[std::size_t(closest)];
    const SimplexVertex w = pair.support(best.normal);
    const Real upper = w.w.dot(best.normal);
    if (upper < best_upper) {
      best_upper = upper;
      best_upper_normal = best.normal;
      best_upper_vertex = w;
    }
    if (upper - best.distance <= tolerance) {
      result.status = EpaStatus::converged;
      break;
    }
    if (poly.vertex_count >= kEpaMaxVertices) {
      result.status = EpaStatus::out_of_capacity;
      break;
    }
    const int new_vertex = poly.vertex_count++;
    poly.vertex[std::size_t(new_vertex)] = w;
    // Remove the faces that see w, by a flood fill from the closest face over shared edges (so
    // a far face that "sees" w only by rounding cannot punch a second hole), and collect the
    // horizon: edges from a removed face to a kept one. Faces are wound counter-clockwise seen
    // from outside, so a neighbour holds the shared edge reversed.
    int horizon_count = 0;
    bool overflow = false;
    std::array<int, kEpaMaxFaces> stack;
    int stack_size = 0;
    poly.face[std::size_t(closest)].live = false;
    stack[std::size_t(stack_size++)] = closest;
    while (stack_size > 0 && !overflow) {
      const Face& removed = poly.face[std::size_t(stack[std::size_t(--stack_size)])];
      for (int e = 0; e < 3 && !overflow; ++e) {
        const Edge edge{removed.v[std::size_t(e)], removed.v[std::size_t((e + 1) % 3)]};
        int neighbour = -1;
        for (int f = 0; f < poly.face_count && neighbour < 0; ++f) {
          const Face& other = poly.face[std::size_t(f)];
          for (int k = 0; k < 3; ++k)
            if (other.v[std::size_t(k)] == edge.to &&
                other.v[std::size_t((k + 1) % 3)] == edge.from)
              neighbour = f;
        }
        Face* next = neighbour >= 0 ? &poly.face[std::size_t(neighbour)] : nullptr;
        if (next != nullptr && !next->live)
          continue;  // removed in this pass: an inner edge of the hole
        if (next != nullptr && next->normal.dot(w.w - poly.vertex[std::size_t(next->v[0])].w) > 0) {
          next->live = false;
          stack[std::size_t(stack_size++)] = neighbour;
        } else if (horizon_count < kEpaMaxFaces) {
          horizon[std::size_t(horizon_count++)] = edge;
        } else {
          overflow = true;
        }
      }
    }
    // Compact the face list so dead faces do not use up the capacity.
    int kept = 0;
    for (int f = 0; f < poly.face_count; ++f)
      if (poly.face[std::size_t(f)].live)
        poly.face[std::size_t(kept++)] = poly.face[std::size_t(f)];
    poly.face_count = kept;
    for (int h = 0; h < horizon_count && !overflow; ++h)
      overflow =
          !poly.add_face(horizon[std::size_t(h)].from, horizon[std::size_t(h)].to, new_vertex);
    if (overflow) {
      result.status = EpaStatus::out_of_capacity;
      closest = -1;
      for (int f = 0; f < poly.face_count; ++f) {
        const Face& face = poly.face[std::size_t(f)];
        if (face.live && std::isfinite(face.distance) &&
            (closest < 0 || face.distance < poly.face[std::size_t(closest)].distance))
          closest = f;
      }
      break;
    }
  }
  result.iterations = iteration;
  if (result.status != EpaStatus::converged) {
    // Fallback: the closest face of the polytope as it stands (its distance is a lower bound of
    // the depth). The index from the last iteration may be stale after the face list changed.
    closest = -1;
    for (int f = 0; f < poly.face_count; ++f) {
      const Face& face = poly.face[std::size_t(f)];
      if (face.live && std::isfinite(face.distance) &&
          (closest < 0 || face.distance < poly.face[std::size_t(closest)].distance))
        closest = f;
    }
  }
  if (result.status != EpaStatus::converged && std::isfinite(best_upper) &&
      (closest < 0 || best_upper - poly.face[std::size_t(closest)].distance > tolerance)) {
    // Fallback for a polytope that has not closed in (curved shapes use up the iterations):
    // the best upper bound, which on a smooth surface is within O(angle^2) of the depth while
    // the face distance is only within O(angle). Its witnesses: the support point on A and
    // its translate on B's supporting plane.
    const Vec3 normal_in_a = -best_upper_normal;
    result.depth = std::max(best_upper, Real(0)) + radii;
    result.normal = a.pose.rotate(normal_in_a);
    result.point_a = a.pose.apply(best_upper_vertex.a - normal_in_a * a.radius);
    result.point_b = result.point_a + result.normal * result.depth;
    return result;
  }
  if (closest < 0) {
    result.status = EpaStatus::degenerate;
    result.depth = radii;
    result.normal = gjk_result.normal;
    const Vec3 core = a.pose.apply(poly.vertex[0].a);
    result.point_a = core - result.normal * a.radius;
    result.point_b = core + result.normal * b.radius;
    return result;
  }
  const Face& face = poly.face[std::size_t(closest)];
  // The origin can sit a rounding error outside a touching polytope: depth is never negative.
  const Real core_depth = std::max(face.distance, Real(0));
  const SimplexVertex& p0 = poly.vertex[std::size_t(face.v[0])];
  const SimplexVertex& p1 = poly.vertex[std::size_t(face.v[1])];
  const SimplexVertex& p2 = poly.vertex[std::size_t(face.v[2])];
  const std::array<Real, 3> l = barycentric(face.normal * face.distance, p0.w, p1.w, p2.w);
  const Vec3 core_a = l[0] * p0.a + l[1] * p1.a + l[2] * p2.a;
  const Vec3 core_b = l[0] * p0.b + l[1] * p1.b + l[2] * p2.b;
  // The face normal n points from the origin out of A - B: moving A by -n separates, so the
  // normal from B to A is -n.
  const Vec3 normal_in_a = -face.normal;
  result.depth = core_depth + radii;
  result.normal = a.pose.rotate(normal_in_a);
  result.point_a = a.pose.apply(core_a - normal_in_a * a.radius);
  result.point_b = a.pose.apply(core_b + normal_in_a * b.radius);
  return result;
}

}  // namespace tumble
