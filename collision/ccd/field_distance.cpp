// plane_and_field and field_and_field (collision/ccd/field_distance.hpp). Both find the least of a
// function of a point by projected gradient descent (collision/ccd/projected_descent.hpp; Rosen,
// "The gradient projection method for nonlinear programming", J. SIAM 8, 1960) over the plane's
// half-space, or all of space for two fields, from a few seeds, the lowest result kept. The
// derivatives with respect to the poses follow from the envelope theorem: at the optimum the
// point's own motion changes the value only to second order, so the distance changes as the fields
// move past a fixed point (docs/sdf.md, "Gradients").
#include "collision/ccd/field_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "collision/ccd/projected_descent.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

// Surface points a field offers as seeds: at most this many, spread by a fixed stride.
constexpr int kSeedCandidates = 128;
constexpr int kSeeds = 3;
// Steps per descent. 2,000 (the solids' cap) left 12 of 10,000 plane-torus configurations less
// than 4 mm from the core ridge, where phi is nearly a cone and the descent zigzags, with
// gradients 0.4% off; the cap is reached only there.
constexpr int kMaxDescentSteps = 20000;

// Keeps the kSeeds lowest (value, point) pairs, lowest first; a point met again is not a new seed.
struct SeedList {
  std::array<std::pair<Real, Vec3>, kSeeds> seeds;
  SeedList() { seeds.fill({std::numeric_limits<Real>::infinity(), Vec3::Zero()}); }
  void offer(Real value, const Vec3& point) {
    if (!std::isfinite(value))
      return;
    for (const auto& seed : seeds)
      if (seed.second == point && std::isfinite(seed.first))
        return;
    std::pair<Real, Vec3> carried{value, point};
    for (auto& seed : seeds)
      if (carried.first < seed.first)
        std::swap(seed, carried);
  }
};

// Calls f(world point) for up to kSeedCandidates of the field's surface points.
template <class F>
void for_each_seed_candidate(const SdfShape& field, const Transform& pose, const F& f) {
  const int count = field.surface_point_count();
  const int stride = std::max(1, (count + kSeedCandidates - 1) / kSeedCandidates);
  for (int i = 0; i < count; i += stride)
    f(pose.apply(field.surface_point(i)));
}

sdf::Sample world_sample(const SdfShape& field, Real time, const Transform& pose, const Vec3& x) {
  sdf::Sample s = field.sample(pose.apply_inverse(x), time);
  s.gradient = pose.rotate(s.gradient);
  return s;
}

void check_within_reach(const SdfShape& field, Real value, const char* which) {
  if (!(std::abs(value) < field.reach()))
    throw Error(std::string("distance_between: the nearest point is beyond ") + which +
                "'s narrow band (values are distances only within " +
                std::to_string(field.reach()) +
                " m of its surface); widen the level set's band (docs/sdf.md)");
}

// Descends from each seed of `seeds`, and keeps in `best` and `core` the lowest end met so far,
// and in `capped` whether that end's descent stopped at its step cap.
template <class Objective, class Project>
void descend_from(const SeedList& seeds, Real size, const Objective& objective,
                  const Project& project, Real& best, Vec3& core, bool& capped) {
  for (const auto& [value, start] : seeds.seeds) {
    if (!std::isfinite(value))
      continue;
    bool stopped = false;
    const auto [x, reached] =
        projected_descent(start, size, kMaxDescentSteps, objective, project, &stopped);
    if (reached.distance < best) {
      best = reached.distance;
      core = x;
      capped = stopped;
    }
  }
}

Vec3 unit_or(const Vec3& v, const Vec3& fallback) {
  const Real n = v.norm();
  return n > 0 ? Vec3(v / n) : fallback;
}

}  // namespace

ShapeDistance plane_and_field(const Transform& plane_pose, const SdfShape& field, Real time,
                              const Transform& field_pose) {
  const Vec3 up = plane_pose.rotate(Vec3::UnitZ());
  const Vec3& origin = plane_pose.translation;
  const auto project = [&](const Vec3& x) {
    const Real height = (x - origin).dot(up);
    return height > 0 ? Vec3(x - height * up) : x;
  };
  const auto objective = [&](const Vec3& x) { return world_sample(field, time, field_pose, x); };
  // Seeds: the field's surface points lowest along the plane's normal, moved onto its solid.
  SeedList seeds;
  for_each_seed_candidate(field, field_pose,
                          [&](const Vec3& p) { seeds.offer((p - origin).dot(up), project(p)); });
  const Real size = field.bounding_radius();
  Real best = std::numeric_limits<Real>::infinity();
  Vec3 core = origin;
  bool capped = false;
  descend_from(seeds, size, objective, project, best, core, capped);
  const sdf::Sample s = world_sample(field, time, field_pose, core);
  check_within_reach(field, s.distance, "the field");
  ShapeDistance d;
  d.converged = !capped;
  d.normal = unit_or(s.gradient, -up);  // from B (the field) to A (the plane): along grad phi_B
  d.distance = s.distance;
  d.point_a = core;
  d.point_b = core - s.distance * d.normal;
  // The point fixed in the plane: moving the plane by v moves it by v (d/dx_A = grad phi), and
  // the field moving by v lowers phi there (d/dx_B = -grad phi); turns likewise about each origin.
  d.gradient_a.head<3>() = s.gradient;
  d.gradient_a.tail<3>() = (core - plane_pose.translation).cross(s.gradient);
  d.gradient_b.head<3>() = -s.gradient;
  d.gradient_b.tail<3>() = -(core - field_pose.translation).cross(s.gradient);
  // The deepest point a minimum of phi itself (the field's deepest point inside the half-space,
  // or a ridge of it held on the plane): the distance does not change as the poses move a little
  // (the rule of solid_and_field in distance_between.cpp).
  if (least_around(objective, core, size, d.distance)) {
    d.gradient_a.setZero();
    d.gradient_b.setZero();
  }
  return d;
}

ShapeDistance field_and_field(const SdfShape& a, Real time_a, const Transform& pose_a,
                              const SdfShape& b, Real time_b, const Transform& pose_b) {
  const auto objective = [&](const Vec3& x) {
    const sdf::Sample sa = world_sample(a, time_a, pose_a, x);
    const sdf::Sample sb = world_sample(b, time_b, pose_b, x);
    return sdf::Sample{sa.distance + sb.distance, Vec3(sa.gradient + sb.gradient)};
  };
  const auto anywhere = [](const Vec3& x) { return x; };
  // Seeds: each field's surface points where the other field is lowest.
  SeedList seeds_on_a, seeds_on_b;
  for_each_seed_candidate(a, pose_a, [&](const Vec3& p) {
    seeds_on_a.offer(world_sample(b, time_b, pose_b, p).distance, p);
  });
  for_each_seed_candidate(b, pose_b, [&](const Vec3& p) {
    seeds_on_b.offer(world_sample(a, time_a, pose_a, p).distance, p);
  });
  const Real size = std::min(a.bounding_radius(), b.bounding_radius());
  Real best = std::numeric_limits<Real>::infinity();
  Vec3 core = pose_a.translation;
  bool capped = false;
  descend_from(seeds_on_a, size, objective, anywhere, best, core, capped);
  descend_from(seeds_on_b, size, objective, anywhere, best, core, capped);
  const sdf::Sample sa = world_sample(a, time_a, pose_a, core);
  const sdf::Sample sb = world_sample(b, time_b, pose_b, core);
  check_within_reach(a, sa.distance, "field A");
  check_within_reach(b, sb.distance, "field B");
  ShapeDistance d;
  d.converged = !capped;
  d.distance = sa.distance + sb.distance;
  // At a smooth optimum grad phi_A = -grad phi_B, and their half difference m is used, so that
  // the two translation gradients are exact opposites (the distance does not change when both
  // move): moving A by v lowers phi_A at the fixed point by grad phi_A . v, so d/dx_A = m; a turn
  // w of A about its origin moves its field past the point by w x (x - x_A).
  // Where the sum has a kink at the optimum (the two gradients do not cancel), the kink is a
  // ridge or a deepest point of one field, which holds the optimum as that body moves: the
  // point is then fixed in that body, and the other field's gradient alone gives the rates.
  Vec3 m = (sb.gradient - sa.gradient) / 2;
  const Real residual = (sa.gradient + sb.gradient).norm();
  if (residual > Real(1e-6)) {
    const Real probe = size * Real(1e-9);
    const auto jumps = [&](const SdfShape& f, Real t, const Transform& pose, const Vec3& g) {
      for (int axis = 0; axis < 3; ++axis)
        for (const Real sign : {Real(-1), Real(1)}) {
          const Vec3 x = core + sign * probe * Vec3::Unit(axis);
          if ((world_sample(f, t, pose, x).gradient - g).norm() > Real(1e-3))
            return true;
        }
      return false;
    };
    const bool kink_of_a = jumps(a, time_a, pose_a, sa.gradient);
    const bool kink_of_b = jumps(b, time_b, pose_b, sb.gradient);
    if (kink_of_a && !kink_of_b)
      m = sb.gradient;  // held by A: B's field moving past A's point
    else if (kink_of_b && !kink_of_a)
      m = -sa.gradient;  // held by B: A's field moving past B's point
  }
  d.normal = unit_or(m, Vec3::UnitZ());
  d.point_a = core - sa.distance * unit_or(sa.gradient, -d.normal);
  d.point_b = core - sb.distance * unit_or(sb.gradient, d.normal);
  d.gradient_a.head<3>() = m;
  d.gradient_a.tail<3>() = (core - pose_a.translation).cross(m);
  d.gradient_b.head<3>() = -m;
  d.gradient_b.tail<3>() = -(core - pose_b.translation).cross(m);
  return d;
}

}  // namespace tumble
