// A convex polyhedron built from a point cloud, with the topology the narrow phase needs:
// outward face planes with their vertex loops, unique edges with their two faces, and each
// vertex's neighbours for hill-climbing support queries on big hulls.
//
// Built with Qhull (Barber, Dobkin and Huhdanpaa, "The Quickhull algorithm for convex hulls",
// ACM TOMS 22(4), 1996; Debian's libqhull_r), the one library besides Eigen the collision
// layer links. Coplanar facets are merged into polygons (Qhull's default C-0), so a box read as
// eight points has six square faces.
//
// Mass properties by the divergence theorem: the solid is cut into tetrahedra from an interior
// point to every face triangle, and each tetrahedron's volume, first and second moments are
// exact closed forms (Mirtich, "Fast and Accurate Computation of Polyhedral Mass Properties",
// JGT 1(2), 1996; Eberly, "Polyhedral Mass Properties (Revisited)", 2002; Blow and Binstock,
// "How to find the inertia tensor (or other mass properties) of a 3D solid body", 2004). The
// vertices are then moved so that the centre of mass is the local origin, as for every shape.
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "collision/math.hpp"
#include "collision/shapes/hull_support_scan.hpp"

namespace tumble {

// Thrown for points that have no solid hull: fewer than 4, non-finite, coincident, collinear
// (a needle) or coplanar (flat). The message says which; the scene loader adds file/line/field.
class DegenerateHullError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct HullFace {
  Vec3 normal;          // outward unit normal (local frame)
  Real offset = 0;      // plane: normal . x = offset for points on the face
  int first_index = 0;  // the loop is face_vertices[first_index, first_index + count)
  int count = 0;        // counter-clockwise seen from outside
};

struct HullEdge {
  int vertex[2] = {0, 0};
  int face[2] = {0, 0};  // face[0] has the edge as vertex[0] -> vertex[1] in its loop
};

class ConvexHull {
 public:
  // Builds the hull of `points` (any frame). Throws DegenerateHullError when it has no volume.
  // The result's vertices are re-centred: vertex_local = point - centre_of_mass_offset(), unless
  // `recentre` is false (a training shape, which stays in its body's frame): then they stay as
  // given, and unit_inertia() is still about the hull's own centre of mass.
  static ConvexHull from_points(std::span<const Vec3> points, bool recentre = true);

  std::span<const Vec3> vertices() const { return vertices_; }
  std::span<const HullFace> faces() const { return faces_; }
  std::span<const int> face_vertices() const { return face_vertices_; }
  std::span<const HullEdge> edges() const { return edges_; }
  // Neighbours of vertex v: neighbours()[neighbour_start(v), neighbour_start(v + 1)).
  std::span<const int> neighbours() const { return neighbours_; }
  int neighbour_start(int v) const { return neighbour_start_[std::size_t(v)]; }

  Real volume() const { return volume_; }
  // Inertia tensor per unit mass about the centre of mass, local frame [m^2].
  const Mat3& unit_inertia() const { return unit_inertia_; }
  // Where the centre of mass was in the frame of the input points.
  const Vec3& centre_of_mass_offset() const { return centre_of_mass_offset_; }
  Real bounding_radius() const { return bounding_radius_; }

  // Index of a vertex farthest along `direction`. Small hulls (kHullScanLimit) scan all
  // vertices with SIMD (hull_support_scan.hpp: the first index of the largest value); big ones
  // climb the vertex graph from `start` and move to the first neighbour that
  // is higher (a convex polytope has no local maxima, and the strict increase ends the climb):
  // from a nearby start, as GJK's and EPA's previous support vertices are, that reads fewer
  // neighbours than the steepest step would. Inline, so GJK's and EPA's support calls have no
  // call in their inner loop.
  int support_index(const Vec3& direction, int start = 0) const;
  // The climb alone, whatever the size: for callers whose successive directions are close, so
  // that the start is one or two steps from the answer (the hull SAT's face queries).
  int climb_support_index(const Vec3& direction, int start) const;
  const Vec3& vertex(int i) const { return vertices_[std::size_t(i)]; }
  // The vertices as padded structure-of-arrays blocks (hull_support_scan.hpp); empty above
  // kHullScanLimit vertices.
  HullScanArrays scan_arrays() const {
    if (scan_padded_count_ == 0)
      return {};  // (an empty vector's data() need not be null)
    const Real* x = scan_coordinates_.data();
    const int m = scan_padded_count_;
    return {x, x + m, x + 2 * m, m};
  }

  // The face whose outward normal is most aligned with `direction`.
  int best_face(const Vec3& direction) const;

 private:
  std::vector<Vec3> vertices_;
  std::vector<HullFace> faces_;
  std::vector<int> face_vertices_;
  std::vector<HullEdge> edges_;
  std::vector<int> neighbours_;
  std::vector<int> neighbour_start_;
  // The vertices' x, y and z as three padded blocks, for scan_support.
  std::vector<Real> scan_coordinates_;
  int scan_padded_count_ = 0;
  Real volume_ = 0;
  Mat3 unit_inertia_ = Mat3::Zero();
  Vec3 centre_of_mass_offset_ = Vec3::Zero();
  Real bounding_radius_ = 0;
};

// Hulls up to this many vertices are scanned; bigger ones are climbed. (On the 43-vertex
// benchmark hull the AVX-512 scan is about 1.3x faster per GJK+EPA query than the climb.)
inline constexpr int kHullScanLimit = 64;

inline int ConvexHull::support_index(const Vec3& d, int start) const {
  if (int(vertices_.size()) <= kHullScanLimit)
    return scan_support(scan_arrays(), d);
  return climb_support_index(d, start);
}

inline int ConvexHull::climb_support_index(const Vec3& d, int start) const {
  const int n = int(vertices_.size());
  int current = (start >= 0 && start < n) ? start : 0;
  Real current_value = vertices_[std::size_t(current)].dot(d);
  int k = neighbour_start_[std::size_t(current)];
  int end = neighbour_start_[std::size_t(current) + 1];
  while (k < end) {
    const int v = neighbours_[std::size_t(k)];
    const Real value = vertices_[std::size_t(v)].dot(d);
    if (value > current_value) {
      current = v;
      current_value = value;
      k = neighbour_start_[std::size_t(current)];
      end = neighbour_start_[std::size_t(current) + 1];
    } else {
      ++k;
    }
  }
  return current;
}

}  // namespace tumble
