#include "collision/shapes/convex_hull.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <utility>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace tumble {
namespace {

// Relative size (to the cloud's extent) below which a spread counts as zero: points closer than
// this are coincident, a cloud thinner than this is a needle or flat. Qhull itself would stop
// on such input with a precision error; checking first gives a message a user understands.
constexpr Real kDegenerateRelative = Real(1e-9);

// Tests the cloud and throws with a specific message when it cannot have a volume.
void check_solid(std::span<const Vec3> points) {
  if (points.size() < 4)
    throw DegenerateHullError("a convex hull needs at least 4 points, got " +
                              std::to_string(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite())
      throw DegenerateHullError("hull point " + std::to_string(i) + " is not finite");
  Vec3 lo = points[0];
  Vec3 hi = points[0];
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Real extent = (hi - lo).norm();
  const Real scale = std::max(extent, std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()));
  if (!(extent > kDegenerateRelative * scale) || extent == 0)
    throw DegenerateHullError("hull points are all coincident (no extent)");
  const Real tolerance = kDegenerateRelative * std::max(extent, Real(1e-300));
  // Farthest pair from point 0, then farthest from the line, then from the plane.
  const Vec3 p0 = points[0];
  std::size_t i1 = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    if ((points[i] - p0).squaredNorm() > (points[i1] - p0).squaredNorm())
      i1 = i;
  const Vec3 axis = (points[i1] - p0).normalized();
  std::size_t i2 = 0;
  Real line_distance = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Real d = (points[i] - p0).cross(axis).norm();
    if (d > line_distance) {
      line_distance = d;
      i2 = i;
    }
  }
  if (!(line_distance > tolerance))
    throw DegenerateHullError("hull points are collinear (a needle with no volume)");
  const Vec3 normal = (points[i1] - p0).cross(points[i2] - p0).normalized();
  Real plane_distance = 0;
  for (const Vec3& p : points)
    plane_distance = std::max(plane_distance, std::abs((p - p0).dot(normal)));
  if (!(plane_distance > tolerance))
    throw DegenerateHullError("hull points are coplanar (a flat hull with no volume)");
}

// Runs Qhull and returns, for each merged facet, its outward normal and its vertex indices
// (into `points`, unordered).
struct RawFacet {
  Vec3 normal;
  std::vector<int> vertices;
};

std::vector<RawFacet> run_qhull(std::span<const Vec3> points) {
  std::vector<coordT> coords(points.size() * 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k)
      coords[3 * i + std::size_t(k)] = points[i][k];
  // Qhull reports errors on a stream; capture it so the message can go into the exception.
  char* message = nullptr;
  std::size_t message_size = 0;
  FILE* errors = open_memstream(&message, &message_size);
  qhT qh_storage;
  qhT* qh = &qh_storage;
  QHULL_LIB_CHECK
  qh_zero(qh, errors);
  char options[] = "qhull Qs";  // Qs: search all points for the initial simplex
  const int exit_code =
      qh_new_qhull(qh, 3, int(points.size()), coords.data(), False, options, nullptr, errors);
  std::vector<RawFacet> facets;
  if (exit_code == 0) {
    facetT* facet;
    vertexT* vertex;
    vertexT** vertexp;
    FORALLfacets {
      RawFacet f;
      f.normal = Vec3(facet->normal[0], facet->normal[1], facet->normal[2]);
      FOREACHvertex_(facet->vertices) {
        f.vertices.push_back(qh_pointid(qh, vertex->point));
      }
      facets.push_back(std::move(f));
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int current_long = 0;
  int total_long = 0;
  qh_memfreeshort(qh, &current_long, &total_long);
  std::fclose(errors);
  std::string text = message != nullptr ? std::string(message, message_size) : std::string();
  std::free(message);
  if (exit_code != 0) {
    const std::size_t end = text.find('\n');
    throw DegenerateHullError("Qhull could not build the hull: " + text.substr(0, end));
  }
  return facets;
}

}  // namespace

ConvexHull ConvexHull::from_points(std::span<const Vec3> points, bool recentre) {
  check_solid(points);
  const std::vector<RawFacet> facets = run_qhull(points);

  ConvexHull hull;
  // Keep only the points that are hull vertices, renumbered.
  std::map<int, int> renumber;
  for (const RawFacet& f : facets)
    for (int v : f.vertices)
      renumber.emplace(v, 0);
  for (auto& [original, index] : renumber) {
    index = int(hull.vertices_.size());
    hull.vertices_.push_back(points[std::size_t(original)]);
  }
  const Vec3 inside = [&] {
    Vec3 sum = Vec3::Zero();
    for (const Vec3& v : hull.vertices_)
      sum += v;
    return Vec3(sum / Real(hull.vertices_.size()));
  }();

  // Faces: order each facet's vertices counter-clockwise about its outward normal.
  for (const RawFacet& f : facets) {
    Vec3 normal = f.normal.normalized();
    std::vector<int> loop;
    Vec3 centre = Vec3::Zero();
    for (int v : f.vertices) {
      loop.push_back(renumber[v]);
      centre += hull.vertices_[std::size_t(loop.back())];
    }
    centre /= Real(loop.size());
    if (normal.dot(centre - inside) < 0)
      normal = -normal;
    Vec3 t1;
    Vec3 t2;
    orthonormal_basis(normal, t1, t2);
    std::vector<std::pair<Real, int>> by_angle;
    for (int v : loop) {
      const Vec3 d = hull.vertices_[std::size_t(v)] - centre;
      by_angle.emplace_back(std::atan2(d.dot(t2), d.dot(t1)), v);
    }
    std::sort(by_angle.begin(), by_angle.end());
    HullFace face;
    face.normal = normal;
    face.first_index = int(hull.face_vertices_.size());
    face.count = int(by_angle.size());
    face.offset = -std::numeric_limits<Real>::infinity();
    for (const auto& [angle, v] : by_angle) {
      hull.face_vertices_.push_back(v);
      face.offset = std::max(face.offset, normal.dot(hull.vertices_[std::size_t(v)]));
    }
    hull.faces_.push_back(face);
  }

  // Mass properties: tetrahedra (inside, a, b, c) over a fan of every face.
  Real volume = 0;
  Vec3 first_moment = Vec3::Zero();
  Mat3 covariance = Mat3::Zero();  // integral of x x^T dV, x relative to `inside`
  Mat3 canonical;
  canonical << 2, 1, 1, 1, 2, 1, 1, 1, 2;
  canonical /= Real(120);
  for (const HullFace& face : hull.faces_) {
    const auto at = [&](int k) {
      return Vec3(
          hull.vertices_[std::size_t(hull.face_vertices_[std::size_t(face.first_index + k)])] -
          inside);
    };
    for (int k = 1; k + 1 < face.count; ++k) {
      Mat3 a;
      a.col(0) = at(0);
      a.col(1) = at(k);
      a.col(2) = at(k + 1);
      const Real det = a.determinant();
      volume += det / 6;
      first_moment += det / 24 * (a.col(0) + a.col(1) + a.col(2));
      covariance += det * a * canonical * a.transpose();
    }
  }
  if (!(volume > 0))
    throw DegenerateHullError("hull has no volume");
  const Vec3 centroid = first_moment / volume;  // relative to `inside`
  const Mat3 central = covariance - volume * centroid * centroid.transpose();
  const Mat3 inertia = Mat3::Identity() * central.trace() - central;
  hull.volume_ = volume;
  hull.unit_inertia_ = inertia / volume;
  hull.unit_inertia_ = Real(0.5) * (hull.unit_inertia_ + hull.unit_inertia_.transpose()).eval();
  hull.centre_of_mass_offset_ = inside + centroid;

  // Re-centre on the centre of mass.
  if (recentre)
    for (Vec3& v : hull.vertices_)
      v -= hull.centre_of_mass_offset_;
  for (HullFace& face : hull.faces_) {
    face.offset = -std::numeric_limits<Real>::infinity();
    for (int k = 0; k < face.count; ++k)
      face.offset = std::max(
          face.offset,
          face.normal.dot(
              hull.vertices_[std::size_t(hull.face_vertices_[std::size_t(face.first_index + k)])]));
  }
  for (const Vec3& v : hull.vertices_)
    hull.bounding_radius_ = std::max(hull.bounding_radius_, v.norm());

  // Structure-of-arrays copy for the SIMD support scan, padded with vertex 0.
  const int count = int(hull.vertices_.size());
  if (count <= kHullScanLimit) {
    const int padded = (count + kHullScanWidth - 1) / kHullScanWidth * kHullScanWidth;
    hull.scan_padded_count_ = padded;
    hull.scan_coordinates_.assign(std::size_t(3 * padded), 0);
    for (int i = 0; i < padded; ++i)
      for (int k = 0; k < 3; ++k)
        hull.scan_coordinates_[std::size_t(k * padded + i)] =
            hull.vertices_[std::size_t(i < count ? i : 0)][k];
  }

  // Edges: each directed loop edge meets its reverse in the neighbouring face.
  std::map<std::pair<int, int>, int> directed_face;
  for (int f = 0; f < int(hull.faces_.size()); ++f) {
    const HullFace& face = hull.faces_[std::size_t(f)];
    for (int k = 0; k < face.count; ++k) {
      const int v0 = hull.face_vertices_[std::size_t(face.first_index + k)];
      const int v1 = hull.face_vertices_[std::size_t(face.first_index + (k + 1) % face.count)];
      directed_face[{v0, v1}] = f;
    }
  }
  std::vector<std::vector<int>> adjacent(hull.vertices_.size());
  for (const auto& [key, f] : directed_face) {
    if (key.first > key.second)
      continue;
    HullEdge edge;
    edge.vertex[0] = key.first;
    edge.vertex[1] = key.second;
    edge.face[0] = f;
    const auto reverse = directed_face.find({key.second, key.first});
    edge.face[1] = reverse != directed_face.end() ? reverse->second : f;
    hull.edges_.push_back(edge);
    adjacent[std::size_t(key.first)].push_back(key.second);
    adjacent[std::size_t(key.second)].push_back(key.first);
  }
  for (const auto& [key, f] : directed_face) {
    // An edge whose reverse only appears as (larger, smaller) was skipped above; add it.
    if (key.first > key.second &&
        directed_face.find({key.second, key.first}) == directed_face.end()) {
      HullEdge edge;
      edge.vertex[0] = key.first;
      edge.vertex[1] = key.second;
      edge.face[0] = edge.face[1] = f;
      hull.edges_.push_back(edge);
      adjacent[std::size_t(key.first)].push_back(key.second);
      adjacent[std::size_t(key.second)].push_back(key.first);
    }
  }
  for (const auto& list : adjacent) {
    hull.neighbour_start_.push_back(int(hull.neighbours_.size()));
    hull.neighbours_.insert(hull.neighbours_.end(), list.begin(), list.end());
  }
  hull.neighbour_start_.push_back(int(hull.neighbours_.size()));
  return hull;
}

int ConvexHull::best_face(const Vec3& direction) const {
  int best = 0;
  Real best_value = -std::numeric_limits<Real>::infinity();
  for (int f = 0; f < int(faces_.size()); ++f) {
    const Real value = faces_[std::size_t(f)].normal.dot(direction);
    if (value > best_value) {
      best_value = value;
      best = f;
    }
  }
  return best;
}

}  // namespace tumble
