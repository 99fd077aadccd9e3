// A compound against any shape: each part whose bounding box (inflated by the margin) overlaps
// the other shape's runs through the ordinary dispatch table, and the parts' contacts are merged
// into one manifold (contact_collector.hpp): the engine keeps one manifold per body pair. The
// part index goes into the compound's half of each feature id so points of different parts never
// share an id. A compound against a compound recurses once (part against compound).
#include "collision/narrow_phase/compound_collide.hpp"

#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/narrow_phase/pairs/contact_collector.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"
#include "collision/shapes/compound_shape.hpp"

namespace tumble::detail {

int compound_any(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                 Real margin, Manifold& out) {
  const CompoundShape& compound = *a.compound;
  const Aabb other = world_aabb(b, pose_b).inflated(margin);
  ContactCollector collector;
  const auto& parts = compound.parts();
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const Transform part_pose = compose(pose_a, parts[i].pose);
    if (!world_aabb(parts[i].shape, part_pose).overlaps(other))
      continue;
    Manifold part;
    if (collide(parts[i].shape, part_pose, b, pose_b, margin, part) == 0)
      continue;
    for (int k = 0; k < part.count; ++k) {
      const ContactPoint& p = part.points[k];
      collector.add(part.normal, p.point_on_a(part.normal), p.depth,
                    {feature::compound_feature(int(i), p.feature.a), p.feature.b});
    }
  }
  return collector.finish(margin, ContactCollector::kMergeFraction * bounding_radius(a), out);
}

}  // namespace tumble::detail
