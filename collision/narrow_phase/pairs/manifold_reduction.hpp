// Contact manifold reduction: from many candidate points sharing one normal (a clipped face, the
// corners of a box swallowed by a plane), keep the four that best hold the bodies: the deepest
// point, the point farthest from it, and the two that add the most area on either side of the
// line through them. After Erin Catto, "Contact Manifolds" (GDC 2007) and Dirk Gregorius,
// "Robust Contact Creation for Physics Simulations" (GDC 2015), whose reduction Jolt's
// PruneContactPoints also follows.
#pragma once

#include <array>
#include <span>

#include "collision/contact.hpp"

namespace tumble {

// Chooses min(candidates.size(), kMaxManifoldPoints) of the candidates and writes their indices
// into `kept`, the deepest first; returns how many. Distances and areas are measured in the
// plane perpendicular to `normal`. Ties go to the lower index, so the choice is deterministic.
int reduce_manifold(const Vec3& normal, std::span<const ContactPoint> candidates,
                    std::array<int, kMaxManifoldPoints>& kept);

// Sets out.normal and adds the points reduce_manifold keeps, the deepest first; returns
// out.count.
int write_reduced_manifold(const Vec3& normal, std::span<const ContactPoint> candidates,
                           Manifold& out);

// A candidate already in the contact plane: coordinates (u, v) on two orthonormal directions
// perpendicular to the normal, and its depth.
struct PlanarCandidate {
  Real u;
  Real v;
  Real depth;
};

// The same choice as reduce_manifold for candidates given in the contact plane (a box's face
// frame gives them for free), without projecting: the same points up to rounding.
int reduce_planar_manifold(std::span<const PlanarCandidate> candidates,
                           std::array<int, kMaxManifoldPoints>& kept);

}  // namespace tumble
