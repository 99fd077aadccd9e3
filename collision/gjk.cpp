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
#include "collision/gjk.hpp"

#include <algorithm>
#include <cmath>

#include "collision/gjk_internal.hpp"

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

struct Closest {
  Vec3 v;
  std::array<Real, 4> lambda;
};

Vec3 combine(const GjkSimplex& s, const std::array<Real, 4>& lambda) {
  Vec3 v = Vec3::Zero();
  for (int i = 0; i < s.count; ++i)
    v += lambda[std::size_t(i)] * s.vertex[std::size_t(i)].w;
  return v;
}

// Closest point to the origin on segment (i, j) of s; returns its squared distance and writes
// the candidate (indices and weights) without changing s.
struct Candidate {
  int count = 0;
  std::array<int, 3> index{};
  std::array<Real, 3> weight{};
  Real distance2 = 0;
};

Candidate segment_candidate(const GjkSimplex& s, int i, int j) {
  const Vec3& a = s.vertex[std::size_t(i)].w;
  const Vec3& b = s.vertex[std::size_t(j)].w;
  const Vec3 ab = b - a;
  const Real len2 = ab.squaredNorm();
  const Real t_num = -a.dot(ab);
  Candidate c;
  c.count = 1;
  c.weight[0] = 1;
  if (!(len2 > 0) || t_num <= 0) {
    // A point, or the origin behind a: a (or b when the segment is a point and b is closer).
    c.index[0] = i;
    c.distance2 = a.squaredNorm();
    if (!(len2 > 0) && b.squaredNorm() < c.distance2) {
      c.index[0] = j;
      c.distance2 = b.squaredNorm();
    }
    return c;
  }
  if (t_num >= len2) {
    c.index[0] = j;
    c.distance2 = b.squaredNorm();
    return c;
  }
  const Real t = t_num / len2;
  c.count = 2;
  c.index = {i, j, 0};
  c.weight = {1 - t, t, 0};
  c.distance2 = (a + t * ab).squaredNorm();
  return c;
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
  Candidate out;
  const Real d1 = -ab.dot(a);
  const Real d2 = -ac.dot(a);
  if (d1 <= 0 && d2 <= 0) {
    out.count = 1;
    out.index[0] = i;
    out.weight[0] = 1;
    out.distance2 = a.squaredNorm();
    return out;
  }
  const Real d3 = -ab.dot(b);
  const Real d4 = -ac.dot(b);
  if (d3 >= 0 && d4 <= d3) {
    out.count = 1;
    out.index[0] = j;
    out.weight[0] = 1;
    out.distance2 = b.squaredNorm();
    return out;
  }
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const Real t = d1 / (d1 - d3);
    out.count = 2;
    out.index = {i, j, 0};
    out.weight = {1 - t, t, 0};
    out.distance2 = (a + t * ab).squaredNorm();
    return out;
  }
  const Real d5 = -ab.dot(c);
  const Real d6 = -ac.dot(c);
  if (d6 >= 0 && d5 <= d6) {
    out.count = 1;
    out.index[0] = k;
    out.weight[0] = 1;
    out.distance2 = c.squaredNorm();
    return out;
  }
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const Real t = d2 / (d2 - d6);
    out.count = 2;
    out.index = {i, k, 0};
    out.weight = {1 - t, t, 0};
    out.distance2 = (a + t * ac).squaredNorm();
    return out;
  }
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const Real t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    out.count = 2;
    out.index = {j, k, 0};
    out.weight = {1 - t, t, 0};
    out.distance2 = (b + t * (c - b)).squaredNorm();
    return out;
  }
  const Real denom = va + vb + vc;
  const Real v = vb / denom;
  const Real w = vc / denom;
  out.count = 3;
  out.index = {i, j, k};
  out.weight = {1 - v - w, v, w};
  out.distance2 = (a + v * ab + w * ac).squaredNorm();
  return out;
}

void apply(GjkSimplex& s, std::array<Real, 4>& lambda, const Candidate& c) {
  std::array<SimplexVertex, 4> kept{};
  for (int n = 0; n < c.count; ++n) {
    kept[std::size_t(n)] = s.vertex[std::size_t(c.index[std::size_t(n)])];
    lambda[std::size_t(n)] = c.weight[std::size_t(n)];
  }
  s.vertex = kept;
  s.count = c.count;
}

// Reduces s to the smallest sub-simplex holding the point closest to the origin. Returns true
// when the origin is inside a (non-degenerate) tetrahedron.
bool reduce(GjkSimplex& s, std::array<Real, 4>& lambda) {
  switch (s.count) {
    case 1:
      lambda[0] = 1;
      return false;
    case 2:
      apply(s, lambda, segment_candidate(s, 0, 1));
      return false;
    case 3:
      apply(s, lambda, triangle_candidate(s, 0, 1, 2));
      return false;
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
  Candidate best;
  best.distance2 = std::numeric_limits<Real>::infinity();
  bool any_outside = false;
  for (const auto& f : kFaces) {
    const Vec3& p = s.vertex[std::size_t(f[0])].w;
    const Vec3 n = (s.vertex[std::size_t(f[1])].w - p).cross(s.vertex[std::size_t(f[2])].w - p);
    const Real origin_side = -n.dot(p);
    const Real opposite_side = n.dot(s.vertex[std::size_t(f[3])].w - p);
    // The origin is outside this face when it is on the other side from the opposite vertex.
    const bool outside = flat || origin_side * opposite_side < 0;
    if (!outside)
      continue;
    any_outside = true;
    const Candidate c = triangle_candidate(s, f[0], f[1], f[2]);
    if (c.distance2 < best.distance2)
      best = c;
  }
  if (!any_outside) {
    // Barycentric weights of the origin, for the witness points.
    const Real va = (b).dot((c).cross(d));
    const Real vb = -(a).dot((c).cross(d));
    const Real vc = (a).dot((b).cross(d));
    const Real vd = -(a).dot((b).cross(c));
    const Real total = va + vb + vc + vd;
    if (total != 0) {
      lambda = {va / total, vb / total, vc / total, vd / total};
    } else {
      lambda = {Real(0.25), Real(0.25), Real(0.25), Real(0.25)};
    }
    return true;
  }
  apply(s, lambda, best);
  return false;
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
  if (!(direction.squaredNorm() > 0) || !direction.allFinite())
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
  for (; iteration < settings.max_iterations; ++iteration) {
    if (vv <= touch2 * max_w2) {
      status = GjkStatus::intersecting;
      break;
    }
    const SimplexVertex w = pair.support(-v);
    if (!w.w.allFinite()) {
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
      break;
    }
    const GjkSimplex previous = s;
    const std::array<Real, 4> previous_lambda = lambda;
    s.vertex[std::size_t(s.count)] = w;
    ++s.count;
    max_w2 = std::max(max_w2, w.w.squaredNorm());
    if (reduce(s, lambda)) {
      status = GjkStatus::intersecting;
      v = Vec3::Zero();
      vv = 0;
      ++iteration;
      break;
    }
    const Vec3 next = combine(s, lambda);
    const Real next_vv = next.squaredNorm();
    // (3) oscillation: rounding stopped the strict decrease; keep the previous simplex.
    if (!(next_vv < vv)) {
      s = previous;
      lambda = previous_lambda;
      status = GjkStatus::separated;
      ++iteration;
      break;
    }
    v = next;
    vv = next_vv;
  }
  result.iterations = iteration;

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
