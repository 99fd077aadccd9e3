// Box against plane: every corner of the box that is below the plane, or above it by less than
// the margin, is a point; depth is the corner's distance below the plane. A box resting flat
// gets its four bottom corners; more than four candidates (a box sunk deeper than its own size,
// or a margin larger than it) are reduced to four by manifold_reduction.
#include <array>

#include "collision/narrow_phase/pairs/manifold_reduction.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"

namespace tumble::detail {

int box_plane(const Shape& a, const Transform& pose_a, const Shape& /*plane*/,
              const Transform& pose_b, Real margin, Manifold& out) {
  const Vec3 normal = pose_b.rotate(Vec3::UnitZ());
  out.normal = normal;
  // The plane normal in the box's frame: the corner heights are then dot products with the
  // local corner, measured from the box centre's height.
  const Vec3 local_normal = pose_a.rotate_inverse(normal);
  const Real centre_height = normal.dot(pose_a.translation - pose_b.translation);

  std::array<ContactPoint, 8> candidates;
  int candidate_count = 0;
  for (int vertex = 0; vertex < 8; ++vertex) {
    Vec3 corner;
    for (int k = 0; k < 3; ++k) {
      corner[k] = (vertex >> k) & 1 ? a.half_extents[k] : -a.half_extents[k];
    }
    const Real depth = -(centre_height + local_normal.dot(corner));
    if (!(depth >= -margin))
      continue;
    const Vec3 point_on_box = pose_a.apply(corner);
    candidates[candidate_count++] = {point_on_box + normal * (depth * Real(0.5)),
                                     depth,
                                     {feature::box_vertex(vertex), feature::kPlane}};
  }

  std::array<int, kMaxManifoldPoints> kept{};
  const int kept_count =
      reduce_manifold(normal, std::span(candidates.data(), std::size_t(candidate_count)), kept);
  for (int i = 0; i < kept_count; ++i) {
    const ContactPoint& p = candidates[kept[i]];
    out.add(p.position, p.depth, p.feature);
  }
  return out.count;
}

}  // namespace tumble::detail
