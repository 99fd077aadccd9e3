// EPA: see epa.hpp for the sources and the contract.
//
// The polytope is a closed triangle mesh with edge adjacency (van den Bergen 2001, 4.3; Ericson
// 9.5): each face knows the face across each of its edges and that edge's index there. Each
// iteration takes the face closest to the origin, asks for the support point along its normal,
// and stops when that point is no farther than the face (within the tolerance). Otherwise the
// faces the new point sees are removed by a depth-first walk over the adjacency that starts at
// the closest face (so a far face that "sees" the point only by rounding cannot punch a second
// hole), the walk collects the horizon (edges from a removed face to a kept one) in order
// around the hole, and a fan of new faces joins the horizon to the new point. Removed faces'
// slots go to a free list and are reused, so nothing is compacted or searched.
//
// Faces are wound counter-clockwise seen from outside (that gives the adjacency), but each
// normal is oriented against an interior point (the centroid of the first tetrahedron, which
// stays inside as the polytope only grows): after rounding, a nearly coplanar new face can be
// wound the wrong way round, and the interior test keeps its normal outward regardless, so a
// distance is never taken on an inward normal ("origin outside the polytope" in other engines
// comes from such flips).
//
// Curved shapes (cylinders): the polytope closes in on a curved patch only slowly and rounding
// in its ever smaller faces stops it near 1e-10 of its size. The loop therefore also ends when
// the best upper bound (the smallest support value along any face normal tried, a feasible
// depth) is within the curved tolerance of the closest face's distance (a lower bound), and
// answers the upper bound. Where the polytope cannot close in at all (near-coaxial cylinders:
// the depth barely varies over all normals around the axis), the fallback's upper bound is
// refined by a descent of the support function (refine_upper_bound below).
#include "collision/narrow_phase/gjk_epa/epa.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "collision/narrow_phase/gjk_epa/gjk_internal.hpp"
#include "collision/shapes/hull_support_scan.hpp"

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
constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

// A polytope vertex. No default member initialisers: the polytope's arrays are large and are
// filled as they are used, not zeroed on every query.
struct Vertex {
  Vec3 w;
  Vec3 a;
  Vec3 b;
  int index_a;
  int index_b;
};

Vertex to_vertex(const SimplexVertex& s) {
  return {s.w, s.a, s.b, s.index_a, s.index_b};
}

struct Face {
  std::array<int, 3> v;              // counter-clockwise seen from outside
  std::array<int, 3> adjacent;       // face across edge e = (v[e], v[e + 1])
  std::array<int, 3> adjacent_edge;  // that edge's index in the adjacent face
  bool live;
};

// A face edge: face index and edge index in it.
struct FaceEdge {
  int face;
  int edge;
};

int next3(int e) {
  return e == 2 ? 0 : e + 1;
}

static_assert(kEpaMaxFaces % kHullScanWidth == 0, "the closest-face scan reads whole blocks");

struct Polytope {
  std::array<Vertex, kEpaMaxVertices> vertex;
  std::array<Face, kEpaMaxFaces> face;
  // The order of the face slots' planes by distance from the origin, as the signed square of
  // the distance, offset |offset| / |normal|^2 (one division, no square root); +inf for free
  // slots and slivers, so the closest-face search is one scan over a packed array.
  std::array<Real, kEpaMaxFaces> distance;
  // Each slot's plane, n . x = offset. n is outward and not normalised (its length is twice
  // the area), or zero for a sliver: visibility, the support direction and the closest-face
  // order need no unit normal, so a new face costs no square root; unit_normal() and
  // plane_distance() are taken for the one face each iteration works on.
  std::array<Real, kEpaMaxFaces> normal_x;
  std::array<Real, kEpaMaxFaces> normal_y;
  std::array<Real, kEpaMaxFaces> normal_z;
  std::array<Real, kEpaMaxFaces> offset;
  std::array<int, kEpaMaxFaces> free_slot;
  int vertex_count = 0;
  int face_end = 0;  // slots [0, face_end) have been used
  int free_count = 0;
  Vec3 interior = Vec3::Zero();

  // A new face (i, j, k) in a free slot with its normal oriented outward; -1 when out of room.
  int add_face(int i, int j, int k) {
    int slot = -1;
    if (free_count > 0) {
      slot = free_slot[std::size_t(--free_count)];
    } else if (face_end < kEpaMaxFaces) {
      slot = face_end++;
      // The closest-face scan reads whole blocks of kHullScanWidth slots: a slot that opens a
      // block marks the rest of it free.
      if (slot % kHullScanWidth == 0)
        std::fill_n(distance.begin() + slot + 1, kHullScanWidth - 1, kInfinity);
    } else {
      return -1;
    }
    Face& f = face[std::size_t(slot)];
    f.v = {i, j, k};
    f.live = true;
    // Written out in scalars (fewer instructions than Eigen's two-lane code for 3-vectors, which
    // shuffles), as this runs for every new face.
    const Vec3& a = vertex[std::size_t(i)].w;
    const Vec3& b = vertex[std::size_t(j)].w;
    const Vec3& c = vertex[std::size_t(k)].w;
    const Real ux = b.x() - a.x(), uy = b.y() - a.y(), uz = b.z() - a.z();
    const Real vx = c.x() - a.x(), vy = c.y() - a.y(), vz = c.z() - a.z();
    Real nx = uy * vz - uz * vy;
    Real ny = uz * vx - ux * vz;
    Real nz = ux * vy - uy * vx;
    Real plane_offset = nx * a.x() + ny * a.y() + nz * a.z();
    // Outward means the interior point is below the plane.
    if (plane_offset < nx * interior.x() + ny * interior.y() + nz * interior.z()) {
      nx = -nx;
      ny = -ny;
      nz = -nz;
      plane_offset = -plane_offset;
    }
    const Real length2 = nx * nx + ny * ny + nz * nz;
    const std::size_t at = std::size_t(slot);
    if (!(length2 > 0) || !(length2 < kInfinity)) {
      // A sliver: it can never be the closest face, and it is never seen from outside.
      normal_x[at] = normal_y[at] = normal_z[at] = offset[at] = 0;
      distance[at] = kInfinity;
      return slot;
    }
    normal_x[at] = nx;
    normal_y[at] = ny;
    normal_z[at] = nz;
    offset[at] = plane_offset;
    distance[at] = plane_offset * std::abs(plane_offset) / length2;
    return slot;
  }

  void remove_face(int slot) {
    face[std::size_t(slot)].live = false;
    distance[std::size_t(slot)] = kInfinity;
    free_slot[std::size_t(free_count++)] = slot;
  }

  void link(int f, int e, int g, int ge) {
    face[std::size_t(f)].adjacent[std::size_t(e)] = g;
    face[std::size_t(f)].adjacent_edge[std::size_t(e)] = ge;
    face[std::size_t(g)].adjacent[std::size_t(ge)] = f;
    face[std::size_t(g)].adjacent_edge[std::size_t(ge)] = e;
  }

  // The live face with the smallest finite distance (lowest slot on ties), or -1: a SIMD argmin
  // (hull_support_scan.hpp) over whole blocks, whose slots past face_end are marked free.
  int closest_face() const {
    const int blocks = (face_end + kHullScanWidth - 1) / kHullScanWidth;
    return first_smallest(distance.data(), blocks * kHullScanWidth);
  }

  // Face f's outward normal as stored (not normalised).
  Vec3 normal(int f) const {
    const std::size_t at = std::size_t(f);
    return {normal_x[at], normal_y[at], normal_z[at]};
  }

  // |n| of face f, read coordinate by coordinate: through a Vec3, GCC loaded normal_x[f] and
  // normal_x[f + 1] as one pair, which waits when the fan has just written them one by one.
  Real normal_length(int f) const {
    const std::size_t at = std::size_t(f);
    const Real x = normal_x[at], y = normal_y[at], z = normal_z[at];
    return std::sqrt(x * x + y * y + z * z);
  }

  Vec3 unit_normal(int f) const {
    const std::size_t at = std::size_t(f);
    const Real inverse = Real(1) / normal_length(f);
    return {normal_x[at] * inverse, normal_y[at] * inverse, normal_z[at] * inverse};
  }

  // Signed distance of face f's plane from the origin.
  Real plane_distance(int f) const { return offset[std::size_t(f)] / normal_length(f); }

  bool sees(int f, const Vec3& w) const {
    const std::size_t at = std::size_t(f);
    return normal_x[at] * w.x() + normal_y[at] * w.y() + normal_z[at] * w.z() > offset[at];
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
bool grow_to_tetrahedron(detail::PairInA& pair, GjkSimplex& simplex, Real scale) {
  auto& vertex = simplex.vertex;
  int& count = simplex.count;
  const Real eps = kGrowTolerance * scale;
  if (count == 4) {
    const Vec3 a = vertex[0].w;
    const Real v6 = (vertex[1].w - a).dot((vertex[2].w - a).cross(vertex[3].w - a));
    if (std::abs(v6) > eps * scale * scale)
      return true;
    count = 3;  // flat: regrow from its first triangle
    // Keep the triangle with the largest area among the four.
    constexpr int kFaces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
    int best = 0;
    Real best_area = -1;
    for (int f = 0; f < 4; ++f) {
      const Vec3& p = vertex[std::size_t(kFaces[f][0])].w;
      const Real area = (vertex[std::size_t(kFaces[f][1])].w - p)
                            .cross(vertex[std::size_t(kFaces[f][2])].w - p)
                            .norm();
      if (area > best_area) {
        best_area = area;
        best = f;
      }
    }
    const std::array<SimplexVertex, 3> kept = {vertex[std::size_t(kFaces[best][0])],
                                               vertex[std::size_t(kFaces[best][1])],
                                               vertex[std::size_t(kFaces[best][2])]};
    for (int i = 0; i < 3; ++i)
      vertex[std::size_t(i)] = kept[std::size_t(i)];
  }
  if (count == 3) {
    const Vec3& a = vertex[0].w;
    const Real area = (vertex[1].w - a).cross(vertex[2].w - a).norm();
    if (!(area > eps * scale))
      count = 2;  // a needle triangle: regrow from its longest edge
    if (count == 2 && (vertex[2].w - a).norm() > (vertex[1].w - a).norm())
      vertex[1] = vertex[2];
  }
  if (count == 2 && !((vertex[1].w - vertex[0].w).norm() > eps))
    count = 1;
  if (count == 1) {
    for (int k = 0; k < 6 && count == 1; ++k) {
      const Vec3 d = Vec3::Unit(k / 2) * (k % 2 == 0 ? Real(1) : Real(-1));
      const SimplexVertex w = pair.support(d);
      if ((w.w - vertex[0].w).norm() > eps)
        vertex[std::size_t(count++)] = w;
    }
    if (count == 1)
      return false;
  }
  if (count == 2) {
    const Vec3 e = (vertex[1].w - vertex[0].w).normalized();
    Vec3 t1;
    Vec3 t2;
    orthonormal_basis(e, t1, t2);
    // Six directions around the segment, 60 degrees apart.
    for (int k = 0; k < 6 && count == 2; ++k) {
      const Real angle = Real(k) * Real(1.0471975511965976);
      const Vec3 d = std::cos(angle) * t1 + std::sin(angle) * t2;
      const SimplexVertex w = pair.support(d);
      if (distance_to_line(w.w, vertex[0].w, vertex[1].w) > eps)
        vertex[std::size_t(count++)] = w;
    }
    if (count == 2)
      return false;
  }
  // Triangle: add the support point farther from its plane, on either side.
  const Vec3& a = vertex[0].w;
  const Vec3 n = (vertex[1].w - a).cross(vertex[2].w - a).normalized();
  const SimplexVertex up = pair.support(n);
  const SimplexVertex down = pair.support(-n);
  const Real up_distance = std::abs(n.dot(up.w - a));
  const Real down_distance = std::abs(n.dot(down.w - a));
  const SimplexVertex& w = up_distance >= down_distance ? up : down;
  if (!(std::max(up_distance, down_distance) > eps))
    return false;
  vertex[3] = w;
  count = 4;
  return true;
}

// The four faces of the tetrahedron in poly.vertex[0..3], wound outward, with their adjacency.
void build_tetrahedron(Polytope& poly) {
  const Vec3& p0 = poly.vertex[0].w;
  if ((poly.vertex[1].w - p0).dot((poly.vertex[2].w - p0).cross(poly.vertex[3].w - p0)) > 0)
    std::swap(poly.vertex[1], poly.vertex[2]);
  // Negative orientation of (0, 1, 2, 3): these windings face away from the fourth vertex.
  const int f012 = poly.add_face(0, 1, 2);
  const int f031 = poly.add_face(0, 3, 1);
  const int f023 = poly.add_face(0, 2, 3);
  const int f132 = poly.add_face(1, 3, 2);
  poly.link(f012, 0, f031, 2);  // 0-1 / 1-0
  poly.link(f012, 1, f132, 2);  // 1-2 / 2-1
  poly.link(f012, 2, f023, 0);  // 2-0 / 0-2
  poly.link(f031, 0, f023, 2);  // 0-3 / 3-0
  poly.link(f031, 1, f132, 0);  // 3-1 / 1-3
  poly.link(f023, 1, f132, 1);  // 2-3 / 3-2
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

// Size of a convex object's core, for relative tolerances: translation-invariant for point
// sets (their box's diagonal), the bounding radius of the core for shapes (spheres and
// capsules are a point and a segment here, their radius is added at the end).
Real core_size(const ConvexSupport& s) {
  if (s.shape != nullptr) {
    if (s.shape->type == ShapeType::sphere)
      return 0;
    if (s.shape->type == ShapeType::capsule)
      return s.shape->half_length;
    return bounding_radius(*s.shape);
  }
  if (s.point_count <= 0)
    return 0;
  Vec3 low = s.points[0];
  Vec3 high = s.points[0];
  for (int i = 1; i < s.point_count; ++i) {
    low = low.cwiseMin(s.points[i]);
    high = high.cwiseMax(s.points[i]);
  }
  return (high - low).norm();
}

// Hill climbing on big hulls starts from the face's own support points: the new support point
// is near them, as the face normal is near theirs. Of the three, the one farthest along the
// normal on A (and against it on B) is the best start.
void set_hints(detail::PairInA& pair, const Polytope& poly, int closest) {
  const Face& face = poly.face[std::size_t(closest)];
  const Vec3 normal = poly.normal(closest);
  const Vertex* best_a = &poly.vertex[std::size_t(face.v[0])];
  const Vertex* best_b = best_a;
  for (int k = 1; k < 3; ++k) {
    const Vertex& p = poly.vertex[std::size_t(face.v[std::size_t(k)])];
    if (p.a.dot(normal) > best_a->a.dot(normal))
      best_a = &p;
    if (p.b.dot(normal) < best_b->b.dot(normal))
      best_b = &p;
  }
  pair.hint_a = best_a->index_a;
  pair.hint_b = best_b->index_b;
}

// A hull big enough to be climbed (ConvexHull::support_index): only those use the hints.
bool climbs(const ConvexSupport& s) {
  return s.shape != nullptr && s.shape->type == ShapeType::hull &&
         int(s.shape->hull->vertices().size()) > kHullScanLimit;
}

// Room for a scanned hull's vertices placed in A's frame.
using PlacedHull = std::array<Real, 3 * kHullScanLimit>;
static_assert(kHullScanLimit % kHullScanWidth == 0, "a scanned hull's padding fits");

// When A and B are both small hulls, places B's vertices in A's frame once (PairInA::b_placed),
// so that each of EPA's support calls is the two scans and nothing else.
void place_small_hull_b(detail::PairInA& pair, PlacedHull& storage) {
  if (pair.a_scan.x == nullptr || pair.b_scan.x == nullptr)
    return;
  pair.b_scan = place_hull(pair.b_scan, pair.rotation_b, pair.translation_b, storage.data());
  pair.b_placed = true;
}

// EPA's support call: with both hulls placed, the two scans in one call, written straight into
// a polytope vertex; otherwise PairInA::support.
__attribute__((always_inline)) inline Vertex support_vertex(detail::PairInA& pair, const Vec3& d) {
  if (pair.b_placed) {
    const SupportPair i = scan_support_pair(pair.a_scan, d, pair.b_scan, -d);
    // Coordinate by coordinate: built as Eigen vectors, GCC stored the loaded scalars and read
    // them back as pairs, a failed store-to-load forwarding that cost 5% of a GJK+EPA query.
    const std::size_t ia = std::size_t(i.a);
    const std::size_t ib = std::size_t(i.b);
    const Real ax = pair.a_scan.x[ia], ay = pair.a_scan.y[ia], az = pair.a_scan.z[ia];
    const Real bx = pair.b_scan.x[ib], by = pair.b_scan.y[ib], bz = pair.b_scan.z[ib];
    Vertex v;
    v.a.x() = ax;
    v.a.y() = ay;
    v.a.z() = az;
    v.b.x() = bx;
    v.b.y() = by;
    v.b.z() = bz;
    v.w.x() = ax - bx;
    v.w.y() = ay - by;
    v.w.z() = az - bz;
    v.index_a = i.a;
    v.index_b = i.b;
    return v;
  }
  return to_vertex(pair.support(d));
}

// Cylinders: the only cores whose support map is curved (spheres and capsules are a point and a
// segment here).
bool has_curved_support(const ConvexSupport& s) {
  return s.shape != nullptr && s.shape->type == ShapeType::cylinder;
}

// An upper bound on the core depth: the support value along a unit normal (a translation by it
// along the normal separates the cores).
struct UpperBound {
  Real value;
  Vec3 normal;
  Vertex vertex;
};

UpperBound support_bound(detail::PairInA& pair, const Vec3& normal) {
  const Vertex w = support_vertex(pair, normal);
  return {w.w.dot(normal), normal, w};
}

// Smallest norm of a point in the convex hull of 2-D points (brute force over the few points,
// segments and triangles); zero when the hull holds the origin.
Eigen::Vector2d min_norm_point(const std::array<Eigen::Vector2d, 5>& p) {
  Eigen::Vector2d best = p[0];
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p[i].squaredNorm() < best.squaredNorm())
      best = p[i];
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const Eigen::Vector2d e = p[j] - p[i];
      const Real len2 = e.squaredNorm();
      const Real t = len2 > 0 ? -p[i].dot(e) / len2 : 0;
      if (t > 0 && t < 1 && (p[i] + t * e).squaredNorm() < best.squaredNorm())
        best = p[i] + t * e;
      for (std::size_t k = j + 1; k < p.size(); ++k) {
        const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
          return u.x() * v.y() - u.y() * v.x();
        };
        const Real c1 = cross(p[j] - p[i], -p[i]);
        const Real c2 = cross(p[k] - p[j], -p[j]);
        const Real c3 = cross(p[i] - p[k], -p[k]);
        if ((c1 > 0 && c2 > 0 && c3 > 0) || (c1 < 0 && c2 < 0 && c3 < 0))
          return Eigen::Vector2d::Zero();
      }
    }
  }
  return best;
}

// Refines an upper bound of the depth on a curved patch by minimising the support function
// h(n) over unit normals (the depth is the minimum of h). h is convex with kinks (along a
// cylinder's side its subdifferential is the whole side segment), so plain gradient steps
// zigzag; this follows gradient sampling (Burke, Lewis and Overton, "A robust gradient sampling
// algorithm for nonsmooth, nonconvex optimization", SIAM J. Optim. 15(3), 2005): each round
// takes the support points at four normals tilted by a sampling radius (the gradients of h
// nearby), and moves the normal against the point of smallest tangential norm in their hull;
// the step doubles on success and halves on failure, and the sampling radius shrinks tenfold
// when that hull holds the origin (stationary at this scale). Every support value tried is a
// feasible depth and only the smallest is kept. Used where the polytope cannot close in:
// near-coaxial cylinders, whose depth varies by little over a wide range of normals, so that
// EPA would have to refine the whole circle.
void refine_upper_bound(detail::PairInA& pair, UpperBound& best) {
  constexpr int kBudget = 400;                  // support calls
  constexpr Real kSmallestAngle = Real(1e-13);  // [rad]
  int calls = 0;
  Real sampling = Real(1e-6);  // [rad]
  Real step = Real(0.05);      // [rad]
  while (calls + 5 <= kBudget && sampling > kSmallestAngle && step > kSmallestAngle) {
    Vec3 t1;
    Vec3 t2;
    orthonormal_basis(best.normal, t1, t2);
    std::array<Eigen::Vector2d, 5> gradients;
    gradients[0] = {best.vertex.w.dot(t1), best.vertex.w.dot(t2)};
    UpperBound probe_best = best;
    for (int k = 0; k < 4; ++k) {
      const Vec3 tilt = (k < 2 ? t1 : t2) * (k % 2 == 0 ? sampling : -sampling);
      const UpperBound probe = support_bound(pair, (best.normal + tilt).normalized());
      gradients[std::size_t(k + 1)] = {probe.vertex.w.dot(t1), probe.vertex.w.dot(t2)};
      if (probe.value < probe_best.value)
        probe_best = probe;
    }
    calls += 4;
    const Eigen::Vector2d g = min_norm_point(gradients);
    if (!(g.norm() > 0)) {
      best = probe_best;
      sampling *= Real(0.1);
      continue;
    }
    const Vec3 descent = -(g.x() * t1 + g.y() * t2).normalized();
    const UpperBound trial =
        support_bound(pair, best.normal * std::cos(step) + descent * std::sin(step));
    ++calls;
    const bool moved = trial.value < probe_best.value;
    best = moved ? trial : probe_best;
    step *= moved ? Real(2) : Real(0.5);
    sampling = std::min(sampling, step);
  }
}

}  // namespace

EpaResult epa(const ConvexSupport& a, const ConvexSupport& b, const GjkResult& gjk_result,
              const EpaSettings& settings) {
  detail::PairInA pair(a, b);
  PlacedHull placed_b;
  place_small_hull_b(pair, placed_b);
  const bool uses_hints = climbs(a) || climbs(b);
  EpaResult result;
  const Real radii = a.radius + b.radius;
  GjkSimplex start = gjk_result.simplex;
  if (start.count == 0) {
    start.vertex[0] = pair.support(Vec3::UnitX());
    start.count = 1;
  }
  // The polytope's size, for relative tolerances: the sum of the cores' sizes (about half the
  // diameter of A - B).
  Real scale = core_size(a) + core_size(b);
  if (!(scale > 0) || !std::isfinite(scale))
    scale = 1;

  const auto degenerate = [&](const Vec3& core_a) {
    result.status = EpaStatus::degenerate;
    result.depth = radii;
    result.normal = gjk_result.normal;
    const Vec3 core = a.pose.apply(core_a);
    result.point_a = core - result.normal * a.radius;
    result.point_b = core + result.normal * b.radius;
    return result;
  };
  if (!grow_to_tetrahedron(pair, start, scale))
    return degenerate(start.vertex[0].a);

  Polytope poly;
  for (int i = 0; i < 4; ++i)
    poly.vertex[std::size_t(i)] = to_vertex(start.vertex[std::size_t(i)]);
  poly.vertex_count = 4;
  poly.interior =
      (poly.vertex[0].w + poly.vertex[1].w + poly.vertex[2].w + poly.vertex[3].w) * Real(0.25);
  build_tetrahedron(poly);

  const Real tolerance = settings.relative_tolerance * scale;
  const bool curved = has_curved_support(a) || has_curved_support(b);
  const Real curved_tolerance = settings.curved_relative_tolerance * scale;
  bool answer_upper_bound = false;
  result.status = EpaStatus::max_iterations;
  int closest = -1;
  int iteration = 0;
  // The horizon and the walk's stack: each removed face adds at most two entries to the stack
  // and its kept neighbours at most three horizon edges.
  std::array<FaceEdge, 2 * kEpaMaxFaces + 3> horizon;
  std::array<FaceEdge, 2 * kEpaMaxFaces + 3> stack;
  std::array<int, kEpaMaxFaces> fan;
  // The smallest upper bound seen: the support value along a face normal is the length of a
  // translation along that normal that separates the objects, so it is a feasible answer.
  // Curved shapes track it as they go (their loop also stops on it); on polytopes it serves
  // only the fallback, so each iteration just records the normal it tried (its support point
  // is the vertex it adds, or `w` for the last) and the bound is found after the loop,
  // keeping a square root, a division and a copy out of every iteration.
  Real best_upper = kInfinity;
  Vec3 best_upper_normal = Vec3::UnitZ();
  Vertex best_upper_vertex = poly.vertex[0];
  std::array<Vec3, kEpaMaxVertices> tried_normal;
  int tried_count = 0;
  Vertex w = poly.vertex[0];
  const auto track_upper_bound = [&](const Vec3& unit, const Vertex& support) {
    const Real upper = support.w.dot(unit);
    if (upper < best_upper) {
      best_upper = upper;
      best_upper_normal = unit;
      best_upper_vertex = support;
    }
    return upper;
  };
  // The closest face: searched over the whole polytope once; after that each iteration takes
  // the better of the closest face the walk kept (searched before the fan is written, so the
  // search does not wait for the fan) and the closest face of the fan (compared as it is made).
  // Ties go to the lower slot, as in one search over all faces, so the choice is the same.
  closest = poly.closest_face();
  for (; iteration < settings.max_iterations; ++iteration) {
    if (closest < 0)
      break;
    const Face& best = poly.face[std::size_t(closest)];
    if (uses_hints)
      set_hints(pair, poly, closest);
    // The support along the unnormalised normal (a support map does not depend on the length
    // of its direction), so the scan need not wait for the normalisation.
    const Vec3 normal = poly.normal(closest);
    w = support_vertex(pair, normal);
    if (curved) {
      const Real best_distance = poly.plane_distance(closest);
      const Real upper = track_upper_bound(poly.unit_normal(closest), w);
      if (upper - best_distance <= tolerance) {
        result.status = EpaStatus::converged;
        break;
      }
      if (best_upper - best_distance <= curved_tolerance) {
        // The depth is bracketed by the closest face (a lower bound) and the best upper bound
        // within the curved tolerance; the upper bound is the closer one on a curved patch.
        result.status = EpaStatus::converged;
        answer_upper_bound = true;
        break;
      }
    } else {
      tried_normal[std::size_t(tried_count++)] = normal;
      // The support value's excess over the face, (w . n - offset) / |n|, within the
      // tolerance, without dividing.
      const Real excess = w.w.dot(normal) - poly.offset[std::size_t(closest)];
      if (excess <= tolerance * poly.normal_length(closest)) {
        result.status = EpaStatus::converged;
        break;
      }
    }
    if (poly.vertex_count >= kEpaMaxVertices) {
      result.status = EpaStatus::out_of_capacity;
      break;
    }
    const int new_vertex = poly.vertex_count++;
    poly.vertex[std::size_t(new_vertex)] = w;

    // Depth-first walk from the closest face over the faces that see w (van den Bergen's
    // silhouette): edges are visited in counter-clockwise order, so the horizon comes out as a
    // loop in order.
    int horizon_count = 0;
    int stack_size = 0;
    for (int e = 2; e >= 0; --e)
      stack[std::size_t(stack_size++)] = {best.adjacent[std::size_t(e)],
                                          best.adjacent_edge[std::size_t(e)]};
    poly.remove_face(closest);
    while (stack_size > 0) {
      const FaceEdge entry = stack[std::size_t(--stack_size)];
      const Face& f = poly.face[std::size_t(entry.face)];
      if (!f.live)
        continue;  // removed in this pass: an inner edge of the hole
      if (poly.sees(entry.face, w.w)) {
        // Continue across the other two edges, the next one counter-clockwise first.
        const int e1 = next3(entry.edge);
        const int e2 = next3(e1);
        stack[std::size_t(stack_size++)] = {f.adjacent[std::size_t(e2)],
                                            f.adjacent_edge[std::size_t(e2)]};
        stack[std::size_t(stack_size++)] = {f.adjacent[std::size_t(e1)],
                                            f.adjacent_edge[std::size_t(e1)]};
        poly.remove_face(entry.face);
      } else {
        horizon[std::size_t(horizon_count++)] = entry;
      }
    }
    // Over the kept faces only: the removed ones are marked free, and the fan's slots (reused
    // or new) are written below, after this search in program order.
    closest = poly.closest_face();
    // The fan: face h joins horizon edge h (reversed in the kept face) to w. Its edge 0 borders
    // the kept face, edge 1 the next fan face and edge 2 the previous one. The walk gives the
    // horizon as a loop in order, so each face is joined to the previous one as it is made.
    bool broken = false;
    bool in_order = true;
    for (int h = 0; h < horizon_count; ++h) {
      const FaceEdge kept = horizon[std::size_t(h)];
      const Face& k = poly.face[std::size_t(kept.face)];
      const int from = k.v[std::size_t(next3(kept.edge))];
      const int to = k.v[std::size_t(kept.edge)];
      const int slot = poly.add_face(from, to, new_vertex);
      if (slot < 0) {
        broken = true;
        break;
      }
      fan[std::size_t(h)] = slot;
      const Real key = poly.distance[std::size_t(slot)];
      if (key < kInfinity && (closest < 0 || key < poly.distance[std::size_t(closest)] ||
                              (key == poly.distance[std::size_t(closest)] && slot < closest)))
        closest = slot;
      poly.link(slot, 0, kept.face, kept.edge);
      if (h > 0) {
        const int previous = fan[std::size_t(h - 1)];
        in_order = in_order && poly.face[std::size_t(previous)].v[1] == from;
        poly.link(previous, 1, slot, 2);
      }
    }
    if (!broken && horizon_count > 0 && in_order &&
        poly.face[std::size_t(fan[std::size_t(horizon_count - 1)])].v[1] ==
            poly.face[std::size_t(fan[0])].v[0]) {
      poly.link(fan[std::size_t(horizon_count - 1)], 1, fan[0], 2);
    } else if (!broken) {
      // Out of order (never seen, kept for safety): join each face to the one that starts
      // where it ends. Should rounding have made the hole pinched (a vertex twice on the
      // horizon), the faces cannot be joined into a closed mesh and the loop stops with the
      // polytope as it stands.
      for (int h = 0; h < horizon_count && !broken; ++h) {
        const int face_h = fan[std::size_t(h)];
        const int end = poly.face[std::size_t(face_h)].v[1];
        int next = -1;
        for (int m = 0; m < horizon_count; ++m)
          if (poly.face[std::size_t(fan[std::size_t(m)])].v[0] == end)
            next = next < 0 ? fan[std::size_t(m)] : -2;
        if (next < 0) {
          broken = true;
          break;
        }
        poly.link(face_h, 1, next, 2);
      }
    }
    if (broken) {
      result.status = EpaStatus::out_of_capacity;
      break;
    }
  }
  result.iterations = iteration;
  if (result.status != EpaStatus::converged) {
    // Fallback: the closest face of the polytope as it stands (its distance is a lower bound of
    // the depth). The index from the last iteration may be stale after the face list changed.
    closest = poly.closest_face();
    if (!curved) {
      // The tried normals in order: iteration k added vertex 4 + k, but the last may have
      // stopped before adding its support point `w`.
      for (int k = 0; k < tried_count; ++k) {
        const std::size_t at = std::size_t(4 + k);
        const Vec3& n = tried_normal[std::size_t(k)];
        const Real length = std::sqrt(n.x() * n.x() + n.y() * n.y() + n.z() * n.z());
        const Vec3 unit = n * (Real(1) / length);
        track_upper_bound(unit, int(at) < poly.vertex_count ? poly.vertex[at] : w);
      }
    }
  }
  if (answer_upper_bound ||
      (result.status != EpaStatus::converged && std::isfinite(best_upper) &&
       (closest < 0 || best_upper - poly.plane_distance(closest) > tolerance))) {
    // Fallback for a polytope that has not closed in (curved shapes use up the iterations):
    // the best upper bound, which on a smooth surface is within O(angle^2) of the depth while
    // the face distance is only within O(angle). Its witnesses: the support point on A and
    // its translate on B's supporting plane.
    UpperBound bound{best_upper, best_upper_normal, best_upper_vertex};
    if (curved && !answer_upper_bound)
      refine_upper_bound(pair, bound);
    const Vec3 normal_in_a = -bound.normal;
    result.depth = std::max(bound.value, Real(0)) + radii;
    result.normal = a.pose.rotate(normal_in_a);
    result.point_a = a.pose.apply(bound.vertex.a - normal_in_a * a.radius);
    result.point_b = result.point_a + result.normal * result.depth;
    return result;
  }
  if (closest < 0)
    return degenerate(poly.vertex[0].a);
  const Face& face = poly.face[std::size_t(closest)];
  const Real face_distance = poly.plane_distance(closest);
  // The origin can sit a rounding error outside a touching polytope: depth is never negative.
  const Real core_depth = std::max(face_distance, Real(0));
  const Vertex& p0 = poly.vertex[std::size_t(face.v[0])];
  const Vertex& p1 = poly.vertex[std::size_t(face.v[1])];
  const Vertex& p2 = poly.vertex[std::size_t(face.v[2])];
  const Vec3 unit = poly.unit_normal(closest);
  const std::array<Real, 3> l = barycentric(unit * face_distance, p0.w, p1.w, p2.w);
  const Vec3 core_a = l[0] * p0.a + l[1] * p1.a + l[2] * p2.a;
  const Vec3 core_b = l[0] * p0.b + l[1] * p1.b + l[2] * p2.b;
  // The face normal n points from the origin out of A - B: moving A by -n separates, so the
  // normal from B to A is -n.
  const Vec3 normal_in_a = -unit;
  result.depth = core_depth + radii;
  result.normal = a.pose.rotate(normal_in_a);
  result.point_a = a.pose.apply(core_a - normal_in_a * a.radius);
  result.point_b = a.pose.apply(core_b + normal_in_a * b.radius);
  return result;
}

}  // namespace tumble
