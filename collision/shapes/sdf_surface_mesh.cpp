// The surface phi = 0 of a signed distance field as triangles, by marching tetrahedra (Doi and
// Koide, "An efficient method of triangulating equi-valued surfaces by using tetrahedral cells",
// IEICE Transactions E74(1), 1991): every cube of a grid is cut into six tetrahedra around its
// main diagonal, and each tetrahedron the surface crosses gives one or two triangles with corners
// where phi changes sign along its edges (linear interpolation). Unlike marching cubes it needs
// no case table and has no ambiguous cases. Normals are the field's gradient at the corners.
#include <array>
#include <cmath>

#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/surface_mesh.hpp"

namespace tumble {
namespace {

// The six tetrahedra of a cube around the diagonal from corner 0 to corner 7 (corner bits: x = 1,
// y = 2, z = 4), each listed with positive orientation.
constexpr std::array<std::array<int, 4>, 6> kTetrahedra{
    {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}}};

struct Corner {
  Vec3 position;
  Real phi;
};

Vec3 crossing(const Corner& a, const Corner& b) {
  const Real t = a.phi / (a.phi - b.phi);
  return a.position + t * (b.position - a.position);
}

void add_triangle(const SdfShape& field, SurfaceMesh& mesh, Vec3 p0, Vec3 p1, Vec3 p2) {
  // Wind outward: the face normal along the field's gradient at the centroid.
  const Vec3 face = (p1 - p0).cross(p2 - p0);
  if (face.squaredNorm() == 0)
    return;
  if (face.dot(field.sample((p0 + p1 + p2) / 3).gradient) < 0)
    std::swap(p1, p2);
  for (const Vec3& p : {p0, p1, p2}) {
    mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
    mesh.positions.push_back(p);
    const Vec3 g = field.sample(p).gradient;
    mesh.normals.push_back(g.squaredNorm() > 0 ? Vec3(g.normalized()) : Vec3(face.normalized()));
  }
}

void polygonize_tetrahedron(const SdfShape& field, const std::array<Corner, 4>& c,
                            SurfaceMesh& mesh) {
  std::array<int, 4> inside{}, outside{};
  int n_in = 0, n_out = 0;
  for (int k = 0; k < 4; ++k) {
    if (c[std::size_t(k)].phi < 0)
      inside[std::size_t(n_in++)] = k;
    else
      outside[std::size_t(n_out++)] = k;
  }
  const auto at = [&](int i, int o) { return crossing(c[std::size_t(i)], c[std::size_t(o)]); };
  if (n_in == 1 || n_in == 3) {
    // One corner apart from the other three: a triangle across its three edges.
    const bool lone_inside = n_in == 1;
    const int lone = lone_inside ? inside[0] : outside[0];
    const std::array<int, 4>& rest = lone_inside ? outside : inside;
    add_triangle(field, mesh, at(lone, rest[0]), at(lone, rest[1]), at(lone, rest[2]));
  } else if (n_in == 2) {
    // Two and two: a quadrilateral across the four edges between the pairs.
    const Vec3 a = at(inside[0], outside[0]);
    const Vec3 b = at(inside[0], outside[1]);
    const Vec3 d = at(inside[1], outside[0]);
    const Vec3 e = at(inside[1], outside[1]);
    add_triangle(field, mesh, a, b, e);
    add_triangle(field, mesh, a, e, d);
  }
}

}  // namespace

SurfaceMesh tessellate_sdf(const SdfShape& field, int cells) {
  SurfaceMesh mesh;
  const Aabb& box = field.local_bounds();
  const Vec3 size = box.max - box.min;
  const Real h = size.maxCoeff() / Real(cells);
  int n[3];
  for (int k = 0; k < 3; ++k)
    n[k] = std::max(1, int(std::ceil(size[k] / h)));
  const auto point = [&](int x, int y, int z) {
    return Vec3(box.min + h * Vec3(Real(x), Real(y), Real(z)));
  };
  // phi at every grid node, computed once.
  const auto node = [&](int x, int y, int z) {
    return std::size_t(x) +
           std::size_t(n[0] + 1) * (std::size_t(y) + std::size_t(n[1] + 1) * std::size_t(z));
  };
  std::vector<Real> phi(std::size_t(n[0] + 1) * std::size_t(n[1] + 1) * std::size_t(n[2] + 1));
  for (int z = 0; z <= n[2]; ++z)
    for (int y = 0; y <= n[1]; ++y)
      for (int x = 0; x <= n[0]; ++x)
        phi[node(x, y, z)] = field.distance(point(x, y, z));
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x) {
        std::array<Corner, 8> cube;
        bool any_in = false, any_out = false;
        for (int k = 0; k < 8; ++k) {
          const int cx = x + (k & 1), cy = y + ((k >> 1) & 1), cz = z + ((k >> 2) & 1);
          cube[std::size_t(k)] = {point(cx, cy, cz), phi[node(cx, cy, cz)]};
          (cube[std::size_t(k)].phi < 0 ? any_in : any_out) = true;
        }
        if (!any_in || !any_out)
          continue;
        for (const auto& t : kTetrahedra)
          polygonize_tetrahedron(field,
                                 {cube[std::size_t(t[0])], cube[std::size_t(t[1])],
                                  cube[std::size_t(t[2])], cube[std::size_t(t[3])]},
                                 mesh);
      }
  return mesh;
}

}  // namespace tumble
