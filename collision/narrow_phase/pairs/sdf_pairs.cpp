// Contacts with a solid given by its signed distance field (collision/shapes/sdf_shape.hpp).
//
// Everything runs in the SDF's frame (B), with two kinds of candidate points:
//  1. Points of the other shape (A) evaluated in B's field: a sphere's centre and points along a
//     capsule's core (direct evaluation: the contact is phi - radius deep along grad phi), and
//     the corners and edges of a box, cylinder or hull (at about B's surface-point spacing) and
//     points over a mesh triangle.
//  2. B's surface points (SdfShape::surface_point) that lie inside A's bounding box, evaluated in
//     A's own signed distance; for an SDF against an SDF, each one's points in the other's field.
//     Such a point lies a fraction of a cell from the true deepest point, so the deepest of them
//     are refined: a Newton walk along the surface to where the partner's distance is least
//     (the surface normal turns to face the partner's gradient), at most kRefineSteps steps; then
//     the depth is the partner's distance there. This is the descent on phi_A + phi_B of
//     Macklin et al., "Local Optimization for Robust Signed Distance Field Collision" (SIGGRAPH
//     2020), restricted to the surface it starts on.
// The candidates are merged into one manifold of at most four points by the contact collector
// (points within 60 degrees of the deepest's normal, measured along a depth-weighted mean of the
// normals of the candidates whose kind says theirs is the better guess; contact_collector.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "collision/narrow_phase/pairs/contact_collector.hpp"
#include "collision/narrow_phase/pairs/field_separation.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"
#include "collision/sdf/sdf_primitives.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/shape_ops.hpp"
#include "collision/shapes/triangle_mesh.hpp"

namespace tumble::detail {
namespace {

constexpr std::uint16_t kSdfSurface = 0xfffe;
constexpr int kRefineSteps = 16;
constexpr Real kConvergedTurn = Real(1e-6);  // rad, between the surface's and partner's normals
constexpr std::size_t kRegions = 64;         // 2^6: the hash below keeps 6 bits
constexpr int kMaxSamplesPerSide = 8;
constexpr Real kPi = Real(3.14159265358979323846);

// The signed distance of shape A, placed at `pose` in B's frame, at a point of B's frame, with
// its gradient in B's frame (when asked: `gradient`). Exact for the primitives and for a hull
// inside it (the farthest face plane; outside, that plane's distance is a lower bound); any other
// shape by its table distance and a central-difference gradient, asked only when refining.
sdf::Sample partner_sample(const Shape& a, const Transform& pose, const Vec3& x, bool gradient) {
  const Vec3 p = pose.apply_inverse(x);
  sdf::Sample s;
  switch (a.type) {
    case ShapeType::sphere:
      s = sdf::sphere(p, a.radius);
      break;
    case ShapeType::box:
      s = sdf::box(p, a.half_extents);
      break;
    case ShapeType::capsule:
      s = sdf::capsule(p, a.radius, a.half_length);
      break;
    case ShapeType::cylinder:
      s = sdf::cylinder(p, a.radius, a.half_length);
      break;
    case ShapeType::plane:
      s = {p.z(), Vec3::UnitZ()};
      break;
    case ShapeType::sdf:
      s = a.sdf->sample(p, a.field_time);
      break;
    case ShapeType::hull: {
      // The farthest face plane and its normal: the exact distance and gradient inside, where
      // contacts are; outside (a point within the margin) a lower bound of the distance, so a
      // speculative contact near an edge starts a hair early, never late.
      s.distance = -std::numeric_limits<Real>::infinity();
      for (const HullFace& f : a.hull->faces()) {
        const Real d = f.normal.dot(p) - f.offset;
        if (d > s.distance) {
          s.distance = d;
          s.gradient = f.normal;
        }
      }
      break;
    }
    default: {
      const auto distance = shape_ops(a.type).signed_distance;
      s.distance = distance(a, p);
      if (!gradient)
        return s;
      const Real h = bounding_radius(a) * Real(1e-6);
      for (int k = 0; k < 3; ++k) {
        Vec3 e = Vec3::Zero();
        e[k] = h;
        s.gradient[k] = (distance(a, p + e) - distance(a, p - e)) / (2 * h);
      }
      break;
    }
  }
  s.gradient = pose.rotate(s.gradient);
  return s;
}

// A surface and its field, in B's frame: B itself, or (for an SDF against an SDF) A placed there.
struct Surface {
  const SdfShape* field;
  Transform pose;  // the field's frame in B's frame
  Real time = 0;   // for a field that changes with time
  sdf::Sample sample(const Vec3& x) const {
    sdf::Sample s = field->sample(pose.apply_inverse(x), time);
    s.gradient = pose.rotate(s.gradient);
    return s;
  }
  // As a partner (surface_points_against): the distance alone when no gradient is asked for
  // (the gradient is then left at its default, and read by no one).
  sdf::Sample sample(const Vec3& x, bool gradient) const {
    if (gradient)
      return sample(x);
    sdf::Sample s;
    s.distance = field->distance(pose.apply_inverse(x), time);
    return s;
  }
};

// A secant walk on the surface: from x on it, toward the point where the partner's distance is
// least, i.e. where the surface's outward normal n is opposite the partner's gradient m. The
// tangential part of m, t = m - (m.n) n, has length sin(delta), delta the angle still to turn;
// a step of alpha t along -t, then back onto the surface, turns delta at a rate of about the
// sum of the two surfaces' curvatures, measured over the last step, so alpha = moved / (how
// much delta fell) lands near the optimum (Newton's step on delta, with a secant slope). A step
// that does not lower the partner's distance is halved.
// `capped` is set when the walk used all its kRefineSteps steps with the normals still more than
// kConvergedTurn apart: it stopped short of the optimum. (It goes on to 1e-12 when it can; at
// 1e-6 rad the depth is within R 1e-12 / 2 of the optimum's, R the radius of curvature. A
// stalled walk, whose halved steps lower nothing, is at the optimum to rounding.)
template <class Partner>
Vec3 refine_on_surface(const Surface& surface, const Partner& partner, Vec3 x, Real cell,
                       bool& capped) {
  const auto project = [&](Vec3 p, sdf::Sample& s) {
    for (int k = 0; k < 3; ++k) {
      s = surface.sample(p);
      const Real g2 = s.gradient.squaredNorm();
      if (!(g2 > 0))
        break;
      p -= (s.distance / g2) * s.gradient;
    }
    s = surface.sample(p);
    return p;
  };
  const auto misalignment = [](const sdf::Sample& own, const sdf::Sample& other, Vec3& t) {
    const Vec3 n = normalized_or(own.gradient, Vec3::UnitZ());
    const Vec3 m = normalized_or(other.gradient, Vec3::UnitZ());
    t = m - m.dot(n) * n;
    return std::atan2(t.norm(), -m.dot(n));  // 0 when m = -n
  };
  sdf::Sample here;
  x = project(x, here);
  sdf::Sample other = partner(x, true);
  Vec3 t;
  Real delta = misalignment(here, other, t);
  Real alpha = cell;
  capped = false;
  for (int i = 0; delta > Real(1e-12); ++i) {
    if (i == kRefineSteps) {
      capped = delta > kConvergedTurn;
      break;
    }
    sdf::Sample next_here;
    const Vec3 next = project(x - alpha * t, next_here);
    const sdf::Sample next_other = partner(next, true);
    if (!(next_other.distance < other.distance)) {
      alpha /= 2;
      if (alpha < cell * Real(1e-6))
        break;
      continue;
    }
    Vec3 next_t;
    const Real next_delta = misalignment(next_here, next_other, next_t);
    const Real moved = (next - x).norm();
    x = next;
    here = next_here;
    other = next_other;
    t = next_t;
    alpha = delta - next_delta > moved * Real(1e-9) ? moved / (delta - next_delta) : 2 * alpha;
    alpha = std::min(alpha, 1e3 * cell);
    delta = next_delta;
  }
  return x;
}

// Points spread over the surface of a box, cylinder or hull (A's frame), at about `spacing`.
template <class F>
void for_each_surface_sample(const Shape& a, Real spacing, F&& f) {
  const auto divisions = [&](Real length) {
    return std::clamp(int(std::ceil(length / spacing)), 1, kMaxSamplesPerSide);
  };
  std::uint16_t id = 0;
  switch (a.type) {
    case ShapeType::box: {
      // Corners and points along the edges; a face's inside meets the field only where the field
      // bulges into it, which the field's own points (kind 2) find.
      const Vec3& h = a.half_extents;
      for (int c = 0; c < 8; ++c)
        f(Vec3((c & 1 ? 1 : -1) * h.x(), (c & 2 ? 1 : -1) * h.y(), (c & 4 ? 1 : -1) * h.z()), id++);
      for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const int n = divisions(2 * h[axis]);
        for (int c = 0; c < 4; ++c)
          for (int i = 1; i < n; ++i) {
            Vec3 p;
            p[axis] = -h[axis] + 2 * h[axis] * Real(i) / Real(n);
            p[u] = (c & 1 ? 1 : -1) * h[u];
            p[v] = (c & 2 ? 1 : -1) * h[v];
            f(p, id++);
          }
      }
      return;
    }
    case ShapeType::cylinder: {
      // The two rims and the caps' centres (the side's and the caps' insides are the field's
      // points' to find, as for a box's faces).
      const int around = std::clamp(int(std::ceil(2 * kPi * a.radius / spacing)), 8, 64);
      for (int k = 0; k < around; ++k) {
        const Real angle = 2 * kPi * Real(k) / Real(around);
        const Vec3 rim(a.radius * std::cos(angle), a.radius * std::sin(angle), 0);
        f(Vec3(rim + Vec3(0, 0, -a.half_length)), id++);
        f(Vec3(rim + Vec3(0, 0, a.half_length)), id++);
      }
      f(Vec3(0, 0, -a.half_length), id++);
      f(Vec3(0, 0, a.half_length), id++);
      return;
    }
    case ShapeType::hull: {
      const ConvexHull& hull = *a.hull;
      for (const Vec3& v : hull.vertices())
        f(v, id++);
      for (const HullEdge& e : hull.edges()) {
        const Vec3 p = hull.vertex(e.vertex[0]), q = hull.vertex(e.vertex[1]);
        const int n = divisions((q - p).norm());
        for (int i = 1; i < n; ++i)
          f(Vec3(p + (q - p) * (Real(i) / Real(n))), id++);
      }
      for (const HullFace& face : hull.faces()) {
        Vec3 c = Vec3::Zero();
        for (int i = 0; i < face.count; ++i)
          c += hull.vertex(hull.face_vertices()[std::size_t(face.first_index + i)]);
        f(Vec3(c / Real(face.count)), id++);
      }
      return;
    }
    default:
      return;
  }
}

// The candidates of kind 2: B's surface points inside `box` (B's frame) that the partner's
// distance puts within the margin. The deepest point of each region (cubes of a quarter of B's
// bounding radius, hashed into kRegions slots) is refined, so that a resting ring or face gives
// points all around it, not only where it is a hair deeper.
// How many walks surface_points_against ran, and how many stopped at the step cap.
struct RefineCounts {
  int refined = 0;
  int capped = 0;
  Real deepest = -std::numeric_limits<Real>::infinity();
  bool deepest_capped = false;
  void into(Manifold& m) const {
    m.refined = std::uint16_t(std::min(refined, 0xffff));
    m.refine_capped = std::uint16_t(std::min(capped, 0xffff));
    m.deepest_walk_capped = deepest_capped;
  }
};

// The raw pass of kind 2: for each region (cubes of a quarter of B's bounding radius, hashed into
// kRegions slots), the surface point inside `box` (B's frame) whose partner distance is least
// and below the margin.
struct RawCandidate {
  std::int64_t region = -1;
  int index = 0;
  Real distance = 0;
};
using RegionCandidates = std::array<RawCandidate, kRegions>;

template <class Partner>
void deepest_per_region(const Surface& surface, const Aabb& box, const Partner& partner,
                        Real margin, RegionCandidates& deepest) {
  deepest.fill(RawCandidate{});
  const SdfShape& field = *surface.field;
  const Aabb local = box.placed(surface.pose.inverse());  // in the field's frame, for the buckets
  const Real region_size = field.bounding_radius() / 4;
  const Vec3& origin = field.local_bounds().min;
  // Buckets of points farther from the partner than their ball's radius plus the margin are
  // skipped whole: every field here is 1-Lipschitz (distances, their CSG bounds, interpolated
  // grids to their interpolation error, which the margin covers).
  // A field that changes with time: its stored points are where it starts or ends, up to
  // surface_motion() from its surface now; each is projected onto that surface first.
  const Real motion = field.surface_motion();
  const auto near = [&](const Vec3& centre, Real radius) {
    return partner(surface.pose.apply(centre), false).distance < radius + motion + margin;
  };
  const auto on_surface_now = [&](Vec3 p) {
    for (int k = 0; k < 3; ++k) {
      const sdf::Sample s = field.sample(p, surface.time);
      const Real g2 = s.gradient.squaredNorm();
      if (!(g2 > 0))
        break;
      p -= (s.distance / g2) * s.gradient;
    }
    return p;
  };
  const bool moving = field.changes_with_time();
  field.for_each_surface_point_in(local, near, [&](int i) {
    const Vec3 own = moving ? on_surface_now(field.surface_point(i)) : field.surface_point(i);
    const Real d = partner(surface.pose.apply(own), false).distance;
    if (!(d < margin))
      return;
    const Vec3 cell = ((own - origin) / region_size).array().floor();
    const std::int64_t region =
        std::int64_t(cell.x()) + 64 * (std::int64_t(cell.y()) + 64 * std::int64_t(cell.z()));
    // Fibonacci hashing: the top bits of the product mix all three coordinates.
    const std::uint64_t mixed = std::uint64_t(region) * 0x9E3779B97F4A7C15ULL;
    RawCandidate& slot = deepest[std::size_t(mixed >> 58)];
    if (slot.region < 0 || d < slot.distance)
      slot = {region, i, d};
  });
}

template <class Partner, class Emit>
void surface_points_against(const Surface& surface, const Aabb& box, const Partner& partner,
                            Real margin, RefineCounts& counts, Emit&& emit) {
  RegionCandidates deepest;
  deepest_per_region(surface, box, partner, margin, deepest);
  const SdfShape& field = *surface.field;
  for (const RawCandidate& raw : deepest) {
    if (raw.region < 0)
      continue;
    const Vec3 start = surface.pose.apply(field.surface_point(raw.index));
    bool capped = false;
    const Vec3 x = refine_on_surface(surface, partner, start, field.cell_size(), capped);
    ++counts.refined;
    counts.capped += capped ? 1 : 0;
    const sdf::Sample own = surface.sample(x);
    const sdf::Sample other = partner(x, true);
    if (!(other.distance < margin))
      continue;
    if (-other.distance > counts.deepest) {
      counts.deepest = -other.distance;
      counts.deepest_capped = capped;
    }
    // The partner is pushed off the surface point the shortest way out of it: against its own
    // gradient there (at the optimum also the surface's normal, but a flat partner's gradient
    // is exact where the curved surface's normal still carries the walk's last error).
    emit(x, normalized_or(Vec3(-other.gradient), own.gradient), other,
         std::uint16_t(raw.index & 0xffff));
  }
}

// The least partner distance surface_points_against would report (below the margin; the margin
// when none is), refining only a few of the regions instead of every one: in order of their raw
// points, at most kLeastRefined, and only while a raw point lies within kLeastReach cells of the
// least refined so far (the deepest point of the surface lies within about a cell and a half of
// one of its points, which then lies at most that much higher: the partner's distance is
// 1-Lipschitz). A region left out may refine deeper still (a walk gains what the surface's
// curvature allows over a few cells); conservative advancement asks the whole narrow phase where
// it stops (collision/ccd/shape_distance.cpp). tests/collision/field_least_separation_test.cpp
// measures both against the narrow phase.
constexpr int kLeastRefined = 4;
constexpr Real kLeastReach = 2;

// The least separation and its candidate's normal (from the partner's side to the surface's,
// the way surface_points_against pushes the partner off), in the surface's frame (B's).
template <class Partner>
FieldSeparation least_surface_distance(const Surface& surface, const Aabb& box,
                                       const Partner& partner, Real margin) {
  RegionCandidates deepest;
  deepest_per_region(surface, box, partner, margin, deepest);
  // The deepest raw points first; ties by point index, so the order does not depend on the hash.
  const auto end = std::partition(deepest.begin(), deepest.end(),
                                  [](const RawCandidate& r) { return r.region >= 0; });
  std::sort(deepest.begin(), end, [](const RawCandidate& p, const RawCandidate& q) {
    return p.distance < q.distance || (p.distance == q.distance && p.index < q.index);
  });
  FieldSeparation least{margin, Vec3::UnitZ()};
  const SdfShape& field = *surface.field;
  const Real reach = kLeastReach * field.cell_size();
  const auto last =
      deepest.begin() + std::min<std::ptrdiff_t>(kLeastRefined, end - deepest.begin());
  for (auto raw = deepest.begin(); raw != last && raw->distance < least.distance + reach; ++raw) {
    const Vec3 start = surface.pose.apply(field.surface_point(raw->index));
    bool capped = false;
    const Vec3 x = refine_on_surface(surface, partner, start, field.cell_size(), capped);
    const sdf::Sample other = partner(x, true);
    if (other.distance < least.distance)
      least = {other.distance, normalized_or(Vec3(-other.gradient), surface.sample(x).gradient)};
  }
  return least;
}

// The field's second derivatives at x, by central differences of its gradient `step` apart,
// symmetrised. Where the field has a ridge between the samples (a kink of a CSG union or
// difference) the differences say so with a large value; the caller bounds it.
Mat3 field_hessian(const SdfShape& field, const Vec3& x, Real time, Real step) {
  Mat3 columns;
  for (int i = 0; i < 3; ++i) {
    const Vec3 offset = Vec3::Unit(i) * step;
    columns.col(i) =
        (field.sample(x + offset, time).gradient - field.sample(x - offset, time).gradient) /
        (2 * step);
  }
  return (columns + columns.transpose()) * Real(0.5);
}

// The points of a sphere's centre or a capsule's core at which a field is sampled: the centre, or
// the core at about a cell apart (2 to 17 points), each with its fraction along the core.
template <class F>
void for_each_core_point(const Shape& a, const Transform& pose_a, Real cell, F&& f) {
  const Vec3 axis = a.type == ShapeType::capsule ? pose_a.rotate(Vec3::UnitZ()) : Vec3::Zero();
  const int n = a.type == ShapeType::capsule
                    ? std::clamp(int(std::ceil(2 * a.half_length / cell)), 1, 16)
                    : 0;
  for (int i = 0; i <= n; ++i) {
    const Real along = n == 0 ? Real(0) : -a.half_length + 2 * a.half_length * Real(i) / Real(n);
    f(Vec3(pose_a.translation + along * axis), Real(i) / Real(std::max(n, 1)));
  }
}

// A (sphere, box, capsule, plane, cylinder, hull) against the SDF B, in B's frame.
int convex_against_sdf(const Shape& a, const Transform& pose_a, const SdfShape& field, Real time,
                       Real margin, Manifold& out) {
  ContactCollector collector;
  RefineCounts refine_counts;
  const Aabb b_box = field.local_bounds().inflated(margin);
  const Surface surface{&field, Transform{}, time};
  // A sphere's or capsule's core is `radius` from the surface when they touch: evaluated directly
  // where the field is a distance that far out, otherwise (a narrow-band level set thinner than
  // the radius) through B's surface points like any other shape.
  const bool round = a.type == ShapeType::sphere || a.type == ShapeType::capsule;
  const bool direct = round && a.radius + margin < field.reach();
  // Kind 1: A's points in B's field.
  Vec3 deepest_core = Vec3::Zero();
  Real deepest = -std::numeric_limits<Real>::infinity();
  if (direct) {
    for_each_core_point(a, pose_a, field.cell_size(), [&](const Vec3& c, Real fraction) {
      const sdf::Sample s = field.sample(c, time);
      const Real depth = a.radius - s.distance;
      if (!(depth >= -margin))
        return;
      if (depth > deepest) {
        deepest = depth;
        deepest_core = c;
      }
      const Vec3 normal = normalized_or(s.gradient, Vec3::UnitZ());
      collector.add(
          normal, c - normal * a.radius, depth,
          {a.type == ShapeType::capsule ? feature::capsule_feature_at(fraction) : feature::kSphere,
           kSdfSurface});
    });
  } else if (!round && a.type != ShapeType::plane) {
    for_each_surface_sample(a, field.cell_size(), [&](const Vec3& local, std::uint16_t id) {
      const Vec3 p = pose_a.apply(local);
      if (!b_box.contains(p))
        return;
      const sdf::Sample s = field.sample(p, time);
      if (!(-s.distance >= -margin))
        return;
      collector.add(normalized_or(s.gradient, Vec3::UnitZ()), p, -s.distance, {id, kSdfSurface}, 1);
    });
  }
  // Kind 2: B's surface points in A's distance (a sphere or capsule evaluated directly needs none:
  // kind 1 is exact).
  if (!direct) {
    const Aabb a_box =
        a.type == ShapeType::plane ? field.local_bounds() : world_aabb(a, pose_a).inflated(margin);
    const auto partner = [&](const Vec3& x, bool gradient) {
      return partner_sample(a, pose_a, x, gradient);
    };
    surface_points_against(
        surface, a_box, partner, margin, refine_counts,
        [&](const Vec3& x, const Vec3& n, const sdf::Sample& other, std::uint16_t id) {
          // A is pushed out along B's normal; its point is `depth` inside B.
          const Real depth = -other.distance;
          collector.add(n, x - n * depth, depth, {kSdfSurface, id});
        });
  }
  const int count =
      collector.finish(margin, ContactCollector::kMergeFraction * field.bounding_radius(), out,
                       ContactCollector::NormalRule::weighted_mean_of_deepest_kind);
  refine_counts.into(out);
  if (direct && count > 0) {
    // The core's separation is phi - radius, so it bends as phi does. Differences a quarter of
    // the radius (or of a cell) apart resolve any surface the ball fits in; a kink between
    // them reads as a curvature of up to 2 / step, which is bounded to the sharpest a surface
    // the core can follow may have (1 / step).
    const Real step = Real(0.25) * std::min(a.radius, field.cell_size());
    Mat3 h = field_hessian(field, deepest_core, time, step);
    const Real squared = h.squaredNorm();
    const Real limit = 1 / step;
    if (!(squared <= limit * limit))
      h *= std::isfinite(squared) ? limit / std::sqrt(squared) : Real(0);
    out.separation_curvature = packed_symmetric(h);
  }
  return count;
}

// convex_against_sdf's least separation (minus its deepest point's depth; the margin when it has
// none) and that candidate's normal, from the same candidates, with kind 2 refined as
// least_surface_distance says; in B's frame.
FieldSeparation least_convex_against_sdf(const Shape& a, const Transform& pose_a,
                                         const SdfShape& field, Real time, Real margin) {
  FieldSeparation least{margin, Vec3::UnitZ()};
  // A's point x in B's field, `radius` out from it (A is pushed along B's gradient).
  const auto consider = [&](const Vec3& x, Real radius) {
    const sdf::Sample s = field.sample(x, time);
    if (s.distance - radius < least.distance)
      least = {s.distance - radius, normalized_or(s.gradient, Vec3::UnitZ())};
  };
  const Aabb b_box = field.local_bounds().inflated(margin);
  const bool round = a.type == ShapeType::sphere || a.type == ShapeType::capsule;
  const bool direct = round && a.radius + margin < field.reach();
  if (direct) {
    for_each_core_point(a, pose_a, field.cell_size(),
                        [&](const Vec3& c, Real) { consider(c, a.radius); });
    return least;
  }
  if (!round && a.type != ShapeType::plane) {
    for_each_surface_sample(a, field.cell_size(), [&](const Vec3& local, std::uint16_t) {
      const Vec3 p = pose_a.apply(local);
      if (b_box.contains(p))
        consider(p, 0);
    });
  }
  const Aabb a_box =
      a.type == ShapeType::plane ? field.local_bounds() : world_aabb(a, pose_a).inflated(margin);
  const Surface surface{&field, Transform{}, time};
  const auto partner = [&](const Vec3& x, bool gradient) {
    return partner_sample(a, pose_a, x, gradient);
  };
  const FieldSeparation of_surface = least_surface_distance(surface, a_box, partner, margin);
  return of_surface.distance < least.distance ? of_surface : least;
}

// A static mesh against the SDF B, in B's frame: each triangle near B sampled in B's field, and
// B's surface points under each triangle measured from its plane.
int mesh_against_sdf(const Shape& a, const Transform& pose_a, const SdfShape& field, Real time,
                     Real margin, Manifold& out) {
  const TriangleMesh& mesh = *a.mesh;
  const Aabb b_box = field.local_bounds().inflated(margin);
  const Aabb query = b_box.placed(pose_a.inverse());  // B's box in the mesh's frame
  ContactCollector collector;
  RefineCounts refine_counts;
  const Surface surface{&field, Transform{}, time};
  const Real spacing = field.cell_size();
  mesh.for_each_overlapping(query, [&](int t) {
    const Vec3 v0 = pose_a.apply(mesh.corner(t, 0));
    const Vec3 v1 = pose_a.apply(mesh.corner(t, 1));
    const Vec3 v2 = pose_a.apply(mesh.corner(t, 2));
    const Vec3 normal = pose_a.rotate(mesh.normal(t));
    const std::uint16_t id = feature::mesh_feature(t, 0);
    // The triangle's points in B's field (a grid of barycentric points, capped).
    const int n = std::clamp(
        int(std::ceil(std::max({(v1 - v0).norm(), (v2 - v1).norm(), (v0 - v2).norm()}) / spacing)),
        1, 4 * kMaxSamplesPerSide);
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 p = v0 + (v1 - v0) * (Real(i) / Real(n)) + (v2 - v0) * (Real(j) / Real(n));
        if (!b_box.contains(p))
          continue;
        const sdf::Sample s = field.sample(p, time);
        // Its depth, but not its normal: grad phi at a floor point beside a ball's bottom leans
        // toward the ball's centre, and the field's points under the face (below) carry the
        // face's own normal.
        if (-s.distance >= -margin)
          collector.add(normalized_or(s.gradient, normal), p, -s.distance, {id, kSdfSurface}, 1);
      }
    // B's surface points below the triangle, inside its prism (the triangle's one-sided plane).
    Aabb prism;
    prism.grow(v0);
    prism.grow(v1);
    prism.grow(v2);
    const Real thickness = 2 * field.inner_radius() + margin;
    prism = prism.inflated(thickness);
    const auto inside_prism = [&](const Vec3& x) {
      const Vec3 e[3] = {v1 - v0, v2 - v1, v0 - v2};
      const Vec3 o[3] = {v0, v1, v2};
      for (int k = 0; k < 3; ++k)
        if (normal.cross(e[k]).dot(x - o[k]) < 0)
          return false;
      return true;
    };
    const auto partner = [&](const Vec3& x, bool) {
      sdf::Sample s;
      s.distance = normal.dot(x - v0);
      s.gradient = normal;
      return s;
    };
    surface_points_against(
        surface, prism, partner, margin, refine_counts,
        [&](const Vec3& x, const Vec3& nb, const sdf::Sample& other, std::uint16_t point) {
          if (!inside_prism(x) || other.distance < -thickness)
            return;
          const Real depth = -other.distance;
          collector.add(nb, x - nb * depth, depth, {std::uint16_t(id | 7), point});
        });
  });
  const int count =
      collector.finish(margin, ContactCollector::kMergeFraction * field.bounding_radius(), out,
                       ContactCollector::NormalRule::weighted_mean_of_kind_zero);
  refine_counts.into(out);
  return count;
}

}  // namespace

int any_sdf(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out) {
  // Into B's frame, and the answer back out.
  const Transform a_in_b = pose_b.relative(pose_a);
  const int count = a.type == ShapeType::mesh
                        ? mesh_against_sdf(a, a_in_b, *b.sdf, b.field_time, margin, out)
                        : convex_against_sdf(a, a_in_b, *b.sdf, b.field_time, margin, out);
  out.normal = pose_b.rotate(out.normal);
  for (int i = 0; i < count; ++i)
    out.points[i].position = pose_b.apply(out.points[i].position);
  const Mat3 turn = pose_b.rotation.toRotationMatrix();
  out.separation_curvature =
      packed_symmetric(turn * unpacked_symmetric(out.separation_curvature) * turn.transpose());
  return count;
}

int sdf_sdf(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out) {
  const Transform a_in_b = pose_b.relative(pose_a);
  const SdfShape& fa = *a.sdf;
  const SdfShape& fb = *b.sdf;
  const Surface surface_a{&fa, a_in_b, a.field_time};
  const Surface surface_b{&fb, Transform{}, b.field_time};
  // Where the two boxes overlap: only there can either surface be inside the other.
  const Aabb a_box = fa.local_bounds().placed(a_in_b);
  const Aabb b_box = fb.local_bounds();
  Aabb overlap{a_box.min.cwiseMax(b_box.min), a_box.max.cwiseMin(b_box.max)};
  overlap = overlap.inflated(margin);
  ContactCollector collector;
  RefineCounts refine_counts;
  // B's points in A's field: A is pushed along B's normal.
  surface_points_against(
      surface_b, overlap,
      [&](const Vec3& x, bool gradient) { return surface_a.sample(x, gradient); }, margin,
      refine_counts,
      [&](const Vec3& x, const Vec3& n, const sdf::Sample& other, std::uint16_t id) {
        const Real depth = -other.distance;
        collector.add(n, x - n * depth, depth, {kSdfSurface, id});
      });
  // A's points in B's field: the point lies on A, pushed along B's gradient.
  surface_points_against(
      surface_a, overlap,
      [&](const Vec3& x, bool gradient) { return surface_b.sample(x, gradient); }, margin,
      refine_counts,
      [&](const Vec3& x, const Vec3&, const sdf::Sample& other, std::uint16_t id) {
        collector.add(normalized_or(other.gradient, Vec3::UnitZ()), x, -other.distance,
                      {id, kSdfSurface});
      });
  const int count = collector.finish(
      margin,
      ContactCollector::kMergeFraction * std::min(fa.bounding_radius(), fb.bounding_radius()), out,
      ContactCollector::NormalRule::weighted_mean);
  refine_counts.into(out);
  out.normal = pose_b.rotate(out.normal);
  for (int i = 0; i < count; ++i)
    out.points[i].position = pose_b.apply(out.points[i].position);
  return count;
}

}  // namespace tumble::detail

namespace tumble {

FieldSeparation field_least_separation(const Shape& a, const Transform& pose_a, const Shape& b,
                                       const Transform& pose_b, Real margin) {
  using namespace detail;
  if (a.type == ShapeType::sdf && b.type != ShapeType::sdf) {
    FieldSeparation flipped = field_least_separation(b, pose_b, a, pose_a, margin);
    flipped.normal = -flipped.normal;
    return flipped;
  }
  const Transform a_in_b = pose_b.relative(pose_a);
  FieldSeparation least;
  if (a.type != ShapeType::sdf) {
    least = least_convex_against_sdf(a, a_in_b, *b.sdf, b.field_time, margin);
  } else {
    // Two fields: sdf_sdf's candidates, both ways.
    const Surface surface_a{a.sdf.get(), a_in_b, a.field_time};
    const Surface surface_b{b.sdf.get(), Transform{}, b.field_time};
    const Aabb a_box = a.sdf->local_bounds().placed(a_in_b);
    const Aabb b_box = b.sdf->local_bounds();
    const Aabb overlap =
        Aabb{a_box.min.cwiseMax(b_box.min), a_box.max.cwiseMin(b_box.max)}.inflated(margin);
    // B's points in A's field (A pushed along B's normal), then A's points in B's field (A pushed
    // along B's gradient there, the opposite of A's surface normal that the walk turns to).
    least = least_surface_distance(
        surface_b, overlap,
        [&](const Vec3& x, bool gradient) { return surface_a.sample(x, gradient); }, margin);
    FieldSeparation of_a = least_surface_distance(
        surface_a, overlap,
        [&](const Vec3& x, bool gradient) { return surface_b.sample(x, gradient); }, margin);
    of_a.normal = -of_a.normal;
    if (of_a.distance < least.distance)
      least = of_a;
  }
  least.normal = pose_b.rotate(least.normal);
  return least;
}
}  // namespace tumble
