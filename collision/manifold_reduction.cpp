#include "collision/manifold_reduction.hpp"

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

}  // namespace

int reduce_manifold(const Vec3& normal, std::span<const ContactPoint> candidates,
                    std::array<int, kMaxManifoldPoints>& kept) {
  const int count = int(candidates.size());
  if (count <= kMaxManifoldPoints) {
    for (int i = 0; i < count; ++i)
      kept[i] = i;
    return count;
  }
  const auto position = [&](int i) -> const Vec3& { return candidates[i].position; };
  const auto taken = [&](int i, int so_far) {
    return std::find(kept.begin(), kept.begin() + so_far, i) != kept.begin() + so_far;
  };

  // 1. The deepest point: the one the solver needs most.
  int first = 0;
  for (int i = 1; i < count; ++i) {
    if (candidates[i].depth > candidates[first].depth)
      first = i;
  }
  kept[0] = first;

  // 2. The point farthest from it in the contact plane: the longest lever arm.
  int second = -1;
  Real farthest = -1;
  for (int i = 0; i < count; ++i) {
    if (i == first)
      continue;
    Vec3 offset = position(i) - position(first);
    offset -= normal * normal.dot(offset);
    if (offset.squaredNorm() > farthest) {
      farthest = offset.squaredNorm();
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
    const Real area = std::abs(signed_area(position(first), position(second), position(i), normal));
    if (area > largest) {
      largest = area;
      third = i;
    }
  }
  kept[2] = third;

  // 4. The point that adds the most area to that triangle: outside one of its edges, by the
  // area of the triangle it makes with that edge. Orient the triangle counter-clockwise so that
  // "outside an edge" is "negative signed area against it".
  const bool counter_clockwise =
      signed_area(position(first), position(second), position(third), normal) >= 0;
  const std::array<int, 3> corner = counter_clockwise ? std::array<int, 3>{first, second, third}
                                                      : std::array<int, 3>{first, third, second};
  int fourth = -1;
  Real most_added = -std::numeric_limits<Real>::infinity();
  for (int i = 0; i < count; ++i) {
    if (taken(i, 3))
      continue;
    Real added = -std::numeric_limits<Real>::infinity();
    for (int e = 0; e < 3; ++e) {
      const Real outside =
          -signed_area(position(corner[e]), position(corner[(e + 1) % 3]), position(i), normal);
      added = std::max(added, outside);
    }
    if (added > most_added) {
      most_added = added;
      fourth = i;
    }
  }
  kept[3] = fourth;
  return kMaxManifoldPoints;
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
  // The steps and tie rules of reduce_manifold above, with areas and distances read directly in
  // the plane.
  const int count = int(candidates.size());
  if (count <= kMaxManifoldPoints) {
    for (int i = 0; i < count; ++i)
      kept[i] = i;
    return count;
  }
  const auto taken = [&](int i, int so_far) {
    return std::find(kept.begin(), kept.begin() + so_far, i) != kept.begin() + so_far;
  };

  int first = 0;
  for (int i = 1; i < count; ++i) {
    if (candidates[i].depth > candidates[first].depth)
      first = i;
  }
  kept[0] = first;

  int second = -1;
  Real farthest = -1;
  for (int i = 0; i < count; ++i) {
    if (i == first)
      continue;
    const Real du = candidates[i].u - candidates[first].u;
    const Real dv = candidates[i].v - candidates[first].v;
    const Real squared = du * du + dv * dv;
    if (squared > farthest) {
      farthest = squared;
      second = i;
    }
  }
  kept[1] = second;

  int third = -1;
  Real largest = -1;
  for (int i = 0; i < count; ++i) {
    if (taken(i, 2))
      continue;
    const Real area = std::abs(signed_area(candidates[first], candidates[second], candidates[i]));
    if (area > largest) {
      largest = area;
      third = i;
    }
  }
  kept[2] = third;

  const bool counter_clockwise =
      signed_area(candidates[first], candidates[second], candidates[third]) >= 0;
  const std::array<int, 3> corner = counter_clockwise ? std::array<int, 3>{first, second, third}
                                                      : std::array<int, 3>{first, third, second};
  int fourth = -1;
  Real most_added = -std::numeric_limits<Real>::infinity();
  for (int i = 0; i < count; ++i) {
    if (taken(i, 3))
      continue;
    Real added = -std::numeric_limits<Real>::infinity();
    for (int e = 0; e < 3; ++e) {
      const Real outside =
          -signed_area(candidates[corner[e]], candidates[corner[(e + 1) % 3]], candidates[i]);
      added = std::max(added, outside);
    }
    if (added > most_added) {
      most_added = added;
      fourth = i;
    }
  }
  kept[3] = fourth;
  return kMaxManifoldPoints;
}

}  // namespace tumble
