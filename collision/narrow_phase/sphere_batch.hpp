// Sphere-sphere over many pairs at once (docs/narrow-phase.md, "Many sphere pairs at once"): the
// narrow phase for scenes of balls, grains and particles, where the per-pair path (dispatch
// table, pair-local frame, a full Manifold per pair) costs more than the geometry itself. Spheres
// are given as structure-of-arrays (centres and radii in separate arrays, the layout a
// data-oriented engine keeps anyway) and pairs as index pairs into them; the pairs are processed in
// blocks by branch-free, vectorised loops.
//
// The answers are those of collide() for the same two spheres, bit for bit (same ordering rule
// of equal shapes, same pair-local frame, same arithmetic): a batch and a loop over collide()
// can be swapped for one another without changing a simulation. A sphere's orientation never
// matters, so the spheres are taken as unrotated.
#pragma once

#include <cstdint>
#include <span>

#include "collision/math.hpp"

namespace tumble {

// n spheres as structure-of-arrays; each pointer addresses n values.
struct SphereArrays {
  const Real* x = nullptr;
  const Real* y = nullptr;
  const Real* z = nullptr;
  const Real* radius = nullptr;
};

struct SpherePair {
  std::int32_t a = 0;  // indices into SphereArrays
  std::int32_t b = 0;
};

// One contact of a pair within the margin, in collide()'s convention: normal from B to A, depth
// positive when they penetrate, position midway between the surfaces.
struct SphereContact {
  std::int32_t pair = 0;  // index into the pair list
  Real depth = 0;
  Vec3 normal = Vec3::UnitZ();
  Vec3 position = Vec3::Zero();
};

// Results for every pair, as structure-of-arrays (each pointer addresses pairs.size() values):
// depth (>= -margin: the pair touches), normal from B to A, and the contact position. Pairs
// apart have their depth and normal too (NaN input gives NaN).
struct SphereContactArrays {
  Real* depth = nullptr;
  Real* normal_x = nullptr;
  Real* normal_y = nullptr;
  Real* normal_z = nullptr;
  Real* x = nullptr;
  Real* y = nullptr;
  Real* z = nullptr;
};

// The fastest form: fills `out` for every pair (no compaction) and returns how many pairs have
// depth >= -margin. The values of touching pairs are collide()'s, bit for bit.
std::size_t collide_sphere_pairs_dense(const SphereArrays& spheres,
                                       std::span<const SpherePair> pairs, Real margin,
                                       const SphereContactArrays& out);

// Writes one SphereContact per pair whose signed depth is at least -margin into `out`, in pair
// order, and returns how many it wrote. `out` needs room for pairs.size() entries (every slot
// may be written as scratch); the call never allocates.
std::size_t collide_sphere_pairs(const SphereArrays& spheres, std::span<const SpherePair> pairs,
                                 Real margin, std::span<SphereContact> out);

}  // namespace tumble
