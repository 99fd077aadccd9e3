#include "collision/narrow_phase/pairs/contact_collector.hpp"

#include "collision/narrow_phase/pairs/manifold_reduction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tumble::detail {
namespace {

constexpr Real kMergeCosine = Real(0.5);  // 60 degrees

}  // namespace

void ContactCollector::add(const Vec3& normal, const Vec3& point_on_a, Real depth,
                           FeatureId feature, std::uint8_t kind) {
  for (int i = 0; i < count_; ++i) {
    const Candidate& c = candidates_[i];
    if (c.point_on_a == point_on_a && c.normal == normal && c.depth == depth)
      return;  // the same contact from a second triangle or part
  }
  const Candidate candidate{normal, point_on_a, depth, feature, kind};
  if (count_ < kCapacity) {
    candidates_[count_++] = candidate;
    return;
  }
  int shallowest = 0;
  for (int i = 1; i < count_; ++i)
    if (candidates_[i].depth < candidates_[shallowest].depth)
      shallowest = i;
  if (depth > candidates_[shallowest].depth)
    candidates_[shallowest] = candidate;
}

int ContactCollector::finish(Real margin, Real merge_distance, Manifold& out,
                             NormalRule rule) const {
  out = Manifold{};
  if (count_ == 0)
    return 0;
  int deepest = 0;
  for (int i = 1; i < count_; ++i)
    if (candidates_[i].depth > candidates_[deepest].depth)
      deepest = i;
  Vec3 normal = candidates_[deepest].normal;
  if (rule != NormalRule::deepest) {
    const auto in_cone = [&](const Candidate& c) { return c.normal.dot(normal) >= kMergeCosine; };
    // Which kind votes: any, the deepest's, or kind 0 while one lies in the cone.
    int voting_kind = -1;
    if (rule == NormalRule::weighted_mean_of_deepest_kind)
      voting_kind = candidates_[deepest].kind;
    if (rule == NormalRule::weighted_mean_of_kind_zero) {
      for (int i = 0; i < count_ && voting_kind < 0; ++i)
        voting_kind = candidates_[i].kind == 0 && in_cone(candidates_[i]) ? 0 : -1;
    }
    Vec3 sum = Vec3::Zero();
    for (int i = 0; i < count_; ++i) {
      const Candidate& c = candidates_[i];
      if (in_cone(c) && (voting_kind < 0 || c.kind == voting_kind))
        sum += std::max(c.depth + margin, Real(0)) * c.normal;
    }
    if (sum.squaredNorm() > 0)
      normal = sum.normalized();
  }
  std::array<ContactPoint, kCapacity> points;
  int n = 0;
  for (int i = 0; i < count_; ++i) {
    const Candidate& c = candidates_[i];
    const Real cosine = c.normal.dot(normal);
    if (cosine < kMergeCosine)
      continue;
    const Real depth = c.depth * cosine;
    if (!(depth >= -margin))
      continue;
    points[n++] = {c.point_on_a + normal * (depth * Real(0.5)), depth, c.feature};
  }
  // Near-coincident points: the deepest of each cluster stays (the first of equally deep ones),
  // the others go; the survivors keep their order.
  if (merge_distance > 0 && n > 1) {
    std::array<int, kCapacity> by_depth;
    for (int i = 0; i < n; ++i)
      by_depth[i] = i;
    // std::sort with the index as tie-break: stable without stable_sort's heap buffer.
    std::sort(by_depth.begin(), by_depth.begin() + n, [&](int x, int y) {
      return points[x].depth != points[y].depth ? points[x].depth > points[y].depth : x < y;
    });
    std::array<bool, kCapacity> keep{};
    const Real limit = merge_distance * merge_distance;
    for (int k = 0; k < n; ++k) {
      const int i = by_depth[k];
      bool near = false;
      for (int q = 0; q < k && !near; ++q) {
        const int j = by_depth[q];
        near = keep[j] && (points[i].position - points[j].position).squaredNorm() < limit;
      }
      keep[i] = !near;
    }
    int kept_count = 0;
    for (int i = 0; i < n; ++i)
      if (keep[i])
        points[kept_count++] = points[i];
    n = kept_count;
  }
  // Points whose depths differ only by rounding (a box flat on a mesh: every corner and every
  // clipped point at one depth) are equally deep; left to rounding, the "deepest" would be an
  // arbitrary one of them, often inside the face, and the four kept points would not span it.
  // So the reduction sees them at one depth with the extreme one along a fixed tangent first:
  // it then keeps the outline, as it does for a box on a plane.
  std::array<ContactPoint, kCapacity> selection;
  Real deepest_depth = -std::numeric_limits<Real>::infinity();
  Real extent = 0;
  for (int i = 0; i < n; ++i) {
    deepest_depth = std::max(deepest_depth, points[i].depth);
    extent = std::max(extent, (points[i].position - points[0].position).norm());
  }
  const Real tie = Real(1e-9) * (extent + std::abs(deepest_depth)) + Real(1e-12);
  Vec3 tangent;
  Vec3 bitangent;
  orthonormal_basis(normal, tangent, bitangent);
  int lead = -1;
  for (int i = 0; i < n; ++i) {
    selection[i] = points[i];
    if (points[i].depth >= deepest_depth - tie) {
      selection[i].depth = deepest_depth;
      if (lead < 0 || points[i].position.dot(tangent) > points[lead].position.dot(tangent))
        lead = i;
    }
  }
  std::array<int, kCapacity> order;
  order[0] = lead;
  for (int i = 0, k = 1; i < n; ++i)
    if (i != lead)
      order[k++] = i;
  std::array<ContactPoint, kCapacity> ordered;
  for (int i = 0; i < n; ++i)
    ordered[i] = selection[order[i]];
  std::array<int, kMaxManifoldPoints> kept{};
  const int count = reduce_manifold(normal, std::span<const ContactPoint>(ordered.data(), n), kept);
  for (int i = 0; i < count; ++i)
    kept[i] = order[kept[i]];
  // A canonical order (by feature id, then by candidate) so the solver visits the points in the
  // same order whichever triangles or parts they came from.
  const auto before = [&](int x, int y) {
    const std::uint32_t kx = points[x].feature.key();
    const std::uint32_t ky = points[y].feature.key();
    return kx != ky ? kx < ky : x < y;
  };
  for (int i = 1; i < count; ++i)  // insertion sort of at most four
    for (int j = i; j > 0 && before(kept[j], kept[j - 1]); --j)
      std::swap(kept[j], kept[j - 1]);
  out.normal = normal;
  for (int i = 0; i < count; ++i)
    out.add(points[kept[i]].position, points[kept[i]].depth, points[kept[i]].feature);
  return out.count;
}

}  // namespace tumble::detail
