// The record of one contact point that both solvers keep (internal): the contact frame, lever
// arms, anchors, precomputed Jacobian rows and the accumulated impulses. Each solver's own point
// derives from it and adds what only it needs (restitution state; penalty spring constants).
#pragma once

#include <cstdint>

#include "collision/math.hpp"

namespace tumble::detail {

struct SolverPoint {
  std::int32_t a = 0;
  std::int32_t b = 0;
  std::uint32_t feature = 0;
  Vec3 normal = Vec3::UnitZ();  // from B to A
  Vec3 tangent1 = Vec3::UnitX();
  Vec3 tangent2 = Vec3::UnitY();
  Vec3 r_a = Vec3::Zero();  // lever arms at the start of the step (world)
  Vec3 r_b = Vec3::Zero();
  Vec3 local_a = Vec3::Zero();  // anchors in each body's frame, to track separation
  Vec3 local_b = Vec3::Zero();
  Real base_separation = 0;  // separation less the anchors' offset along the normal
  // Jacobian rows precomputed once per step (Catto, GDC 2005): the lever arm crossed with
  // each direction, and the angular velocity change per unit impulse along it,
  // I^-1 (r x d), for A and B. They turn every velocity read and impulse into dot products
  // and scaled additions instead of matrix products.
  Vec3 rn_a = Vec3::Zero(), rn_b = Vec3::Zero();
  Vec3 rt1_a = Vec3::Zero(), rt1_b = Vec3::Zero();
  Vec3 rt2_a = Vec3::Zero(), rt2_b = Vec3::Zero();
  Vec3 in_a = Vec3::Zero(), in_b = Vec3::Zero();
  Vec3 it1_a = Vec3::Zero(), it1_b = Vec3::Zero();
  Vec3 it2_a = Vec3::Zero(), it2_b = Vec3::Zero();
  Real inv_mass_a = 0, inv_mass_b = 0;
  Real normal_mass = 0;
  Real tangent_mass1 = 0;
  Real tangent_mass2 = 0;
  Real friction = 0;
  Real normal_impulse = 0;  // accumulated (impulse solver: per step; penalty: per substep)
  Real tangent_impulse1 = 0;
  Real tangent_impulse2 = 0;
};

}  // namespace tumble::detail
