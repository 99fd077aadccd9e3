#include "collision/narrow_phase/pairs/manifold_reduction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tumble {
namespace {

// Twice the signed area of triangle (a, b, c) seen along `normal` (positive counter-clockwise).
Real signed_area(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& normal) {
  return (b - a).cross(c - a).dot(normal);
}

// Twice the signed area of triangle (a, b, c) in the plane.
Real signed_area(const PlanarCandidate& a, const PlanarCandidate& b, const PlanarCandidate& c) {
  return (b.u - a.u) * (c.v - a.v) - (b.v - a.v) * (c.u - a.u);
}

// The choice itself, for any way of giving the candidates' geometry: `depth(i)`, the squared
// in-plane distance `lever2(i, j)` and twice the signed area `area(i, j, k)` seen along the
// normal (positive counter-clockwise). reduce_manifold and reduce_planar_manifold differ only in
// these (projecting 3D points, or reading plane coordinates), so their choices follow one set of
// steps and tie rules.
template <class Depth, class Lever2, class Area>
int reduce(int count, const Depth& depth, const Lever2& lever2, const Area& area,
           std::array<int, kMaxManifoldPoints>& kept) {
  if (count <= kMaxManifoldPoints) {
    for (int i = 0; i < count; ++i)
      kept[i] = i;
    return count;
  }
  const auto taken = [&](int i, int so_far) {
    return std::find(kept.begin(), kept.begin() + so_far, i) != kept.begin() + so_far;
  };

  // 1. The deepest point: the one the solver needs most.
  int first = 0;
  for (int i = 1; i < count; ++i) {
    if (depth(i) > depth(first))
      first = i;
  }
  kept[0] = first;

  // 2. The point farthest from it in the contact plane: the longest lever arm.
  int second = -1;
  Real farthest = -1;
  for (int i = 0; i < count; ++i) {
    if (i == first)
      continue;
    const Real squared = lever2(i, first);
    if (squared > farthest) {
      farthest = squared;
      second = i;
    }
  }
  kept[1] = second;

  // 3. The point that makes the largest triangle with the first two, on either side.
  int third = -1;
  Real largest = -1;
  for (int i = 0; i < count; ++i) {
    if (taken(i, 2))
      continue;
    const Real size = std::abs(area(first, second, i));
    if (size > largest) {
      largest = size;
      third = i;
    }
  }
  kept[2] = third;

  // 4. The point that adds the most area to that triangle: outside one of its edges, by the
  // area of the triangle it makes with that edge. Orient the triangle counter-clockwise so that
  // "outside an edge" is "negative signed area against it".
  const bool counter_clockwise = area(first, second, third) >= 0;
  const std::array<int, 3> corner = counter_clockwise ? std::array<int, 3>{first, second, third}
                                                      : std::array<int, 3>{first, third, second};
  int fourth = -1;
  Real most_added = -std::numeric_limits<Real>::infinity();
  for (int i = 0; i < count; ++i) {
    if (taken(i, 3))
      continue;
    Real added = -std::numeric_limits<Real>::infinity();
    for (int e = 0; e < 3; ++e)
      added = std::max(added, -area(corner[e], corner[(e + 1) % 3], i));
    if (added > most_added) {
      most_added = added;
      fourth = i;
    }
  }
  kept[3] = fourth;
  return kMaxManifoldPoints;
}

}  // namespace

int reduce_manifold(const Vec3& normal, std::span<const ContactPoint> candidates,
                    std::array<int, kMaxManifoldPoints>& kept) {
  const auto position = [&](int i) -> const Vec3& { return candidates[std::size_t(i)].position; };
  return reduce(
      int(candidates.size()), [&](int i) { return candidates[std::size_t(i)].depth; },
      [&](int i, int j) {
        Vec3 offset = position(i) - position(j);
        offset -= normal * normal.dot(offset);
        return offset.squaredNorm();
      },
      [&](int i, int j, int k) {
        return signed_area(position(i), position(j), position(k), normal);
      },
      kept);
}

int write_reduced_manifold(const Vec3& normal, std::span<const ContactPoint> candidates,
                           Manifold& out) {
  out.normal = normal;
  std::array<int, kMaxManifoldPoints> kept{};
  const int kept_count = reduce_manifold(normal, candidates, kept);
  for (int i = 0; i < kept_count; ++i) {
    const ContactPoint& p = candidates[std::size_t(kept[std::size_t(i)])];
    out.add(p.position, p.depth, p.feature);
  }
  return out.count;
}

int reduce_planar_manifold(std::span<const PlanarCandidate> candidates,
                           std::array<int, kMaxManifoldPoints>& kept) {
  const auto at = [&](int i) -> const PlanarCandidate& { return candidates[std::size_t(i)]; };
  return reduce(
      int(candidates.size()), [&](int i) { return at(i).depth; },
      [&](int i, int j) {
        const Real du = at(i).u - at(j).u;
        const Real dv = at(i).v - at(j).v;
        return du * du + dv * dv;
      },
      [&](int i, int j, int k) { return signed_area(at(i), at(j), at(k)); }, kept);
}

}  // namespace tumble
