// The contact convention (docs/architecture.md, "One step"): for a pair (A, B) the normal is a unit
// vector pointing from B to A, the depth is positive when the shapes penetrate and negative when
// they are apart, and the point is world-space, midway between the two surfaces. Feature ids name
// which vertex, edge or face of each shape made the point, so points can be matched across steps.
#pragma once

#include <array>
#include <cstdint>

#include "collision/math.hpp"

namespace tumble {

// Which features of A and B produced a contact point. Shapes number their own features; a
// swap of A and B swaps the two halves.
struct FeatureId {
  std::uint16_t a = 0;
  std::uint16_t b = 0;

  std::uint32_t key() const { return (std::uint32_t(a) << 16) | b; }
  FeatureId swapped() const { return {b, a}; }
  bool operator==(const FeatureId&) const = default;
};

struct ContactPoint {
  Vec3 position = Vec3::Zero();  // world, midway between the surfaces [m]
  Real depth = 0;                // positive = penetration [m]
  FeatureId feature;

  // The points on A and on B that the contact joins (n from B to A).
  Vec3 point_on_a(const Vec3& normal) const { return position - normal * (depth * Real(0.5)); }
  Vec3 point_on_b(const Vec3& normal) const { return position + normal * (depth * Real(0.5)); }
};

inline constexpr int kMaxManifoldPoints = 4;

// Up to four points sharing one normal.
struct Manifold {
  Vec3 normal = Vec3::UnitZ();  // from B to A
  int count = 0;
  std::array<ContactPoint, kMaxManifoldPoints> points{};
  // How the separation bends as A moves relative to B: its second derivative with respect to
  // that displacement (world, packed) [1/m]. Zero but where a round shape's core
  // is measured in a curved field; there the solver follows the surface through the step
  // instead of its tangent plane (docs/architecture.md, "Curved contacts").
  PackedSymmetric separation_curvature{};
  // Field contacts (narrow_phase/pairs/sdf_pairs.cpp): how many candidate points the surface walk
  // refined, and how many of those stopped at its step cap before converging (their depth is then
  // the walk's last, a lower bound). Zero for every other pair.
  std::uint16_t refined = 0;
  std::uint16_t refine_capped = 0;
  // Whether the walk that ended deepest (the one the manifold's depth comes from, when a walk's
  // point is the deepest candidate) was one of the capped ones.
  bool deepest_walk_capped = false;

  void add(const Vec3& position, Real depth, FeatureId feature) {
    if (count < kMaxManifoldPoints)
      points[count++] = {position, depth, feature};
  }
};

}  // namespace tumble
