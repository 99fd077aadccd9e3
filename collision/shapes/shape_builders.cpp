// Shapes built from data (include/tumble/shape.hpp): the public face of the hull, mesh and
// compound builders, whose own errors become tumble::Error.
#include <memory>
#include <string>
#include <utility>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/triangle_mesh.hpp"
#include "tumble/error.hpp"

namespace tumble {

Shape hull_from_points(std::span<const Vec3> points, Vec3* centre_of_mass) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite())
      throw Error("hull_from_points: point " + std::to_string(i) + " is not finite");
  }
  try {
    auto hull = std::make_shared<const ConvexHull>(ConvexHull::from_points(points));
    if (centre_of_mass != nullptr)
      *centre_of_mass = hull->centre_of_mass_offset();
    return Shape::convex_hull(std::move(hull));
  } catch (const std::exception& e) {
    throw Error(std::string("hull_from_points: ") + e.what());
  }
}

Shape mesh_from_triangles(std::vector<Vec3> vertices,
                          std::vector<std::array<std::int32_t, 3>> triangles) {
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (!vertices[i].allFinite())
      throw Error("mesh_from_triangles: vertex " + std::to_string(i) + " is not finite");
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (const std::int32_t v : triangles[t]) {
      if (v < 0 || std::size_t(v) >= vertices.size())
        throw Error("mesh_from_triangles: triangle " + std::to_string(t) + " names vertex " +
                    std::to_string(v) + " of " + std::to_string(vertices.size()));
    }
  }
  try {
    return Shape::triangle_mesh(std::make_shared<const TriangleMesh>(
        TriangleMesh::build(std::move(vertices), std::move(triangles))));
  } catch (const std::exception& e) {
    throw Error(std::string("mesh_from_triangles: ") + e.what());
  }
}

Shape hull_in_frame(std::span<const Vec3> points) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite())
      throw Error("hull_in_frame: point " + std::to_string(i) + " is not finite");
  }
  try {
    return Shape::convex_hull(
        std::make_shared<const ConvexHull>(ConvexHull::from_points(points, false)));
  } catch (const std::exception& e) {
    throw Error(std::string("hull_in_frame: ") + e.what());
  }
}

Shape compound_in_frame(std::vector<CompoundPart> parts) {
  try {
    return Shape::compound_of(std::make_shared<const CompoundShape>(
        CompoundShape::build(std::move(parts), nullptr, false)));
  } catch (const std::exception& e) {
    throw Error(std::string("compound_in_frame: ") + e.what());
  }
}

Shape compound_from_parts(std::vector<CompoundPart> parts, Vec3* centre_of_mass) {
  try {
    return Shape::compound_of(std::make_shared<const CompoundShape>(
        CompoundShape::build(std::move(parts), centre_of_mass)));
  } catch (const std::exception& e) {
    throw Error(std::string("compound_from_parts: ") + e.what());
  }
}

}  // namespace tumble
