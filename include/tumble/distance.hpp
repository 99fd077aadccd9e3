// The signed distance between two shapes and its derivative with respect to both poses: for
// trajectory optimisation, grasp planning and differentiable learning, which need to know how a
// clearance or a penetration changes when a body moves.
//
//   tumble::ShapeDistance d = tumble::distance_between(a, pose_a, b, pose_b);
//   // d.distance < 0: penetrating by -d.distance; d.gradient_a[0..2] = d distance / d x_a
//
// The derivative of a distance (or of a penetration depth) is that of the support along the
// fixed closest direction (the envelope theorem): moving A by v and turning it by w about its
// origin changes the distance at the rate n . (v + w x (p_a - x_a)), with n the unit normal from
// B to A and p_a A's closest (or deepest) point. It holds wherever the closest features are
// unique; where they are not (two faces parallel, a box resting flat), the distance has a kink
// and the answer is one of the one-sided derivatives (docs/sdf.md, "Gradients").
#pragma once

#include <Eigen/Core>

#include "tumble/math.hpp"
#include "tumble/shape.hpp"

namespace tumble {

// A derivative with respect to a pose: [d/d translation (x, y, z); d/d rotation about the body's
// own origin, world axes (x, y, z)].
using PoseGradient = Eigen::Matrix<Real, 6, 1>;

struct ShapeDistance {
  Real distance = 0;            // m; negative in penetration (minus the penetration depth)
  Vec3 point_a = Vec3::Zero();  // A's closest point (deepest, in penetration), world
  Vec3 point_b = Vec3::Zero();  // B's
  Vec3 normal = Vec3::UnitZ();  // unit, from B to A
  PoseGradient gradient_a = PoseGradient::Zero();
  PoseGradient gradient_b = PoseGradient::Zero();
  // False when GJK or EPA stopped at its iteration cap or on a degenerate simplex: the numbers are
  // the best found, not converged.
  bool converged = true;
};

// Between two convex shapes (sphere, box, capsule, cylinder, hull), a convex shape and a plane
// (the solid half-space below it), or a signed distance field and a convex shape, a plane or
// another field. Against a field: the least value of the field over the shape (a sphere's or
// capsule's over its core less the radius; over the half-space for a plane), with gradients
// from grad phi there, zero where that point is a kink of the field phi cannot go below; two
// fields: the least of phi_A + phi_B (their distance while apart). Throws tumble::Error for a
// mesh, a compound, two planes, or a pose that is not finite. Without `gradients` the gradients
// are left zero (a penetrating pair with a cylinder whose supports along the normal are both
// faces then costs one query instead of 25: its gradients are central differences of the depth;
// docs/sdf.md, "Cylinders in penetration").
ShapeDistance distance_between(const Shape& a, const Transform& pose_a, const Shape& b,
                               const Transform& pose_b, bool gradients = true);

// The smooth contact potential of a pair at distance d: k/2 d^2 in penetration (d < 0), zero
// apart, and its gradients k d (d distance / d pose), each component clipped to
// [-max_gradient, max_gradient] so that a deep penetration does not throw an optimiser far.
struct ContactPotential {
  Real value = 0;
  PoseGradient gradient_a = PoseGradient::Zero();
  PoseGradient gradient_b = PoseGradient::Zero();
};
ContactPotential contact_potential(const ShapeDistance& d, Real stiffness, Real max_gradient);

}  // namespace tumble
