#include "engine/step_workspace.hpp"

namespace tumble {

std::size_t StepWorkspace::bytes_reserved() const {
  const auto bytes = [](const auto& v) {
    return v.capacity() * sizeof(typename std::decay_t<decltype(v)>::value_type);
  };
  return bytes(box_queries) + bytes(box_candidates) + bytes(box_manifolds) + bytes(sphere_x) +
         bytes(sphere_y) + bytes(sphere_z) + bytes(sphere_radius) + bytes(sphere_pairs) +
         bytes(sphere_candidates) + bytes(sphere_out) + bytes(other_candidates) +
         bytes(candidate_manifolds) + bytes(candidate_kept) + bytes(candidate_route) +
         bytes(candidate_axis) + bytes(box_axes_found) + bytes(candidate_uses_gjk) +
         bytes(candidate_gjk) + bytes(candidate_is_hull_pair) + bytes(candidate_hull_axis) +
         bytes(hull_hits) + bytes(next_manifolds) + bytes(next_box_axes) + bytes(next_gjk_caches) +
         bytes(next_hull_axes) + bytes(next_resting_touches) + solver.bytes_reserved() +
         bytes(shape_poses) + bytes(carries) + islands.bytes_reserved() + bytes(root_of) +
         bytes(substeps_of_root) + bytes(group_of_root) + bytes(group_fill) +
         bytes(contacts_wanting) + bytes(level_needed) + bytes(level_before) + bytes(hold_before) +
         bytes(weighed_level) + bytes(island_mass);
}

}  // namespace tumble
