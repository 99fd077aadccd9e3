// Convex shape against a static triangle mesh: the mesh's BVH is queried with the convex
// shape's bounding box in the mesh's frame (inflated by the margin), each triangle it returns
// gets a convex-triangle contact (convex_triangle.cpp, with the internal-edge rules there), and
// the contacts of all triangles are merged into one manifold of at most four points
// (contact_collector.hpp). Sphere, box and capsule have closed-form convex-triangle functions;
// cylinder and hull go through GJK/EPA (convex_triangle_generic.cpp).
#include "collision/narrow_phase/pairs/contact_collector.hpp"
#include "collision/narrow_phase/pairs/convex_triangle.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"
#include "collision/shapes/triangle_mesh.hpp"

namespace tumble::detail {

int convex_mesh(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                Real margin, Manifold& out) {
  using TriangleFunction = int (*)(const Shape&, const TriangleView&, Real, TriangleContact&);
  TriangleFunction function = nullptr;
  switch (a.type) {
    case ShapeType::sphere:
      function = sphere_triangle;
      break;
    case ShapeType::box:
      function = box_triangle;
      break;
    case ShapeType::capsule:
      function = capsule_triangle;
      break;
    case ShapeType::cylinder:
    case ShapeType::hull:
      function = generic_triangle;
      break;
    default:
      return 0;
  }
  const TriangleMesh& mesh = *b.mesh;
  // The convex shape's pose in the mesh's frame, for the query, and the mesh's pose in the
  // convex shape's frame, for the triangles.
  const Quat mesh_to_convex = pose_a.rotation.conjugate() * pose_b.rotation;
  const Vec3 mesh_origin_in_convex = pose_a.rotate_inverse(pose_b.translation - pose_a.translation);
  const Transform convex_in_mesh = pose_b.relative(pose_a);
  const Aabb query = world_aabb(a, convex_in_mesh).inflated(margin);
  const Mat3 rotation = mesh_to_convex.toRotationMatrix();

  ContactCollector collector;
  mesh.for_each_overlapping(query, [&](int t) {
    TriangleView view;
    for (int k = 0; k < 3; ++k) {
      view.corner[k] = rotation * mesh.corner(t, k) + mesh_origin_in_convex;
      view.edge[k] = mesh.edge_kind(t, k);
      view.corner_active[k] = mesh.corner_is_active(t, k);
    }
    view.normal = rotation * mesh.normal(t);
    TriangleContact contact;
    if (function(a, view, margin, contact) == 0)
      return;
    const Vec3 normal = pose_a.rotate(contact.normal);
    for (int i = 0; i < contact.count; ++i) {
      const Vec3 point_on_a = pose_a.apply(contact.point_on_convex[i]);
      // Face contacts name the surface, not the triangle, so a corner sliding across a flat
      // mesh keeps its id (and its warm start) from one triangle to the next.
      const std::uint16_t mesh_side = contact.region[i] == detail::TriangleRegion::face
                                          ? feature::kMeshFace
                                          : feature::mesh_feature(t, int(contact.region[i]));
      collector.add(normal, point_on_a, contact.depth[i], {contact.convex_feature[i], mesh_side});
    }
  });
  return collector.finish(margin, ContactCollector::kMergeFraction * bounding_radius(a), out);
}

}  // namespace tumble::detail
