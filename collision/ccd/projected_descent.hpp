// Projected gradient descent to the least of a function over a convex set (Rosen, "The gradient
// projection method for nonlinear programming", J. SIAM 8, 1960), as the distances against
// signed distance fields use it (collision/ccd/distance_between.cpp, field_distance.cpp): a step
// against the gradient, projected back onto the set, then the least of a parabola fitted along
// the segment to it (the value at both ends and the slope at the start), kept when the value
// falls (the step then doubles if the whole segment was taken) and the step halved otherwise.
// At the optimum the tangential derivative is zero, so an error e in the point is an error of
// order e^2 in the value.
#pragma once

#include <algorithm>
#include <utility>

#include "collision/math.hpp"
#include "collision/sdf/sdf_primitives.hpp"

namespace tumble {

// From `start` (in the set): `objective(x)` gives the value and gradient (an sdf::Sample),
// `project(x)` the point of the set nearest x. Stops when the projected step vanishes (a
// stationary point, or the gradient pointing straight out of the set), when the step falls below
// 1e-14 of `size`, or after `max_steps` steps (then `*capped`, when given, is set). Returns the
// point and its sample.
template <class Objective, class Project>
std::pair<Vec3, sdf::Sample> projected_descent(const Vec3& start, Real size, int max_steps,
                                               const Objective& objective, const Project& project,
                                               bool* capped = nullptr) {
  Vec3 x = start;
  sdf::Sample here = objective(x);
  Real step = size / 8;
  int iteration = 0;
  for (; iteration < max_steps && step > size * Real(1e-14); ++iteration) {
    const Vec3 d = project(Vec3(x - step * here.gradient)) - x;
    if (!(d.norm() > size * Real(1e-15)))
      break;
    const Real slope = here.gradient.dot(d);
    if (!(slope < 0)) {
      step /= 2;  // not downhill (a kink, or rounding): a shorter step
      continue;
    }
    const Real end = objective(Vec3(x + d)).distance;
    const Real curvature = end - here.distance - slope;
    const Real t = curvature > 0 ? std::min(Real(1), -slope / (2 * curvature)) : Real(1);
    const Vec3 y = x + t * d;
    const sdf::Sample there = objective(y);
    if (!(there.distance < here.distance)) {
      step /= 2;
      continue;
    }
    x = y;
    here = there;
    if (t == 1)
      step *= 2;  // the whole step was taken: there may be room for a longer one
  }
  if (capped != nullptr)
    *capped = iteration == max_steps;
  return {x, here};
}

// Whether `point` is a least point of `objective` itself (a kink such as a field's deepest point
// or a ridge, not only the least over the set): no step of 1e-10 of `size` along any of the 26
// grid directions goes below `value` (a smooth objective falls along one of them). There the
// least value does not change as the poses move a little, and its gradients are zero.
template <class Objective>
bool least_around(const Objective& objective, const Vec3& point, Real size, Real value) {
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        if ((i != 0 || j != 0 || k != 0) &&
            !(objective(
                  Vec3(point + size * Real(1e-10) * Vec3(Real(i), Real(j), Real(k)).normalized()))
                  .distance >= value))
          return false;
  return true;
}

}  // namespace tumble
