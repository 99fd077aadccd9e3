// Conservative advancement (Mirtich, "Timewarp Rigid Body Simulation", SIGGRAPH 2000; Zhang,
// Redon, Lee and Kim, "Continuous Collision Detection for Articulated Models using Taylor Models
// and Temporal Culling", SIGGRAPH 2007, for the motion bound).
//
// Two bodies move over s in [0, 1] (collision/ccd/rigid_motion.hpp). At the current time the
// distance query gives a lower bound d of the distance and the axis n it was measured along.
// Along a fixed axis the gap between the two shapes closes no faster than
//   mu = max(0, -(v_A - v_B) . n) + |w_A| r_A + |w_B| r_B
// (linear motion: the centre velocities v are constant; r is the largest distance from the
// centre of mass to the surface), so the shapes cannot touch before s + d / mu: the time
// advances by that much and the query repeats. The steps adapt to the gap (never a fixed
// sampling, which can step over a thin contact) and shrink geometrically as the shapes close. For
// screw motion, and when the query has no axis, the centre velocities change direction, so mu uses
// their full speeds instead of the projection.
//
// The distance callback is any callable `DistanceBound(const Transform& a, const Transform& b)`
// returning a lower bound (collision/ccd/shape_distance.hpp); GJK plugs in the same way.
#pragma once

#include <cmath>
#include <cstdint>
#include <string_view>

#include "collision/ccd/rigid_motion.hpp"
#include "collision/ccd/shape_distance.hpp"

namespace tumble {

enum class ToiStatus : std::uint8_t {
  separated,       // the gap stays above the target for s in [0, 1]
  hit,             // the gap fell to the target (within the tolerance) at time_of_impact
  overlapping,     // the gap is within the tolerance of the target already at s = 0
  max_iterations,  // the iteration cap was reached; time_of_impact is the time reached (safe)
  invalid_input,   // NaN or infinite distance or motion
};

std::string_view toi_status_name(ToiStatus status);

struct ToiSettings {
  // The advancement stops once the distance bound is within `tolerance` above this [m]; the
  // contact is reported there. Zero asks for the moment of touching; a positive target stops
  // short of it (the stepper leaves a gap), a negative one allows that much penetration (the
  // stepper's test for bodies already in contact that must not pass through).
  Real target_distance = 0;
  // Width of the band above the target where the search stops [m]; > 0. The time error of a
  // hit is about tolerance / approach speed.
  Real tolerance = Real(1e-6);
  int max_iterations = 64;
};

// Where the advancement stops: the target plus the tolerance (1e-6 m when it is not positive).
// The distance callback may use it to know below what a loose bound must not be given.
inline Real stop_distance(const ToiSettings& settings) {
  return settings.target_distance + (settings.tolerance > 0 ? settings.tolerance : Real(1e-6));
}

struct ToiResult {
  ToiStatus status = ToiStatus::separated;
  Real time_of_impact = 1;      // in [0, 1]; 1 when separated
  Vec3 normal = Vec3::UnitZ();  // from B to A at the time of impact (hit only)
  Real distance = 0;            // the distance bound at time_of_impact [m]
  int iterations = 0;

  bool hit() const { return status == ToiStatus::hit || status == ToiStatus::overlapping; }
};

// The fastest two bodies' centres close under their motions: their relative speed when both move
// on straight lines, else the sum of their speeds.
inline Real centre_closing_speed(const RigidMotion& a, const RigidMotion& b) {
  const bool both_linear = a.kind() == MotionKind::linear && b.kind() == MotionKind::linear;
  return both_linear ? (a.linear_velocity() - b.linear_velocity()).norm()
                     : a.centre_speed() + b.centre_speed();
}

// The part the turning adds: each body's turn times its radius (nothing for a body that does
// not turn, even with an infinite radius: a plane).
inline Real turning_closing_speed(const RigidMotion& a, Real radius_a, const RigidMotion& b,
                                  Real radius_b) {
  const Real angular_a = a.angular_velocity().norm();
  const Real angular_b = b.angular_velocity().norm();
  return (angular_a > 0 ? angular_a * radius_a : Real(0)) +
         (angular_b > 0 ? angular_b * radius_b : Real(0));
}

// The fastest the gap between two bodies can close under their motions (radii as below), the
// two parts above: conservative_advancement's step never assumes more, so a gap larger than this
// over the motion is never closed.
inline Real greatest_closing_speed(const RigidMotion& a, Real radius_a, const RigidMotion& b,
                                   Real radius_b) {
  return centre_closing_speed(a, b) + turning_closing_speed(a, radius_a, b, radius_b);
}

// r_a, r_b: bounding radii about the centres of mass (0 for a body that does not turn).
template <class DistanceFunction>
ToiResult conservative_advancement(const RigidMotion& a, Real radius_a, const RigidMotion& b,
                                   Real radius_b, DistanceFunction&& distance,
                                   const ToiSettings& settings = {}) {
  ToiResult out;
  const Real spin_bound = turning_closing_speed(a, radius_a, b, radius_b);
  const bool both_linear = a.kind() == MotionKind::linear && b.kind() == MotionKind::linear;
  const Vec3 relative_velocity = a.linear_velocity() - b.linear_velocity();
  const Real full_speed = centre_closing_speed(a, b);
  const Real target = settings.target_distance;
  const Real stop = stop_distance(settings);
  Real s = 0;
  for (int it = 0; it < settings.max_iterations; ++it) {
    out.iterations = it + 1;
    const DistanceBound d = distance(a.at(s), b.at(s));
    if (!std::isfinite(d.distance) || !d.normal.allFinite() || !std::isfinite(spin_bound) ||
        !std::isfinite(full_speed)) {
      out.status = ToiStatus::invalid_input;
      out.time_of_impact = s;
      return out;
    }
    out.distance = d.distance;
    out.normal = d.normal;
    if (d.distance <= stop) {
      out.status = s == 0 ? ToiStatus::overlapping : ToiStatus::hit;
      out.time_of_impact = s;
      return out;
    }
    Real approach = full_speed;
    if (both_linear && d.separating_normal)
      approach = std::max(Real(0), -relative_velocity.dot(d.normal));
    const Real bound = approach + spin_bound;
    // Advance until the gap could have closed to the target (never past it); by the query's own
    // least advance where it measured one along each part's axis (a shape against a mesh).
    Real step = bound > 0 ? (d.distance - target) / bound : Real(2);
    if (d.least_advance > step)
      step = d.least_advance;
    if (s + step >= 1) {
      // The gap stays above the target up to s = 1: no contact in this motion.
      out.status = ToiStatus::separated;
      out.time_of_impact = 1;
      return out;
    }
    s += step;
  }
  out.status = ToiStatus::max_iterations;
  out.time_of_impact = s;
  return out;
}

// Time of impact of two shapes under their motions, with shape_distance_bound as the query.
ToiResult time_of_impact(const Shape& a, const RigidMotion& motion_a, const Shape& b,
                         const RigidMotion& motion_b, const ToiSettings& settings = {});

// A shape swept along a straight line (no rotation) from `pose` by `translation`, against a
// static shape: the shape cast. The hit time is the fraction of `translation` travelled.
ToiResult shape_cast(const Shape& moving, const Transform& pose, const Vec3& translation,
                     const Shape& target, const Transform& target_pose,
                     const ToiSettings& settings = {});

}  // namespace tumble
