#include "collision/pairs/contact_collector.hpp"

#include "collision/manifold_reduction.hpp"

namespace tumble::detail {
namespace {

constexpr Real kMergeCosine = Real(0.5);  // 60 degrees

}  // namespace

void ContactCollector::add(const Vec3& normal, const Vec3& point_on_a, Real depth,
                           FeatureId feature) {
  for (int i = 0; i < count_; ++i) {
    const Candidate& c = candidates_[i];
    if (c.point_on_a == point_on_a && c.normal == normal && c.depth == depth)
      return;  // the same contact from a second triangle or part
  }
  const Candidate candidate{normal, point_on_a, depth, feature};
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

int ContactCollector::finish(Real margin, Manifold& out) const {
  out = Manifold{};
  if (count_ == 0)
    return 0;
  int deepest = 0;
  for (int i = 1; i < count_; ++i)
    if (candidates_[i].depth > candidates_[deepest].depth)
      deepest = i;
  const Vec3 normal = candidates_[deepest].normal;
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
  std::array<int, kMaxManifoldPoints> kept{};
  const int count = reduce_manifold(normal, std::span<const ContactPoint>(points.data(), n), kept);
  out.normal = normal;
  for (int i = 0; i < count; ++i)
    out.add(points[kept[i]].position, points[kept[i]].depth, points[kept[i]].feature);
  return out.count;
}

}  // namespace tumble::detail
