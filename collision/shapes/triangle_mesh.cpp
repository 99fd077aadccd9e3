#include "collision/shapes/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace tumble {
namespace {

// Neighbouring faces whose normals differ by less than this angle count as one flat surface
// [rad]: a grid floor written with rounded coordinates is still flat.
constexpr Real kFlatAngle = Real(1e-3);
constexpr int kLeafSize = 4;
constexpr int kBins = 16;

Real surface_area(const Aabb& b) {
  const Vec3 e = (b.max - b.min).cwiseMax(Vec3::Zero());
  return 2 * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
}

}  // namespace

TriangleMesh TriangleMesh::build(std::vector<Vec3> vertices, std::vector<Triangle> triangles) {
  if (triangles.empty())
    throw MeshError("a mesh needs at least one triangle");
  const std::int64_t n = std::int64_t(vertices.size());
  Aabb bounds;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (!vertices[i].allFinite())
      throw MeshError("vertex " + std::to_string(i) + " is not finite");
    bounds.grow(vertices[i]);
  }
  const Real size = vertices.empty() ? Real(0) : (bounds.max - bounds.min).norm();
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Triangle& tri = triangles[t];
    const std::string name = "triangle " + std::to_string(t);
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= n)
        throw MeshError(name + " has vertex index " + std::to_string(tri[k]) +
                        " out of range (the mesh has " + std::to_string(n) + " vertices)");
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      throw MeshError(name + " repeats a vertex");
    const Vec3 cross =
        (vertices[tri[1]] - vertices[tri[0]]).cross(vertices[tri[2]] - vertices[tri[0]]);
    if (!(cross.norm() > Real(1e-12) * size * size))
      throw MeshError(name + " has zero area (its corners are collinear or coincide)");
  }

  TriangleMesh mesh;
  mesh.vertices_ = std::move(vertices);
  mesh.triangles_ = std::move(triangles);
  mesh.bounds_ = bounds;
  mesh.normals_.reserve(mesh.triangles_.size());
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const Vec3 cross =
        (mesh.corner(t, 1) - mesh.corner(t, 0)).cross(mesh.corner(t, 2) - mesh.corner(t, 0));
    mesh.normals_.push_back(cross.normalized());
  }
  for (const Vec3& v : mesh.vertices_)
    mesh.bounding_radius_ = std::max(mesh.bounding_radius_, v.norm());
  mesh.build_adjacency();
  mesh.build_hierarchy();
  mesh.compute_mass_properties();
  return mesh;
}

void TriangleMesh::build_adjacency() {
  // Edges keyed by their sorted vertex pair; each holds the triangles (and their edge slot) that
  // use it. std::map keeps the build deterministic.
  struct Use {
    std::int32_t triangle;
    int edge;
  };
  std::map<std::pair<std::int32_t, std::int32_t>, std::vector<Use>> edges;
  for (int t = 0; t < triangle_count(); ++t) {
    for (int e = 0; e < 3; ++e) {
      const std::int32_t i = triangles_[t][e];
      const std::int32_t j = triangles_[t][(e + 1) % 3];
      edges[{std::min(i, j), std::max(i, j)}].push_back({t, e});
    }
  }
  edge_kinds_.assign(triangles_.size(),
                     {EdgeKind::boundary, EdgeKind::boundary, EdgeKind::boundary});
  closed_ = true;
  const Real flat_cos = std::cos(kFlatAngle);
  for (const auto& [key, uses] : edges) {
    if (uses.size() > 2)
      throw MeshError("the edge between vertices " + std::to_string(key.first) + " and " +
                      std::to_string(key.second) + " is shared by " + std::to_string(uses.size()) +
                      " triangles (at most 2 allowed)");
    if (uses.size() == 1) {
      closed_ = false;
      continue;
    }
    const Use& u = uses[0];
    const Use& v = uses[1];
    // Consistent orientation: the two triangles run the shared edge in opposite directions.
    if (triangles_[u.triangle][u.edge] == triangles_[v.triangle][v.edge])
      closed_ = false;
    const Vec3& nu = normals_[u.triangle];
    const Vec3& nv = normals_[v.triangle];
    EdgeKind kind = EdgeKind::flat;
    if (nu.dot(nv) < flat_cos) {
      // The neighbour's far corner below u's plane means a ridge (convex), above a valley.
      const Vec3 far = corner(v.triangle, (v.edge + 2) % 3);
      const Real height = nu.dot(far - corner(u.triangle, 0));
      kind = height < 0 ? EdgeKind::convex : EdgeKind::concave;
    }
    edge_kinds_[u.triangle][u.edge] = kind;
    edge_kinds_[v.triangle][v.edge] = kind;
  }
  // A corner is active when any edge through that vertex (in any triangle) is a boundary or
  // convex edge.
  std::vector<char> vertex_active(vertices_.size(), 0);
  for (int t = 0; t < triangle_count(); ++t) {
    for (int e = 0; e < 3; ++e) {
      const EdgeKind kind = edge_kinds_[t][e];
      if (kind == EdgeKind::boundary || kind == EdgeKind::convex) {
        vertex_active[triangles_[t][e]] = 1;
        vertex_active[triangles_[t][(e + 1) % 3]] = 1;
      }
    }
  }
  active_corners_.resize(triangles_.size());
  for (int t = 0; t < triangle_count(); ++t)
    for (int k = 0; k < 3; ++k)
      active_corners_[t][k] = vertex_active[triangles_[t][k]] != 0;
}

void TriangleMesh::build_hierarchy() {
  const int count = triangle_count();
  std::vector<Aabb> boxes(count);
  std::vector<Vec3> centres(count);
  for (int t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k)
      boxes[t].grow(corner(t, k));
    centres[t] = (boxes[t].min + boxes[t].max) * Real(0.5);
  }
  leaf_triangles_.resize(count);
  for (int t = 0; t < count; ++t)
    leaf_triangles_[t] = t;
  nodes_.clear();
  nodes_.reserve(2 * std::size_t(count));

  // Recursive on the triangle range [begin, end); returns the node index.
  struct Builder {
    TriangleMesh& mesh;
    const std::vector<Aabb>& boxes;
    const std::vector<Vec3>& centres;

    std::int32_t build(int begin, int end, int depth) {
      const std::int32_t index = std::int32_t(mesh.nodes_.size());
      mesh.nodes_.push_back({});
      Aabb bounds;
      Aabb centre_bounds;
      for (int i = begin; i < end; ++i) {
        bounds.grow(boxes[mesh.leaf_triangles_[i]]);
        centre_bounds.grow(centres[mesh.leaf_triangles_[i]]);
      }
      mesh.nodes_[index].bounds = bounds;
      const int n = end - begin;
      const int split =
          n > kLeafSize && depth < kMaxDepth ? choose_split(begin, end, centre_bounds) : -1;
      if (split < 0) {
        mesh.nodes_[index].first = begin;
        mesh.nodes_[index].count = n;
        return index;
      }
      build(begin, split, depth + 1);
      const std::int32_t right = build(split, end, depth + 1);
      mesh.nodes_[index].first = right;
      mesh.nodes_[index].count = 0;
      return index;
    }

    // Binned SAH over the widest centroid axis; partitions the range and returns the split
    // index, or a median split when all centroids share one bin, or -1 for identical centroids.
    int choose_split(int begin, int end, const Aabb& centre_bounds) {
      const Vec3 extent = centre_bounds.max - centre_bounds.min;
      int axis = 0;
      for (int k = 1; k < 3; ++k)
        if (extent[k] > extent[axis])
          axis = k;
      auto* first = mesh.leaf_triangles_.data() + begin;
      auto* last = mesh.leaf_triangles_.data() + end;
      if (!(extent[axis] > 0))
        return -1;
      const Real lo = centre_bounds.min[axis];
      const Real scale = kBins / extent[axis];
      const auto bin_of = [&](std::int32_t t) {
        return std::min(kBins - 1, int((centres[t][axis] - lo) * scale));
      };
      std::array<Aabb, kBins> bin_bounds;
      std::array<int, kBins> bin_count{};
      for (auto* p = first; p != last; ++p) {
        const int b = bin_of(*p);
        bin_bounds[b].grow(boxes[*p]);
        ++bin_count[b];
      }
      // Cost of splitting after bin s: left area * left count + right area * right count.
      std::array<Real, kBins - 1> left_cost{};
      Aabb acc;
      int acc_count = 0;
      for (int s = 0; s < kBins - 1; ++s) {
        acc.grow(bin_bounds[s]);
        acc_count += bin_count[s];
        left_cost[s] = acc_count > 0 ? surface_area(acc) * acc_count : 0;
      }
      acc = Aabb{};
      acc_count = 0;
      int best = -1;
      Real best_cost = std::numeric_limits<Real>::infinity();
      for (int s = kBins - 2; s >= 0; --s) {
        acc.grow(bin_bounds[s + 1]);
        acc_count += bin_count[s + 1];
        const int left_count = (end - begin) - acc_count;
        if (left_count == 0 || acc_count == 0)
          continue;
        const Real cost = left_cost[s] + surface_area(acc) * acc_count;
        if (cost < best_cost) {
          best_cost = cost;
          best = s;
        }
      }
      if (best < 0) {
        // Median split on the axis (stable, so the build is deterministic).
        auto* mid = first + (end - begin) / 2;
        std::nth_element(first, mid, last, [&](std::int32_t x, std::int32_t y) {
          return centres[x][axis] < centres[y][axis] ||
                 (centres[x][axis] == centres[y][axis] && x < y);
        });
        return begin + (end - begin) / 2;
      }
      auto* mid =
          std::stable_partition(first, last, [&](std::int32_t t) { return bin_of(t) <= best; });
      return begin + int(mid - first);
    }
  };
  Builder builder{*this, boxes, centres};
  builder.build(0, count, 0);
}

void TriangleMesh::compute_mass_properties() {
  if (!closed_)
    return;
  // Integrals of 1, x, y, z, x^2, y^2, z^2, xy, yz, zx over the solid as a sum over signed
  // tetrahedra (origin, a, b, c) (Eberly 2002; Tonon, "Explicit exact formulas for the 3-D
  // tetrahedron inertia tensor", J. Math. Stat. 2005). For a tetrahedron with corners 0, a, b,
  // c and determinant d = a . (b x c): volume d/6, first moment d/24 (a+b+c), and the second
  // moment of coordinates i, j is d/120 (sum over corners of p_i p_j + (sum p_i)(sum p_j)).
  Real v6 = 0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();  // integral of p p^T
  for (int t = 0; t < triangle_count(); ++t) {
    const Vec3 a = corner(t, 0);
    const Vec3 b = corner(t, 1);
    const Vec3 c = corner(t, 2);
    const Real d = a.dot(b.cross(c));
    v6 += d;
    const Vec3 sum = a + b + c;
    first += d * sum;
    second +=
        d * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
  }
  const Real vol = v6 / 6;
  if (!(vol > 0)) {
    // Inside-out or flat: not a solid with a usable volume.
    closed_ = false;
    return;
  }
  volume_ = vol;
  centroid_ = first / 24 / vol;
  const Mat3 covariance = second / 120 / vol - centroid_ * centroid_.transpose();  // per unit mass
  unit_inertia_ = Mat3::Identity() * covariance.trace() - covariance;
}

Aabb TriangleMesh::world_aabb(const Transform& pose) const {
  const Vec3 centre = (bounds_.min + bounds_.max) * Real(0.5);
  const Vec3 half = (bounds_.max - bounds_.min) * Real(0.5);
  const Vec3 c = pose.apply(centre);
  const Vec3 e = pose.rotation.toRotationMatrix().cwiseAbs() * half;
  return {c - e, c + e};
}

Vec3 TriangleMesh::support(const Vec3& direction) const {
  Vec3 best = vertices_.empty() ? Vec3::Zero() : vertices_[0];
  Real best_dot = best.dot(direction);
  for (const Vec3& v : vertices_) {
    const Real d = v.dot(direction);
    if (d > best_dot) {
      best_dot = d;
      best = v;
    }
  }
  return best;
}

}  // namespace tumble
