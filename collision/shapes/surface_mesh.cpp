// Tessellations of shapes (collision/shapes/surface_mesh.hpp): surfaces of revolution by latitude
// rings; the generic convex path samples the support map along the vertex directions of a
// subdivided icosahedron (Loop's midpoint subdivision of the icosahedron, each new vertex pushed
// onto the sphere: the "icosphere"), whose connectivity joins the support points; the enclosed
// volume by the divergence theorem (a sum of signed tetrahedra from the origin).
#include "collision/shapes/surface_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/shape.hpp"
#include "collision/shapes/shape_ops.hpp"
#include "collision/shapes/triangle_mesh.hpp"

namespace tumble {
namespace {

void add_triangle(SurfaceMesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  mesh.indices.push_back(a);
  mesh.indices.push_back(b);
  mesh.indices.push_back(c);
}

// A surface of revolution about z made of latitude rings: each ring is a latitude angle and the
// z offset of its centre. A sphere is one run of rings from the south to the north pole; a
// capsule is the same with the southern half moved down and the northern half moved up, so
// that the band between the two equator rings is the cylinder.
struct Ring {
  Real latitude;
  Real z_offset;
};

SurfaceMesh revolve(Real radius, const std::vector<Ring>& rings, int segments) {
  SurfaceMesh mesh;
  const int columns = segments + 1;  // the seam column is duplicated so texture-free rows close
  for (const Ring& ring : rings) {
    const Real c = std::cos(ring.latitude);
    const Real s = std::sin(ring.latitude);
    for (int j = 0; j < columns; ++j) {
      const Real theta = 2 * std::numbers::pi_v<Real> * j / segments;
      const Vec3 n(c * std::cos(theta), c * std::sin(theta), s);
      mesh.normals.push_back(n);
      mesh.positions.push_back(radius * n + Vec3(0, 0, ring.z_offset));
    }
  }
  for (std::size_t i = 0; i + 1 < rings.size(); ++i) {
    for (int j = 0; j < segments; ++j) {
      const auto at = [&](std::size_t row, int column) {
        return static_cast<std::uint32_t>(row * columns + column);
      };
      // Counter-clockwise from outside: along the ring first (theta grows), then up.
      add_triangle(mesh, at(i, j), at(i, j + 1), at(i + 1, j + 1));
      add_triangle(mesh, at(i, j), at(i + 1, j + 1), at(i + 1, j));
    }
  }
  return mesh;
}

std::vector<Ring> hemisphere_rings(int count, Real first, Real last, Real z_offset) {
  std::vector<Ring> rings;
  for (int i = 0; i <= count; ++i)
    rings.push_back({first + (last - first) * i / count, z_offset});
  return rings;
}

}  // namespace

SurfaceMesh tessellate_sphere(Real radius, const TessellationDetail& detail) {
  const int segments = std::max(detail.segments, 6);
  const Real half_pi = std::numbers::pi_v<Real> / 2;
  return revolve(radius, hemisphere_rings(segments / 2, -half_pi, half_pi, 0), segments);
}

SurfaceMesh tessellate_capsule(Real radius, Real half_length, const TessellationDetail& detail) {
  const int segments = std::max(detail.segments, 6);
  const Real half_pi = std::numbers::pi_v<Real> / 2;
  std::vector<Ring> rings = hemisphere_rings(segments / 4, -half_pi, 0, -half_length);
  const std::vector<Ring> north = hemisphere_rings(segments / 4, 0, half_pi, half_length);
  rings.insert(rings.end(), north.begin(), north.end());
  return revolve(radius, rings, segments);
}

SurfaceMesh tessellate_box(const Vec3& half_extents) {
  SurfaceMesh mesh;
  for (int axis = 0; axis < 3; ++axis) {
    for (const Real sign : {Real(-1), Real(1)}) {
      Vec3 n = Vec3::Zero();
      n[axis] = sign;
      // u x v = n, so corners listed -u-v, +u-v, +u+v, -u+v run counter-clockwise from outside.
      Vec3 u = Vec3::Zero();
      Vec3 v = Vec3::Zero();
      u[(axis + 1) % 3] = 1;
      v[(axis + 2) % 3] = 1;
      if (sign < 0)
        std::swap(u, v);
      const auto base = static_cast<std::uint32_t>(mesh.positions.size());
      for (const auto& [su, sv] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
        const Vec3 corner = n + Real(su) * u + Real(sv) * v;
        mesh.positions.push_back(corner.cwiseProduct(half_extents));
        mesh.normals.push_back(n);
      }
      add_triangle(mesh, base, base + 1, base + 2);
      add_triangle(mesh, base, base + 2, base + 3);
    }
  }
  return mesh;
}

void icosphere(int subdivision, std::vector<Vec3>& directions,
               std::vector<std::uint32_t>& indices) {
  const Real t = (1 + std::sqrt(Real(5))) / 2;
  directions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& d : directions)
    d.normalize();
  indices = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
             4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
             6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  for (int level = 0; level < subdivision; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end())
        return found->second;
      const auto index = static_cast<std::uint32_t>(directions.size());
      directions.push_back((directions[a] + directions[b]).normalized());
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<std::uint32_t> finer;
    finer.reserve(indices.size() * 4);
    for (std::size_t i = 0; i < indices.size(); i += 3) {
      const std::uint32_t a = indices[i], b = indices[i + 1], c = indices[i + 2];
      const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      finer.insert(finer.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    indices = std::move(finer);
  }
}

SurfaceMesh tessellate_convex_support(const Shape& shape, const TessellationDetail& detail) {
  if (!shape.is_bounded()) {
    throw std::invalid_argument("cannot tessellate an unbounded " +
                                std::string(shape_type_name(shape.type)) + " shape");
  }
  std::vector<Vec3> directions;
  std::vector<std::uint32_t> triangles;
  icosphere(std::clamp(detail.subdivision, 0, 6), directions, triangles);
  std::vector<Vec3> points(directions.size());
  for (std::size_t i = 0; i < directions.size(); ++i)
    points[i] = support(shape, directions[i]);

  // Smooth shading where the support direction agrees with the facet within this angle.
  const Real smooth_cosine = std::cos(Real(25) * std::numbers::pi_v<Real> / 180);
  const Real scale = bounding_radius(shape);
  const Real min_double_area = Real(1e-10) * scale * scale;
  SurfaceMesh mesh;
  for (std::size_t i = 0; i < triangles.size(); i += 3) {
    std::uint32_t corner[3] = {triangles[i], triangles[i + 1], triangles[i + 2]};
    Vec3 face =
        (points[corner[1]] - points[corner[0]]).cross(points[corner[2]] - points[corner[0]]);
    const Real double_area = face.norm();
    if (!(double_area > min_double_area))
      continue;  // collapsed onto a vertex or an edge of the shape
    face /= double_area;
    if (face.dot(directions[corner[0]] + directions[corner[1]] + directions[corner[2]]) < 0) {
      std::swap(corner[1], corner[2]);
      face = -face;
    }
    for (const std::uint32_t k : corner) {
      mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
      mesh.positions.push_back(points[k]);
      mesh.normals.push_back(directions[k].dot(face) >= smooth_cosine ? directions[k] : face);
    }
  }
  return mesh;
}

SurfaceMesh tessellate_triangle_mesh(const TriangleMesh& source) {
  SurfaceMesh mesh;
  for (int t = 0; t < source.triangle_count(); ++t) {
    for (int k = 0; k < 3; ++k) {
      mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
      mesh.positions.push_back(source.corner(t, k));
      mesh.normals.push_back(source.normal(t));
    }
  }
  return mesh;
}

SurfaceMesh tessellate_compound(const CompoundShape& compound, const TessellationDetail& detail) {
  SurfaceMesh mesh;
  for (const CompoundPart& part : compound.parts()) {
    const SurfaceMesh piece = tessellate(part.shape, detail);
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (std::size_t i = 0; i < piece.positions.size(); ++i) {
      mesh.positions.push_back(part.pose.apply(piece.positions[i]));
      mesh.normals.push_back(part.pose.rotate(piece.normals[i]));
    }
    for (const std::uint32_t index : piece.indices)
      mesh.indices.push_back(base + index);
  }
  return mesh;
}

SurfaceMesh tessellate(const Shape& shape, const TessellationDetail& detail) {
  return shape_ops(shape.type).surface_mesh(shape, detail);
}

Real enclosed_volume(const SurfaceMesh& mesh) {
  Real six_volume = 0;
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    const Vec3& a = mesh.positions[mesh.indices[i]];
    const Vec3& b = mesh.positions[mesh.indices[i + 1]];
    const Vec3& c = mesh.positions[mesh.indices[i + 2]];
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6;
}

}  // namespace tumble
