// Vertex-face and edge-edge continuous collision under linear vertex motion (Provot, "Collision
// and self-collision handling in cloth model dedicated to design garments", Graphics Interface
// 1997; Bridson, Fedkiw and Anderson, "Robust treatment of collisions, contact and friction for
// cloth animation", SIGGRAPH 2002), in two conservative stages.
//
// 1. The coplanarity cubic. A contact needs the four points coplanar: f(t) = det[u, v, w] = 0
//    with u, v, w differences of the moving vertices (vertex-face: n(t) . (p(t) - a(t)) with n(t)
//    the triangle's normal, cubic in t). Instead of a closed-form root (Cardano is fragile near
//    double roots and useless when f is identically zero, as for coplanar motion), f is written
//    in the Bernstein basis of [0, 1]. Each Bernstein coefficient is a mean of determinants of
//    the vertex differences at t = 0 and t = 1, so it is computed directly from the input with a
//    rounding error bounded a priori. By the convex hull property, f has no root on an
//    interval where all its coefficients are of one sign beyond that bound; halving by de
//    Casteljau (each half again a Bernstein form) brackets the roots into a few intervals,
//    and an interval on which f stays within the bound (coplanar or parallel motion) is kept
//    whole. No interval holding a root is ever dropped; nothing is iterated to convergence.
//
// 2. The inside test, on each kept time interval in order. The contact condition is that
//    F(t, u, v) = 0 for some t in the interval and (u, v) in [0, 1]^2, with
//      vertex-face: F = p(t) - a(t) - u (b(t) - a(t)) - (1 - u) v (c(t) - a(t))
//      edge-edge:   F = a0(t) + u (a1(t) - a0(t)) - b0(t) - v (b1(t) - b0(t)).
//    For the triangle, (u, (1 - u) v) is the collapsed square of Duffy ("Quadrature over a
//    pyramid or cube of integrands with a singularity at a vertex", SIAM J. Numer. Anal. 19(6),
//    1982): it maps [0, 1]^2 onto the closed triangle exactly (the side u = 1 collapses to b),
//    so no box holds parameters outside it. (Barycentric (u, v) with u + v <= 1 needs the
//    square's other half cut away, and a box that straddles the diagonal u + v = 1 holds points
//    beyond edge bc: a vertex passing just outside bc is a zero of F inside that box, and boxes
//    had to shrink to the gap before they left the diagonal.)
//    F is affine in each of t, u and v separately (multilinear), so over a box of parameters
//    each of its components, and its component along any fixed direction, lies between its
//    values at the 8 corners. A box holds no contact if, on some direction, the corner values
//    widened by their rounding bound leave zero out. The directions are the three axes and, for
//    the triangle, its normal and its three edges' normals in its plane at the box's middle
//    time: the axes alone leave a vertex that slides in the plane of the triangle just outside
//    an edge to boxes no wider than the gap, a curve of them over the motion (a search that ran
//    out of boxes); the edge's normal separates it at once. A box not excluded is split along
//    the parameter that spreads F most. A box whose image is narrower than the tolerance is
//    reported as a contact at its earliest time; boxes are taken earliest first, so the first
//    contact box ends the search. This is the inclusion test of Wang, Ferguson, Schneider,
//    Jiang, Attene and Panozzo, "A Large-scale Benchmark and an Inclusion-based Algorithm for
//    Continuous Collision Detection", ACM TOG 40(5), 2021, with the box bounded by its corners
//    (exact for multilinear F) and restricted to the time intervals of stage 1. Degenerate
//    motions need no special case: a coplanar sliding vertex is decided by the same boxes as
//    any other.
//
// Rounding: every bound assumes round-to-nearest doubles and is a generous multiple of the
// worst case, measured against M, the largest coordinate magnitude in the query. Parameters
// are dyadic (halving), so 1 - t and 1 - u are exact.
#include "collision/ccd/mesh_ccd.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tumble {
namespace {

enum class Feature : std::uint8_t { vertex_face, edge_edge };

constexpr Real kUnitRoundoff = std::numeric_limits<Real>::epsilon() / 2;  // 2^-53
// Parameter boxes are not split below this width (the parameters stay exact dyadics).
constexpr Real kMinParameterWidth = Real(1) / Real(1ull << 50);
// Coplanarity intervals are not halved below 2^-kMaxCubicDepth.
constexpr int kMaxCubicDepth = 10;
constexpr int kMaxTimeIntervals = 32;
constexpr int kStackSize = 200;  // > the deepest chain of splits (3 * 50 parameters)
// The later halves of splits in t, kept in time order (stage 2), 7 KB. The vertex-face queries
// of the sample keep at most 48 there, those of bench_ccd's sliding set 7; some coplanar and
// degenerate motions fill it, and its latest boxes are then dropped and searched again later
// (see search_interval).
constexpr int kQueueSize = 128;

struct Query {
  Feature feature;
  std::array<Vec3, 4> start;
  std::array<Vec3, 4> end;
  Real magnitude = 0;  // M: the largest |coordinate|
};

struct TimeInterval {
  Real begin;
  Real end;
};

Real triple(const Vec3& u, const Vec3& v, const Vec3& w) {
  return u.dot(v.cross(w));
}

// The three edge vectors whose determinant is the coplanarity function at one end of the step.
void coplanarity_vectors(Feature feature, const std::array<Vec3, 4>& x, Vec3& u, Vec3& v, Vec3& w) {
  if (feature == Feature::vertex_face) {
    u = x[2] - x[1];  // b - a
    v = x[3] - x[1];  // c - a
    w = x[0] - x[1];  // p - a
  } else {
    u = x[1] - x[0];  // a1 - a0
    v = x[2] - x[0];  // b0 - a0
    w = x[3] - x[0];  // b1 - a0
  }
}

// Stage 1: the time intervals that may hold a root of the coplanarity cubic, in increasing
// order. Returns how many were written.
int coplanarity_intervals(const Query& q, std::array<TimeInterval, kMaxTimeIntervals>& out) {
  Vec3 u0, v0, w0, u1, v1, w1;
  coplanarity_vectors(q.feature, q.start, u0, v0, w0);
  coplanarity_vectors(q.feature, q.end, u1, v1, w1);
  // f(t) = det[(1-t) u0 + t u1, ...]: the Bernstein coefficient k is the mean of the
  // determinants that take k of their three vectors from t = 1.
  std::array<Real, 4> b{};
  b[0] = triple(u0, v0, w0);
  b[1] = (triple(u1, v0, w0) + triple(u0, v1, w0) + triple(u0, v0, w1)) / 3;
  b[2] = (triple(u0, v1, w1) + triple(u1, v0, w1) + triple(u1, v1, w0)) / 3;
  b[3] = triple(u1, v1, w1);
  // Each difference is at most 2M with error 2M u; a determinant has six triple products of
  // such numbers and five sums: below 60 u (2M)^3 = 480 u M^3. Take four times that.
  const Real m = q.magnitude;
  const Real coefficient_error = 2048 * kUnitRoundoff * m * m * m;
  Real largest = 0;
  for (Real c : b)
    largest = std::max(largest, std::abs(c));

  struct Piece {
    Real begin;
    Real end;
    std::array<Real, 4> b;
    int depth;
  };
  std::array<Piece, 2 * kMaxCubicDepth + 2> stack{};
  int top = 0;
  stack[top++] = {0, 1, b, 0};
  int count = 0;
  while (top > 0) {
    const Piece p = stack[--top];
    // De Casteljau halving adds at most three roundings of size u * largest per level.
    const Real bound = coefficient_error + 4 * (p.depth + 1) * kUnitRoundoff * largest;
    const Real lo = std::min({p.b[0], p.b[1], p.b[2], p.b[3]});
    const Real hi = std::max({p.b[0], p.b[1], p.b[2], p.b[3]});
    if (lo > bound || hi < -bound)
      continue;  // one sign throughout: no root here
    const bool flat = lo >= -bound && hi <= bound;
    if (flat || p.depth == kMaxCubicDepth) {
      if (count > 0 && out[count - 1].end == p.begin) {
        out[count - 1].end = p.end;  // adjacent: merge
      } else if (count == kMaxTimeIntervals) {
        out[count - 1].end = p.end;  // full: widen the last one (still covers every root)
      } else {
        out[count++] = {p.begin, p.end};
      }
      continue;
    }
    const Real mid = Real(0.5) * (p.begin + p.end);
    const Real b01 = Real(0.5) * (p.b[0] + p.b[1]);
    const Real b12 = Real(0.5) * (p.b[1] + p.b[2]);
    const Real b23 = Real(0.5) * (p.b[2] + p.b[3]);
    const Real b012 = Real(0.5) * (b01 + b12);
    const Real b123 = Real(0.5) * (b12 + b23);
    const Real b0123 = Real(0.5) * (b012 + b123);
    // Later half first, so that the earlier half is taken off the stack first.
    stack[top++] = {mid, p.end, {b0123, b123, b23, p.b[3]}, p.depth + 1};
    stack[top++] = {p.begin, mid, {p.b[0], b01, b012, b0123}, p.depth + 1};
  }
  return count;
}

struct Box {
  Real t0, t1, u0, u1, v0, v1;
  std::int32_t depth;  // splits from the interval's box: orders boxes that start together
};

// F at one time as o - u e - w g, with w = (1 - u) v for the triangle and w = v for two edges.
struct Residual {
  Vec3 o, e, g;
};

Residual residual_at(const Query& q, Real t) {
  const Real s = 1 - t;  // exact: t is dyadic
  std::array<Vec3, 4> x;
  for (int i = 0; i < 4; ++i)
    x[i] = s * q.start[i] + t * q.end[i];
  if (q.feature == Feature::vertex_face)
    return {x[0] - x[1], x[2] - x[1], x[3] - x[1]};  // p - a, b - a, c - a
  return {x[0] - x[2], x[0] - x[1], x[3] - x[2]};    // a0 - b0, a0 - a1, b1 - b0
}

Vec3 residual(Feature feature, const Residual& r, Real u, Real v) {
  const Real w = feature == Feature::vertex_face ? (1 - u) * v : v;
  return r.o - u * r.e - w * r.g;
}

// The directions besides the axes on which the corner values of F are tested (see the top of
// the file): for the triangle its normal and its edges' normals in its plane, here at the box's
// middle time. Any vector is sound (the hull property holds along every fixed direction); these
// only need to be close to the separating ones. Returns how many were written.
int separating_directions(Feature feature, const Residual& r0, const Residual& r1,
                          std::array<Vec3, 4>& out) {
  if (feature != Feature::vertex_face)
    return 0;
  const Vec3 ab = r0.e + r1.e;  // twice the mid-time edges; the length does not matter
  const Vec3 ac = r0.g + r1.g;
  const Vec3 n = ab.cross(ac);
  out[0] = n;
  out[1] = ab.cross(n);
  out[2] = n.cross(ac);
  out[3] = (ac - ab).cross(n);
  return 4;
}

// True if the values `f` leave zero out along `d` by more than their rounding. Each value has
// an error below `residual_error` per component, and the dot product adds at most 3u sum |d_k
// f_k| < 21 u M |d|_1 (|f_k| < 7M): with d scaled to a largest component of 1 (|d|_1 <= 3),
// 2 |d|_1 residual_error covers both. A direction too short to scale is skipped (no verdict).
bool separated_along(Vec3 d, const std::array<Vec3, 8>& f, Real residual_error) {
  const Real scale = d.cwiseAbs().maxCoeff();
  if (!(scale >= std::numeric_limits<Real>::min()) || !std::isfinite(scale))
    return false;
  d /= scale;
  const Real bound = 2 * d.lpNorm<1>() * residual_error;
  Real lo = d.dot(f[0]);
  Real hi = lo;
  for (int c = 1; c < 8; ++c) {
    const Real value = d.dot(f[c]);
    lo = std::min(lo, value);
    hi = std::max(hi, value);
  }
  return lo > bound || hi < -bound;
}

enum class BoxVerdict : std::uint8_t { excluded, contact, split_t, split_u, split_v };

BoxVerdict examine(const Query& q, const Box& box, Real residual_error, Real tolerance) {
  const Residual r0 = residual_at(q, box.t0);
  const Residual r1 = residual_at(q, box.t1);
  // corner index: bit 0 = t, bit 1 = u, bit 2 = v.
  std::array<Vec3, 8> f;
  for (int c = 0; c < 8; ++c) {
    f[c] = residual(q.feature, (c & 1) ? r1 : r0, (c & 2) ? box.u1 : box.u0,
                    (c & 4) ? box.v1 : box.v0);
  }
  Vec3 lo = f[0];
  Vec3 hi = f[0];
  for (int c = 1; c < 8; ++c) {
    lo = lo.cwiseMin(f[c]);
    hi = hi.cwiseMax(f[c]);
  }
  for (int k = 0; k < 3; ++k) {
    if (lo[k] > residual_error || hi[k] < -residual_error)
      return BoxVerdict::excluded;
  }
  std::array<Vec3, 4> directions;
  const int count = separating_directions(q.feature, r0, r1, directions);
  for (int i = 0; i < count; ++i) {
    if (separated_along(directions[i], f, residual_error))
      return BoxVerdict::excluded;
  }
  if ((hi - lo).maxCoeff() <= tolerance)
    return BoxVerdict::contact;
  // How much each parameter spreads F: the largest change between corners differing in it.
  std::array<Real, 3> spread{};
  for (int c = 0; c < 8; ++c) {
    for (int d = 0; d < 3; ++d) {
      if (!(c & (1 << d)))
        spread[d] = std::max(spread[d], (f[c | (1 << d)] - f[c]).cwiseAbs().maxCoeff());
    }
  }
  const std::array<Real, 3> width = {box.t1 - box.t0, box.u1 - box.u0, box.v1 - box.v0};
  int best = -1;
  for (int d = 0; d < 3; ++d) {
    if (width[d] > kMinParameterWidth && (best < 0 || spread[d] > spread[best]))
      best = d;
  }
  if (best < 0)
    return BoxVerdict::contact;  // cannot split further: conservatively a contact
  return best == 0 ? BoxVerdict::split_t : best == 1 ? BoxVerdict::split_u : BoxVerdict::split_v;
}

// Splits `box` in half along the parameter `verdict` names; `first` gets the lower half.
void split(const Box& box, BoxVerdict verdict, Box& first, Box& second) {
  first = box;
  second = box;
  first.depth = second.depth = box.depth + 1;
  if (verdict == BoxVerdict::split_t) {
    first.t1 = second.t0 = Real(0.5) * (box.t0 + box.t1);
  } else if (verdict == BoxVerdict::split_u) {
    first.u1 = second.u0 = Real(0.5) * (box.u0 + box.u1);
  } else {
    first.v1 = second.v0 = Real(0.5) * (box.v0 + box.v1);
  }
}

// The open boxes of stage 2, earliest start first and, among equal starts, the deepest (the
// smallest) first: a binary heap in a fixed array, so that no query allocates.
class BoxQueue {
 public:
  bool empty() const { return size_ == 0; }
  bool full() const { return size_ == kQueueSize; }
  void clear() { size_ = 0; }
  void push(const Box& box) {
    boxes_[size_++] = box;
    std::push_heap(boxes_.begin(), boxes_.begin() + size_, Later{});
  }
  Box pop() {
    std::pop_heap(boxes_.begin(), boxes_.begin() + size_, Later{});
    return boxes_[--size_];
  }
  // Drops every box that starts at or after a cut time, chosen so that about the latest
  // quarter goes, and returns it; returns `floor` (dropping nothing) if no box starts later.
  Real cut(Real floor) {
    std::array<Real, kQueueSize> starts;
    for (int i = 0; i < size_; ++i)
      starts[i] = boxes_[i].t0;
    const int k = size_ - std::max(1, size_ / 4);  // in [0, size_): a quarter, at least one
    std::nth_element(starts.begin(), starts.begin() + k, starts.begin() + size_);
    Real time = starts[k];
    if (time <= floor)
      time = *std::max_element(starts.begin(), starts.begin() + size_);
    if (time <= floor)
      return floor;
    size_ = static_cast<int>(std::remove_if(boxes_.begin(), boxes_.begin() + size_,
                                            [time](const Box& b) { return b.t0 >= time; }) -
                             boxes_.begin());
    std::make_heap(boxes_.begin(), boxes_.begin() + size_, Later{});
    return time;
  }

 private:
  struct Later {  // a function object, so that the heap's comparisons are inlined
    bool operator()(const Box& a, const Box& b) const {
      return a.t0 != b.t0 ? a.t0 > b.t0 : a.depth < b.depth;
    }
  };
  std::array<Box, kQueueSize> boxes_;
  int size_ = 0;
};

// The search state of one time interval: the earliest contact box found so far (a contact found
// depth-first need not be the earliest), and the boxes still allowed.
struct Search {
  const Query& q;
  Real tolerance;
  Real residual_error;
  std::int32_t& boxes_left;
  MeshCcdResult& result;
  bool found = false;
  Real best = 1;
};

// Depth-first search of `start` (with a bounded stack), for when the queue is full. Returns
// false if it ran out of boxes.
bool depth_first(Search& s, const Box& start) {
  std::array<Box, kStackSize> stack;
  int top = 0;
  stack[top++] = start;
  while (top > 0) {
    const Box box = stack[--top];
    if (s.found && box.t0 >= s.best)
      continue;
    if (s.boxes_left == 0)
      return false;
    --s.boxes_left;
    ++s.result.boxes;
    const BoxVerdict verdict = examine(s.q, box, s.residual_error, s.tolerance);
    if (verdict == BoxVerdict::contact) {
      s.best = s.found ? std::min(s.best, box.t0) : box.t0;
      s.found = true;
    } else if (verdict != BoxVerdict::excluded) {
      split(box, verdict, stack[top + 1], stack[top]);  // the lower half on top
      top += 2;
    }
  }
  return true;
}

// Stage 2 on one time interval. Returns true with `result` set (a contact, or the search ran out
// of boxes: a contact at the earliest open time). `boxes_left` counts down.
//
// The boxes are taken earliest start first, so the first contact box taken is the earliest
// one (every open box starts no earlier) and the search stops there. Depth first, a vertex that
// slides along an edge within rounding of it (erleben-cube-cliff-edges/vertex-face) met a
// contact box late in the step and walked back towards the first contact one box at a time:
// 3,100 boxes for one query with barycentric parameters, 38,000 with the collapsed square.
// Only the later half of a split in t goes into the queue: the lower half of any split is taken
// next, and the upper half of a split in u or v, which starts as early, goes on a stack that is
// emptied before the queue is touched (a heap operation per box cost more than the box).
// When the queue is full, its latest-starting boxes are dropped and the time they start from
// is kept (`resume`): if nothing before it holds a contact, the search starts again there with
// the whole (u, v) square. If every open box starts together, the later half is searched depth
// first instead. Both are as sound as the queue, only slower.
bool search_interval(const Query& q, const TimeInterval& interval, Real tolerance,
                     Real residual_error, std::int32_t& boxes_left, MeshCcdResult& result) {
  Search s{q, tolerance, residual_error, boxes_left, result};
  BoxQueue queue;                     // boxes that start later than `box`, or as late
  std::array<Box, kStackSize> stack;  // boxes that start with `box`
  int top = 0;
  Real resume = interval.end;  // boxes starting at or after this were dropped
  Box box{interval.begin, interval.end, 0, 1, 0, 1, 0};
  for (;;) {
    // Here `box` starts no later than any open box (stacked, queued or from `resume` on).
    bool capped = false;
    if (s.found && box.t0 >= s.best) {
      top = 0;  // every open box starts later than a contact found depth first
      queue.clear();
    } else if (s.boxes_left == 0) {
      capped = true;
    } else {
      --s.boxes_left;
      ++result.boxes;
      const BoxVerdict verdict = examine(q, box, residual_error, tolerance);
      if (verdict == BoxVerdict::contact) {
        result.status = MeshCcdStatus::hit;
        result.time_of_impact = box.t0;  // <= s.best: checked above
        return true;
      }
      if (verdict != BoxVerdict::excluded) {
        Box first, second;
        split(box, verdict, first, second);
        if (verdict != BoxVerdict::split_t) {
          stack[top++] = second;  // at most 100 splits in u and v on a path
        } else {
          if (second.t0 < resume && queue.full()) {
            const Real cut = queue.cut(box.t0);
            if (cut > box.t0)  // else nothing was dropped
              resume = std::min(resume, cut);
          }
          if (second.t0 < resume) {
            if (!queue.full())
              queue.push(second);
            else
              capped = !depth_first(s, second);
          }
        }
        if (!capped) {
          box = first;
          continue;
        }
      }
    }
    if (capped) {
      result.status = MeshCcdStatus::max_iterations;
      result.time_of_impact = s.found ? std::min(s.best, box.t0) : box.t0;
      return true;
    }
    if (top > 0) {
      box = stack[--top];
      continue;
    }
    if (queue.empty()) {
      if (resume >= interval.end || (s.found && s.best <= resume))
        break;
      queue.push({resume, interval.end, 0, 1, 0, 1, 0});
      resume = interval.end;
    }
    box = queue.pop();
  }
  if (s.found) {
    result.status = MeshCcdStatus::hit;
    result.time_of_impact = s.best;
  }
  return s.found;
}

MeshCcdResult feature_ccd(Feature feature, const std::array<Vec3, 4>& start,
                          const std::array<Vec3, 4>& end, const MeshCcdSettings& settings) {
  MeshCcdResult result;
  Query q{feature, start, end, 0};
  for (int i = 0; i < 4; ++i) {
    if (!start[i].allFinite() || !end[i].allFinite()) {
      result.status = MeshCcdStatus::invalid_input;
      result.time_of_impact = 0;
      return result;
    }
    q.magnitude =
        std::max({q.magnitude, start[i].cwiseAbs().maxCoeff(), end[i].cwiseAbs().maxCoeff()});
  }
  // A residual at a corner, o - u e - w g: interpolated coordinates (error 3 u M), their
  // differences (below 2M, error 8 u M), products with u and w = (1 - u) v or v in [0, 1] (the
  // product (1 - u) v rounded too) and two sums: below 40 u M in all. Take ten times that,
  // plus the smallest normal number so that underflow cannot hide a contact.
  const Real residual_error = 512 * kUnitRoundoff * q.magnitude + std::numeric_limits<Real>::min();
  const Real tolerance = settings.tolerance > 0 ? settings.tolerance : MeshCcdSettings{}.tolerance;

  std::array<TimeInterval, kMaxTimeIntervals> intervals;
  const int count = coplanarity_intervals(q, intervals);
  std::int32_t boxes_left = std::max<std::int32_t>(1, settings.max_boxes);
  for (int i = 0; i < count; ++i) {
    if (search_interval(q, intervals[i], tolerance, residual_error, boxes_left, result))
      return result;
  }
  return result;
}

}  // namespace

MeshCcdResult vertex_face_ccd(const std::array<Vec3, 4>& start, const std::array<Vec3, 4>& end,
                              const MeshCcdSettings& settings) {
  return feature_ccd(Feature::vertex_face, start, end, settings);
}

MeshCcdResult edge_edge_ccd(const std::array<Vec3, 4>& start, const std::array<Vec3, 4>& end,
                            const MeshCcdSettings& settings) {
  return feature_ccd(Feature::edge_edge, start, end, settings);
}

std::string_view mesh_ccd_status_name(MeshCcdStatus status) {
  switch (status) {
    case MeshCcdStatus::separated:
      return "separated";
    case MeshCcdStatus::hit:
      return "hit";
    case MeshCcdStatus::max_iterations:
      return "max_iterations";
    case MeshCcdStatus::invalid_input:
      return "invalid_input";
  }
  return "unknown";
}

}  // namespace tumble
