// GJK: see gjk.hpp for the sources and the contract.
//
// The sub-simplex search returns the point of the current simplex closest to the origin and the
// smallest sub-simplex that holds it, by the Voronoi-region tests of Ericson (Real-Time
// Collision Detection, 2005, 5.1.2, 5.1.5, 5.1.6). Like Montanari et al.'s signed volumes it
// decides regions by signs of (unnormalised) barycentric coordinates and divides only once the
// region is known, by a quantity that is then positive; a simplex whose area or volume is below
// rounding relative to its size is treated as its best face or edge, so a flat tetrahedron or a
// needle triangle never produces a NaN.
//
// Termination (van den Bergen 1999): (1) ||v||^2 - v.w <= eps_rel^2 ||v||^2 (the support point
// brings no more than the relative tolerance), (2) w is already in the simplex, (3) ||v|| no
// longer decreases (oscillation from rounding), (4) the simplex is a tetrahedron holding the
// origin or ||v|| is below the touching tolerance (intersecting), (5) the iteration cap.
//
// Stalls: (2) and (3) can stop the loop far from convergence when a curved shape nearly touches
// a face (a cylinder's rim over a triangle or a box). The supports along successive directions
// then pair a rim point that still moves with the same corner of the face, so the simplex keeps
// vertices whose rim points came from earlier, less accurate directions; the closest point
// stops decreasing while ||v|| is still many times the distance (measured: 2.4e-9 m for a true
// 9.5e-10 m, up to 5.5e-8 of the shapes' size over 20,000 such poses). A stop with the gap
// ||v||^2 - v.w above kStallGap ||v||^2 is therefore taken as a stall, and two remedies are
// tried before giving up:
//   - refresh: the simplex's points on A (or on B) are replaced by those of the new support w:
//     all of them, or only those near w's, or, on a cylinder, each moved around the axis to w's
//     angle on its own cap (a cylinder lying on a face has both rim ends in the simplex, and the
//     support never returns the stale one); for two cylinders, the simplex becomes the four
//     pairs of ends of their side lines, at w's angles or facing each other across the axes'
//     common perpendicular (crossed sides touch inside both lines, which only the rims support),
//     or one's rim points closest to the other's axis (Newton on the angle: the one or two
//     minima, and the chord between two) against the other's side line facing them (a cylinder
//     leaning or standing on a lying one); every vertex stays a point of
//     A - B, so ||v|| stays an upper bound, and the closest of these simplices is adopted if it
//     is closer;
//   - restart (once, and only when the gap is above its own rounding): the search goes on from
//     w alone, so that the new simplex is built of supports near the final direction; the better
//     of the two answers is kept.
// With both, the same 20,000 poses end within 4e-11 of the size, 20,000 crossed cylinders within
// 1e-11, and a cylinder on another's side within 5e-10 leaning on a rim point and 3e-11 with its
// cap flat (tests/collision/gjk_epa_test.cpp).
#include "collision/narrow_phase/gjk_epa/gjk.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "collision/narrow_phase/gjk_epa/gjk_internal.hpp"

namespace tumble {

const char* gjk_status_name(GjkStatus status) {
  switch (status) {
    case GjkStatus::separated:
      return "separated";
    case GjkStatus::intersecting:
      return "intersecting";
    case GjkStatus::max_iterations:
      return "max_iterations";
    case GjkStatus::degenerate:
      return "degenerate";
  }
  return "unknown";
}

ConvexSupport ConvexSupport::of(const Shape& shape, const Transform& pose) {
  ConvexSupport s;
  s.shape = &shape;
  s.pose = pose;
  if (shape.type == ShapeType::sphere || shape.type == ShapeType::capsule)
    s.radius = shape.radius;
  return s;
}

ConvexSupport ConvexSupport::of_points(const Vec3* points, int count, const Transform& pose,
                                       Real radius) {
  ConvexSupport s;
  s.points = points;
  s.point_count = count;
  s.pose = pose;
  s.radius = radius;
  return s;
}

Vec3 ConvexSupport::core_support(const Vec3& direction, int& index) const {
  return pose.apply(detail::local_core_support(*this, pose.rotate_inverse(direction), index));
}

namespace {

// Relative size below which an edge, triangle or tetrahedron counts as degenerate.
constexpr Real kDegenerate = Real(1e-14);
// A stop by (2) or (3) with the gap ||v||^2 - v.w above this fraction of ||v||^2 (the lower
// bound more than 1e-6 of the distance short of ||v||) is a stall (see the file comment).
constexpr Real kStallGap = Real(1e-6);
// The gap's rounding: v carries an absolute error of a few ulps of the simplex's points, so
// v.w does of a few ulps of |w|^2. A restart is tried only for a gap above this fraction of
// the largest |w|^2 seen, where the lower bound is not just rounding.
constexpr Real kGapRounding = Real(1e-13);
// A refresh that replaces only nearby points takes those within this fraction of the largest
// |w| of the new support's.
constexpr Real kRefreshReach = Real(1e-2);

// A sub-simplex holding the point closest to the origin: the indices of its vertices in the
// simplex (ascending), their barycentric weights and the point's squared distance.
struct Candidate {
  int count = 0;
  std::array<int, 3> index{};
  std::array<Real, 3> weight{};
  Real distance2 = 0;
};

// The vertex region of vertex i (at p).
Candidate vertex_region(int i, const Vec3& p) {
  Candidate c;
  c.count = 1;
  c.index[0] = i;
  c.weight[0] = 1;
  c.distance2 = p.squaredNorm();
  return c;
}

// The edge region of edge (i, j) from p to p + edge, at parameter t in (0, 1).
Candidate edge_region(int i, int j, const Vec3& p, const Vec3& edge, Real t) {
  Candidate c;
  c.count = 2;
  c.index = {i, j, 0};
  c.weight = {1 - t, t, 0};
  c.distance2 = (p + t * edge).squaredNorm();
  return c;
}

// Closest point to the origin on segment (i, j) of s.
Candidate segment_candidate(const GjkSimplex& s, int i, int j) {
  const Vec3& a = s.vertex[std::size_t(i)].w;
  const Vec3& b = s.vertex[std::size_t(j)].w;
  const Vec3 ab = b - a;
  const Real len2 = ab.squaredNorm();
  const Real t_num = -a.dot(ab);
  if (!(len2 > 0)) {
    // A point: the closer end.
    return b.squaredNorm() < a.squaredNorm() ? vertex_region(j, b) : vertex_region(i, a);
  }
  if (t_num <= 0)
    return vertex_region(i, a);
  if (t_num >= len2)
    return vertex_region(j, b);
  return edge_region(i, j, a, ab, t_num / len2);
}

// Ericson's ClosestPtPointTriangle with the origin as the point, over vertices i, j, k of s.
Candidate triangle_candidate(const GjkSimplex& s, int i, int j, int k) {
  const Vec3& a = s.vertex[std::size_t(i)].w;
  const Vec3& b = s.vertex[std::size_t(j)].w;
  const Vec3& c = s.vertex[std::size_t(k)].w;
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Real area2 = ab.cross(ac).squaredNorm();
  if (!(area2 > kDegenerate * kDegenerate * ab.squaredNorm() * ac.squaredNorm()) || !(area2 > 0)) {
    // A needle or a point: the best of the three edges.
    Candidate best = segment_candidate(s, i, j);
    for (const Candidate& other : {segment_candidate(s, j, k), segment_candidate(s, i, k)})
      if (other.distance2 < best.distance2)
        best = other;
    return best;
  }
  const Real d1 = -ab.dot(a);
  const Real d2 = -ac.dot(a);
  if (d1 <= 0 && d2 <= 0)
    return vertex_region(i, a);
  const Real d3 = -ab.dot(b);
  const Real d4 = -ac.dot(b);
  if (d3 >= 0 && d4 <= d3)
    return vertex_region(j, b);
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0)
    return edge_region(i, j, a, ab, d1 / (d1 - d3));
  const Real d5 = -ab.dot(c);
  const Real d6 = -ac.dot(c);
  if (d6 >= 0 && d5 <= d6)
    return vertex_region(k, c);
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0)
    return edge_region(i, k, a, ac, d2 / (d2 - d6));
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return edge_region(j, k, b, c - b, (d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const Real denom = va + vb + vc;
  const Real v = vb / denom;
  const Real w = vc / denom;
  Candidate out;
  out.count = 3;
  out.index = {i, j, k};
  out.weight = {1 - v - w, v, w};
  out.distance2 = (a + v * ab + w * ac).squaredNorm();
  return out;
}

// The point of the candidate, summed in the order the simplex will hold its vertices. (Always
// inlined, as closest_sub_simplex is: the stall recovery calls them too, and GCC then stopped
// inlining them into the main loop.)
[[gnu::always_inline]] inline Vec3 candidate_point(const GjkSimplex& s, const Candidate& c) {
  Vec3 v = Vec3::Zero();
  for (int n = 0; n < c.count; ++n)
    v += c.weight[std::size_t(n)] * s.vertex[std::size_t(c.index[std::size_t(n)])].w;
  return v;
}

// Keeps only the candidate's vertices, in place (its indices ascend, so no vertex is
// overwritten before it is moved).
void apply(GjkSimplex& s, std::array<Real, 4>& lambda, const Candidate& c) {
  for (int n = 0; n < c.count; ++n) {
    const int from = c.index[std::size_t(n)];
    if (from != n)
      s.vertex[std::size_t(n)] = s.vertex[std::size_t(from)];
    lambda[std::size_t(n)] = c.weight[std::size_t(n)];
  }
  s.count = c.count;
}

// For the face (p, q, r) of a tetrahedron with the fourth vertex o, and n = (q - p) x (r - p):
// n . (0 - p) and n . (o - p), the sides of the origin and of o. In scalars: from Eigen's cross
// product GCC wrote n's coordinates one by one and read two back as a pair before the stores
// had retired (a failed store-to-load forwarding; perf put a tenth of gjk()'s own samples on
// the instruction after that load). The same operations in the same order as Eigen's: the same
// bits (checked on 100,000 random pairs of hulls, boxes, cylinders, capsules and spheres).
struct FaceSides {
  Real origin;
  Real opposite;
};

[[gnu::always_inline]] inline FaceSides face_sides(const Vec3& p, const Vec3& q, const Vec3& r,
                                                   const Vec3& o) {
  const Real ux = q.x() - p.x(), uy = q.y() - p.y(), uz = q.z() - p.z();
  const Real vx = r.x() - p.x(), vy = r.y() - p.y(), vz = r.z() - p.z();
  const Real nx = uy * vz - uz * vy;
  const Real ny = uz * vx - ux * vz;
  const Real nz = ux * vy - uy * vx;
  const Real origin = -(nx * p.x() + ny * p.y() + nz * p.z());
  const Real opposite = nx * (o.x() - p.x()) + ny * (o.y() - p.y()) + nz * (o.z() - p.z());
  return {origin, opposite};
}

// The smallest sub-simplex of s holding the point closest to the origin. Returns false when
// the origin is inside s, a (non-degenerate) tetrahedron; `inside_weights` then receives the
// origin's barycentric weights (for the witness points).
[[gnu::always_inline]] inline bool closest_sub_simplex(const GjkSimplex& s, Candidate& out,
                                                       std::array<Real, 4>& inside_weights) {
  switch (s.count) {
    case 1:
      out = vertex_region(0, s.vertex[0].w);
      return true;
    case 2:
      out = segment_candidate(s, 0, 1);
      return true;
    case 3:
      out = triangle_candidate(s, 0, 1, 2);
      return true;
    default:
      break;
  }
  const Vec3& a = s.vertex[0].w;
  const Vec3& b = s.vertex[1].w;
  const Vec3& c = s.vertex[2].w;
  const Vec3& d = s.vertex[3].w;
  const Real volume6 = (b - a).dot((c - a).cross(d - a));
  const Real size = std::max({(b - a).norm(), (c - a).norm(), (d - a).norm()});
  const bool flat = !(std::abs(volume6) > kDegenerate * size * size * size);
  // Faces (i, j, k) with the opposite vertex l.
  constexpr int kFaces[4][4] = {{0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 3, 1}, {1, 2, 3, 0}};
  out.distance2 = std::numeric_limits<Real>::infinity();
  bool any_outside = false;
  for (const auto& f : kFaces) {
    const FaceSides sides =
        face_sides(s.vertex[std::size_t(f[0])].w, s.vertex[std::size_t(f[1])].w,
                   s.vertex[std::size_t(f[2])].w, s.vertex[std::size_t(f[3])].w);
    const Real origin_side = sides.origin;
    const Real opposite_side = sides.opposite;
    // The origin is outside this face when it is on the other side from the opposite vertex.
    const bool outside = flat || origin_side * opposite_side < 0;
    if (!outside)
      continue;
    any_outside = true;
    const Candidate candidate = triangle_candidate(s, f[0], f[1], f[2]);
    if (candidate.distance2 < out.distance2)
      out = candidate;
  }
  if (any_outside)
    return true;
  const Real va = (b).dot((c).cross(d));
  const Real vb = -(a).dot((c).cross(d));
  const Real vc = (a).dot((b).cross(d));
  const Real vd = -(a).dot((b).cross(c));
  const Real total = va + vb + vc + vd;
  if (total != 0) {
    inside_weights = {va / total, vb / total, vc / total, vd / total};
  } else {
    inside_weights = {Real(0.25), Real(0.25), Real(0.25), Real(0.25)};
  }
  return false;
}

bool finite(const Vec3& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

// The answer the search had when it restarted, if it did. The answer is a union member, set only
// by a restart: as a std::optional, GCC cleared its 400 bytes on every query (rep stos), which cost
// separated boxes 6%.
struct StalledAnswer {
  struct Answer {
    GjkSimplex simplex;
    std::array<Real, 4> lambda;
    Vec3 v;
    Real vv;
  };
  bool restarted = false;
  union {
    Answer answer;
  };
  StalledAnswer() {}
  void save(const GjkSimplex& simplex, const std::array<Real, 4>& lambda, const Vec3& v, Real vv) {
    std::construct_at(&answer, Answer{simplex, lambda, v, vv});
    restarted = true;
  }
};

// The squared distance from a circle's point at an angle to a line, and the angles of its minima.
// The circle: centre c, orthonormal u and v spanning its plane, radius r; the line: through p
// along the unit e. With g = q + cos(a) U + sin(a) V, the point's offset square to the line
// (q, U, V the parts of c - p, r u, r v square to e), the squared distance |g|^2 is a
// trigonometric polynomial of the angle whose six coefficients are worked out once, so a Newton
// step costs one sine and cosine and a few products.
struct CircleToLine {
  Real qq, qu, qv, uu, uv, vv;

  CircleToLine(const Vec3& c, const Vec3& u, const Vec3& v, Real r, const Vec3& p, const Vec3& e) {
    const auto across = [&](const Vec3& x) { return Vec3(x - e * e.dot(x)); };
    const Vec3 q = across(c - p);
    const Vec3 big_u = across(u) * r;
    const Vec3 big_v = across(v) * r;
    qq = q.squaredNorm();
    qu = q.dot(big_u);
    qv = q.dot(big_v);
    uu = big_u.squaredNorm();
    uv = big_u.dot(big_v);
    vv = big_v.squaredNorm();
  }

  Real squared(Real angle) const {
    const Real c = std::cos(angle);
    const Real s = std::sin(angle);
    return qq + 2 * (c * qu + s * qv) + c * c * uu + 2 * s * c * uv + s * s * vv;
  }

  // Newton's method on the angle from `angle`, a fixed step downhill where the curvature is not
  // positive (away from a minimum). Returns the angle of the minimum it reaches.
  Real minimum_from(Real angle) const {
    for (int step = 0; step < 12; ++step) {
      const Real c = std::cos(angle);
      const Real s = std::sin(angle);
      // Halves of the first and second derivatives of |g|^2: g.g' and |g'|^2 + g.g''.
      const Real slope = -s * qu + c * qv + c * s * (vv - uu) + (c * c - s * s) * uv;
      const Real curvature = (s * s - c * c) * (uu - vv) - 4 * s * c * uv - c * qu - s * qv;
      const Real change = curvature > 0 ? slope / curvature : std::copysign(Real(0.5), slope);
      angle -= change;
      if (!(std::abs(change) > Real(1e-12)))
        break;
    }
    return angle;
  }
};

// The refreshed simplices (see the file comment). Each is built from the stalled simplex s and the
// new support w; every vertex stays a point of A - B.

// Every vertex's point on A (on_a) or on B replaced by w's, or (near_only) only those within
// `reach2` (squared) of w's.
GjkSimplex with_parts_of_w(const GjkSimplex& s, const SimplexVertex& w, bool on_a, bool near_only,
                           Real reach2) {
  GjkSimplex t = s;
  for (int i = 0; i < t.count; ++i) {
    SimplexVertex& u = t.vertex[std::size_t(i)];
    if (on_a && (!near_only || (u.a - w.a).squaredNorm() <= reach2)) {
      u.a = w.a;
      u.index_a = w.index_a;
    } else if (!on_a && (!near_only || (u.b - w.b).squaredNorm() <= reach2)) {
      u.b = w.b;
      u.index_b = w.index_b;
    }
    u.w = u.a - u.b;
  }
  return t;
}

// A cylinder's points (A's, or B's) turned about its axis to w's angle, each on its own cap.
GjkSimplex turned_to_w(const detail::PairInA& pair, const GjkSimplex& s, const SimplexVertex& w,
                       bool on_a) {
  GjkSimplex t = s;
  for (int i = 0; i < t.count; ++i) {
    SimplexVertex& u = t.vertex[std::size_t(i)];
    if (on_a) {
      // A's frame is the cylinder's: the axis is z.
      u.a.x() = w.a.x();
      u.a.y() = w.a.y();
    } else {
      // B's axis is the third column of its rotation into A's frame.
      const Vec3 axis = pair.rotation_b.col(2);
      const Vec3 around = w.b - u.b;
      u.b += around - axis * axis.dot(around);
    }
    u.w = u.a - u.b;
  }
  return t;
}

// Two cylinders' sides crossed: the closest points lie inside both side lines, and a simplex of
// three of the four end pairs can miss where the lines cross, so all four go in (a flat
// tetrahedron: closest_sub_simplex takes its best face). The lines are those of the support
// `ends`: A's runs along z in A's frame, B's along its axis from its support point to the other
// cap.
GjkSimplex side_line_ends(const detail::PairInA& pair, const SimplexVertex& ends) {
  const Vec3 axis_b = pair.rotation_b.col(2);
  const Real length_b = 2 * pair.b->shape->half_length;
  const Vec3 b_other = ends.b + axis_b * (ends.index_b == 1 ? -length_b : length_b);
  const Real half_a = pair.a->shape->half_length;
  GjkSimplex t;
  for (int corner = 0; corner < 4; ++corner) {
    SimplexVertex& u = t.vertex[std::size_t(corner)];
    u.a = Vec3(ends.a.x(), ends.a.y(), corner & 1 ? half_a : -half_a);
    u.index_a = corner & 1;
    u.b = corner & 2 ? ends.b : b_other;
    u.index_b = corner & 2 ? ends.index_b : 1 - ends.index_b;
    u.w = u.a - u.b;
  }
  t.count = 4;
  return t;
}

// The support facing across the two cylinders' common perpendicular of their axes (near touching,
// v's direction can be far off while |v| is small); false for parallel axes, whose sides touch
// along a line that GJK finds.
bool support_across_axes(detail::PairInA& pair, SimplexVertex& out) {
  Vec3 across = Vec3::UnitZ().cross(Vec3(pair.rotation_b.col(2)));
  if (!(across.squaredNorm() > kDegenerate))
    return false;
  if (across.dot(pair.translation_b) > 0)
    across = -across;  // from B to A
  out = pair.support(-across);
  return true;
}

// One cylinder's rim on the other's side (rim_of_a: A's rim on B's side): the rim points closest
// to the other's axis line, on the rim of w's cap, against the other's side line facing them;
// the closest point is the rim's distance to the side (when it lies between the caps). Empty
// (count 0) when the rim point is on the other's axis.
GjkSimplex rim_on_side(const detail::PairInA& pair, const SimplexVertex& w, bool rim_of_a) {
  const Shape& rim_shape = rim_of_a ? *pair.a->shape : *pair.b->shape;
  const Shape& side_shape = rim_of_a ? *pair.b->shape : *pair.a->shape;
  // Both cylinders in A's frame: A's axis is z through the origin.
  const Vec3 axis_b = pair.rotation_b.col(2);
  const Vec3 rim_axis = rim_of_a ? Vec3::UnitZ() : axis_b;
  const Vec3 rim_u = rim_of_a ? Vec3::UnitX() : Vec3(pair.rotation_b.col(0));
  const Vec3 rim_v = rim_of_a ? Vec3::UnitY() : Vec3(pair.rotation_b.col(1));
  const Vec3 rim_centre_of_axis = rim_of_a ? Vec3::Zero() : pair.translation_b;
  const Vec3 side_axis = rim_of_a ? axis_b : Vec3::UnitZ();
  const Vec3 side_centre = rim_of_a ? pair.translation_b : Vec3::Zero();
  const Vec3& rim_start = rim_of_a ? w.a : w.b;
  const int rim_cap = rim_of_a ? w.index_a : w.index_b;
  const Vec3 rim_centre = rim_centre_of_axis + rim_axis * (rim_cap == 1 ? rim_shape.half_length
                                                                        : -rim_shape.half_length);
  // The squared distance to the other's axis along the rim has at most two minima. Newton from
  // w's angle and from the opposite one finds them; the two closest distinct ones are kept. (Five
  // starts around the rim measured 4.7e-11 of the size against 1.9e-10 on a probe of 20,000 caps
  // flat on a side, at 1.4x the time.)
  const CircleToLine to_axis(rim_centre, rim_u, rim_v, rim_shape.radius, side_centre, side_axis);
  const Vec3 start = rim_start - rim_centre;
  Real angle = 0;
  Real across_angle = 0;
  Real best_squared = std::numeric_limits<Real>::infinity();
  Real second_squared = std::numeric_limits<Real>::infinity();
  const Real start_angle = std::atan2(start.dot(rim_v), start.dot(rim_u));
  for (int k = 0; k < 2; ++k) {
    const Real found = to_axis.minimum_from(start_angle + k * std::numbers::pi_v<Real>);
    const Real squared = to_axis.squared(found);
    const bool same =
        k > 0 && std::abs(std::remainder(found - angle, 2 * std::numbers::pi_v<Real>)) < Real(1e-9);
    if (squared < best_squared) {
      if (!same) {
        across_angle = angle;
        second_squared = best_squared;
      }
      angle = found;
      best_squared = squared;
    } else if (!same && squared < second_squared) {
      across_angle = found;
      second_squared = squared;
    }
  }
  if (!(second_squared < std::numeric_limits<Real>::infinity()))
    across_angle = angle;
  const auto rim_at = [&](Real a) {
    return Vec3(rim_centre + (rim_u * std::cos(a) + rim_v * std::sin(a)) * rim_shape.radius);
  };
  const Vec3 rim_point = rim_at(angle);
  Vec3 outward = rim_point - side_centre;
  outward -= side_axis * side_axis.dot(outward);
  GjkSimplex t;
  if (!(outward.squaredNorm() > 0))
    return t;
  outward.normalize();
  // The other minimum (a cap flat over the side has two, where the rim crosses over the side
  // line): with both, the simplex holds the chord between them, which the line passes under.
  const Vec3 second_point = rim_at(across_angle);
  t.count = (second_point - rim_point).squaredNorm() > 0 ? 4 : 2;
  for (int corner = 0; corner < t.count; ++corner) {
    SimplexVertex& u = t.vertex[std::size_t(corner)];
    const int end = corner & 1;
    const Vec3& on_rim = corner < 2 ? rim_point : second_point;
    const Vec3 side_point =
        side_centre + outward * side_shape.radius +
        side_axis * (end == 1 ? side_shape.half_length : -side_shape.half_length);
    u.a = rim_of_a ? on_rim : side_point;
    u.b = rim_of_a ? side_point : on_rim;
    u.index_a = rim_of_a ? rim_cap : end;
    u.index_b = rim_of_a ? end : rim_cap;
    u.w = u.a - u.b;
  }
  return t;
}

// Refresh (see the file comment): tries the simplices above and adopts the closest into
// (s, lambda, v, vv); returns true when it is closer than the current one. The order is fixed,
// and the first of equally close ones is kept.
bool refresh(detail::PairInA& pair, const SimplexVertex& w, Real max_w2, GjkSimplex& s,
             std::array<Real, 4>& lambda, Vec3& v, Real& vv) {
  const auto is_cylinder = [](const ConvexSupport* c) {
    return c->shape != nullptr && c->shape->type == ShapeType::cylinder;
  };
  const bool a_cylinder = is_cylinder(pair.a);
  const bool b_cylinder = is_cylinder(pair.b);
  GjkSimplex best_simplex;
  Candidate best_candidate;
  Vec3 best_point = v;
  Real best_vv = vv;
  // Keeps simplex t if its closest point is the closest yet.
  const auto consider = [&](const GjkSimplex& t) {
    Candidate candidate;
    std::array<Real, 4> unused{};
    if (t.count == 0 || !closest_sub_simplex(t, candidate, unused))
      return;  // four side-line ends around the origin: not a separated answer; left to GJK
    const Vec3 point = candidate_point(t, candidate);
    if (point.squaredNorm() < best_vv) {
      best_vv = point.squaredNorm();
      best_point = point;
      best_simplex = t;
      best_candidate = candidate;
    }
  };
  const Real reach2 = kRefreshReach * kRefreshReach * max_w2;
  for (const bool near_only : {false, true}) {
    consider(with_parts_of_w(s, w, true, near_only, reach2));
    consider(with_parts_of_w(s, w, false, near_only, reach2));
  }
  if (a_cylinder)
    consider(turned_to_w(pair, s, w, true));
  if (b_cylinder)
    consider(turned_to_w(pair, s, w, false));
  if (a_cylinder && b_cylinder) {
    consider(side_line_ends(pair, w));
    SimplexVertex across;
    if (support_across_axes(pair, across))
      consider(side_line_ends(pair, across));
    consider(rim_on_side(pair, w, true));
    consider(rim_on_side(pair, w, false));
  }
  if (!(best_vv < vv))
    return false;
  s = best_simplex;
  apply(s, lambda, best_candidate);
  v = best_point;
  vv = best_vv;
  return true;
}

// Where the search goes on from after a stall: the closest point, its squared norm and its
// barycentric weights.
struct Resume {
  bool go_on = false;
  Vec3 v = Vec3::Zero();
  Real vv = 0;
  std::array<Real, 4> lambda{};
};

// After a stop by (2) or (3) at support w with the gap above kStallGap ||v||^2: a refresh, or else
// a restart (once, and only when the gap is above its rounding) from w alone, saving the answer in
// `stalled`. Out of line, with v, vv and lambda in and out by value, so that the main loop's code
// is what it was without the recovery (separated boxes measure the same, 196-201 ns against
// 196-198).
[[gnu::noinline]] Resume recover_from_stall(detail::PairInA& pair, const SimplexVertex w,
                                            Real max_w2, GjkSimplex& s, std::array<Real, 4> lambda,
                                            Vec3 v, Real vv, StalledAnswer& stalled) {
  if (refresh(pair, w, max_w2, s, lambda, v, vv))
    return {true, v, vv, lambda};
  const Real gap = vv - v.dot(w.w);
  if (stalled.restarted || !(gap > kStallGap * vv + kGapRounding * max_w2))
    return {};
  stalled.save(s, lambda, v, vv);
  s.vertex[0] = w;
  s.count = 1;
  return {true, w.w, w.w.squaredNorm(), {1, 0, 0, 0}};
}

}  // namespace

GjkResult gjk(const ConvexSupport& a, const ConvexSupport& b, GjkCache* cache,
              const GjkSettings& settings) {
  detail::PairInA pair(a, b);
  GjkResult result;
  Vec3 direction = pair.translation_b * Real(-1);  // from B's centre towards A's
  if (cache != nullptr && cache->valid) {
    direction = cache->axis_in_a;
    pair.hint_a = cache->index_a;
    pair.hint_b = cache->index_b;
  }
  if (!(direction.squaredNorm() > 0) || !finite(direction))
    direction = Vec3::UnitX();

  GjkSimplex& s = result.simplex;
  std::array<Real, 4> lambda{1, 0, 0, 0};
  s.vertex[0] = pair.support(-direction);
  s.count = 1;
  Vec3 v = s.vertex[0].w;
  Real vv = v.squaredNorm();
  Real max_w2 = vv;
  const Real rel2 = settings.relative_tolerance * settings.relative_tolerance;
  const Real touch2 = settings.touching_tolerance * settings.touching_tolerance;
  GjkStatus status = GjkStatus::max_iterations;
  int iteration = 0;
  // The answer before a restart (see the file comment).
  StalledAnswer stalled;
  // After a stop by (2) or (3): whether the search goes on (see the file comment). The cheap test
  // first, so that a search that converged does not call out of line.
  const auto recover = [&](const SimplexVertex& w) {
    if (!(vv - v.dot(w.w) > kStallGap * vv))
      return false;
    const Resume resume = recover_from_stall(pair, w, max_w2, s, lambda, v, vv, stalled);
    if (resume.go_on) {
      v = resume.v;
      vv = resume.vv;
      lambda = resume.lambda;
    }
    return resume.go_on;
  };
  // The loop runs again after a recovered stall. Stops by (2) and (3) leave it with the support
  // they stopped at, so that the recovery stays out of the loop's body.
  for (;;) {
    // 2 or 3, the test that stopped the loop short; the support it stopped at is left in the slot
    // after the simplex.
    int stopped_by = 0;
    for (; iteration < settings.max_iterations; ++iteration) {
      if (vv <= touch2 * max_w2) {
        status = GjkStatus::intersecting;
        break;
      }
      const SimplexVertex w = pair.support(-v);
      if (!finite(w.w)) {
        status = GjkStatus::degenerate;
        break;
      }
      // (1) no more than the relative tolerance to gain: converged.
      if (vv - v.dot(w.w) <= rel2 * vv) {
        status = GjkStatus::separated;
        break;
      }
      // (2) w already in the simplex: no progress is possible.
      bool repeated = false;
      for (int i = 0; i < s.count; ++i)
        repeated = repeated || s.vertex[std::size_t(i)].w == w.w;
      if (repeated) {
        status = GjkStatus::separated;
        stopped_by = 2;
        s.vertex[std::size_t(s.count)] = w;
        break;
      }
      // w goes into the slot after the simplex; the simplex takes it only once the new closest
      // point is known to be closer, so an oscillation leaves the previous simplex as it was.
      s.vertex[std::size_t(s.count)] = w;
      ++s.count;
      max_w2 = std::max(max_w2, w.w.squaredNorm());
      Candidate candidate;
      if (!closest_sub_simplex(s, candidate, lambda)) {
        status = GjkStatus::intersecting;
        v = Vec3::Zero();
        vv = 0;
        ++iteration;
        break;
      }
      const Vec3 next = candidate_point(s, candidate);
      const Real next_vv = next.squaredNorm();
      // (3) oscillation: rounding stopped the strict decrease; keep the previous simplex.
      if (!(next_vv < vv)) {
        --s.count;
        status = GjkStatus::separated;
        stopped_by = 3;
        break;
      }
      apply(s, lambda, candidate);
      v = next;
      vv = next_vv;
    }
    // (3) counts its iteration; so does (2) when the search goes on.
    if (stopped_by == 3)
      ++iteration;
    if (stopped_by == 0 || !recover(s.vertex[std::size_t(s.count)]))
      break;
    if (stopped_by == 2)
      ++iteration;
    status = GjkStatus::max_iterations;
  }
  result.iterations = iteration;
  if (stalled.restarted) {
    if (status != GjkStatus::intersecting && !(vv < stalled.answer.vv)) {
      // The restart found nothing closer: the answer before it stands.
      s = stalled.answer.simplex;
      lambda = stalled.answer.lambda;
      v = stalled.answer.v;
      vv = stalled.answer.vv;
    }
    // A restart begins after the search has stopped with an answer; running out of iterations
    // or meeting a non-finite support in it leaves that answer (or a better one) standing.
    if (status == GjkStatus::max_iterations || status == GjkStatus::degenerate)
      status = GjkStatus::separated;
  }

  Vec3 on_a = Vec3::Zero();
  Vec3 on_b = Vec3::Zero();
  for (int i = 0; i < s.count; ++i) {
    on_a += lambda[std::size_t(i)] * s.vertex[std::size_t(i)].a;
    on_b += lambda[std::size_t(i)] * s.vertex[std::size_t(i)].b;
  }
  const Real core_distance = std::sqrt(vv);
  Vec3 normal_in_a = core_distance > 0 ? Vec3(v / core_distance) : Vec3(direction.normalized());
  if (status == GjkStatus::intersecting) {
    result.distance = 0;
    normal_in_a = direction.normalized();
    on_b = on_a;
  } else {
    result.distance = core_distance - a.radius - b.radius;
    on_a -= normal_in_a * a.radius;
    on_b += normal_in_a * b.radius;
    if (cache != nullptr) {
      cache->axis_in_a = v;
      cache->index_a = pair.hint_a;
      cache->index_b = pair.hint_b;
      cache->valid = true;
    }
  }
  result.status = status;
  result.normal = a.pose.rotate(normal_in_a);
  result.point_a = a.pose.apply(on_a);
  result.point_b = a.pose.apply(on_b);
  return result;
}

}  // namespace tumble
