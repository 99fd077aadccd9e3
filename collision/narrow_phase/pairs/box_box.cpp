// Box against box.
//
// Axis: the separating-axis test over the 15 candidate axes of two oriented boxes, the 3 + 3 face
// normals and the 9 cross products of edge directions, in the form of Gottschalk, Lin and Manocha,
// "OBBTree: A Hierarchical Structure for Rapid Interference Detection", SIGGRAPH 1996 (and Ericson,
// Real-Time Collision Detection, 2005, 4.4.1): everything is expressed in A's frame, where B's axes
// are the columns of R = Ra^T Rb and B's centre is t, so each axis costs a few products of entries
// of R, |R| and t instead of two matrix-vector products. All fifteen are computed without a branch
// on the data and then tested once against the margin (a branch per axis would be mispredicted
// about half the time, which costs more than the arithmetic it saves). For the edge axis a_i x b_j
// the length |a_i x b_j| = sqrt(R(i+1, j)^2 + R(i+2, j)^2) has no cancellation, so the separation
// is exact up to rounding; axes shorter than kMinCrossSine (near-parallel edges) are skipped
// instead of padding |R| with an epsilon as the paper does, because the face axes cover them and
// the padding would bias every reported depth. Face axes win over edge axes, and A's faces over
// B's, unless the other is clearly more separated (clearly_more_separated in pairs.hpp; Gregorius,
// "The Separating Axis Test between Convex Polyhedra", GDC 2013, biases the same way), so the
// manifold does not flip between features from rounding.
//
// Points, face axis: the face of the other box most anti-parallel to the reference face's normal is
// the incident face; it is clipped against the four side planes of the reference face
// (Sutherland-Hodgman; Ericson 8.3.4; Catto, "Contact Manifolds", GDC 2007). The clipping runs in
// the reference box's own frame, where the side planes are coordinate bounds, and only the kept
// points go back to the pair frame. Every clipped point below the reference face, or above it by
// less than the margin, is kept with its depth measured along the normal; more than four are
// reduced by manifold_reduction. Each clipped point carries the features that made it: an incident
// vertex inside the reference face, an incident edge crossing a reference side edge, or a reference
// corner inside the incident face.
//
// Points, edge axis: one point at the closest points of the two edges that are extreme along the
// axis (Ericson 5.1.9), computed in A's frame.
//
// Apart but within the margin, the separation along the best axis can be smaller than the true
// distance (two boxes corner to corner). The axis is kept at once when its own points show that it
// realises the distance (a clipped incident point, or the closest points of the two edges, as far
// apart as the separation: the distance is at least the separation and at most that). Otherwise the
// exact closest features are found by brute force over the 8 + 8 corners against the other box and
// the 12 x 12 edge pairs; an axis is kept when it realises that distance (face-face, face-edge and
// edge-edge contacts), otherwise the single closest pair is the point and its direction the normal.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "collision/narrow_phase/pairs/manifold_reduction.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"

namespace tumble::detail {
namespace {

// Cross products of edge directions shorter than this (sine of the angle between the edges) are not
// tested: their direction would be mostly rounding.
constexpr Real kMinCrossSine = Real(1e-6);
// A separating axis "realises" the distance of boxes that are apart when its separation is within
// this fraction of the pair's size of the exact distance.
constexpr Real kRealisesDistanceTolerance = Real(1e-9);
// closest_features skips an edge pair whose bounding spheres are farther apart than the closest
// distance found by more than this share of the pair's size.
constexpr Real kCullBand = Real(1e-9);

// The pair seen from A's frame (Gottschalk et al. 1996, section 5): B's axes are the columns of r,
// B's centre is t.
struct PairInA {
  Vec3 centre_a;
  Vec3 centre_b;
  Mat3 axes_a;  // columns: A's axes in the pair frame
  Quat rotation_b;
  Vec3 half_a;
  Vec3 half_b;
  Mat3 r;      // r(i, j) = a_i . b_j
  Mat3 abs_r;  // |r(i, j)|
  Vec3 t;      // centre_b - centre_a in A's frame

  Mat3 axes_b() const { return rotation_b.toRotationMatrix(); }  // B's axes in the pair frame
};

enum class AxisKind { face_of_a, face_of_b, edges };

struct Axis {
  AxisKind kind = AxisKind::face_of_a;
  int index_a = 0;                   // A's face axis, or A's edge direction
  int index_b = 0;                   // B's face axis, or B's edge direction
  Vec3 normal_in_a = Vec3::UnitZ();  // edge axes: unit, from B to A, in A's frame
  Real separation = -std::numeric_limits<Real>::infinity();
};

// ---- Clipping, in the reference box's frame
// ---------------------------------------------------

// Sutherland-Hodgman on a quadrilateral against four planes adds at most one vertex per plane; the
// slack covers rounding at grazing angles. The vertices live in one pool that only grows (the
// incident corners, then every crossing a pass makes), and a pass turns one loop of pool indices
// into the next: a vertex that stays costs one index, not a copy. A pass writes each index
// unconditionally and counts only those that stay (no branch on the geometry), so a loop holds two
// entries per input vertex; a pass adds at most one crossing per input vertex to the pool.
constexpr int kMaxClipVertices = 16;

// Coordinates in the reference face's frame: u and v along the reference box's axes (axis + 1) % 3
// and (axis + 2) % 3, h along the face's axis. Side s of the face bounds u (s = 0: u <= half_u, s =
// 1: -u <= half_u) or v (s = 2, 3). Fields are separate arrays, so that every value is read with
// the width it was written with (store-to-load forwarding).
struct ClipVertices {
  static constexpr int kCapacity = 4 + 4 * kMaxClipVertices;
  std::array<std::array<Real, kCapacity>, 3> coordinate;  // [u, v, h][vertex]
  std::array<std::uint16_t, kCapacity> incident_feature;
  std::array<std::uint16_t, kCapacity> reference_feature;
  // The polygon edge that leaves a vertex runs along an incident box edge (`outgoing_edge`) or,
  // after a clip, along a reference side plane (`outgoing_side` >= 0).
  std::array<std::uint16_t, kCapacity> outgoing_edge;
  std::array<std::int8_t, kCapacity> outgoing_side;
  int count = 0;
};

struct ClipLoop {
  std::array<std::uint8_t, 2 * kMaxClipVertices> vertex;  // indices into ClipVertices
  int count = 0;
};

// The reference face: face `axis` of the reference box on the `positive` side, with the feature ids
// of its sides and corners worked out once.
struct ReferenceFace {
  int axis;
  bool positive;
  Real half_u;
  Real half_v;
  Real half_h;
  std::uint16_t face_feature;
  std::array<std::uint16_t, 4> side_edge;  // the edge of the face in side plane s
  std::array<int, 4> side_bit;             // the vertex sign bit that side s sets

  ReferenceFace(int face_axis, bool face_positive, const Vec3& half)
      : axis(face_axis), positive(face_positive) {
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    half_u = half[u];
    half_v = half[v];
    half_h = half[axis];
    face_feature = feature::box_face(axis, positive);
    const int face_bit = positive ? 1 << axis : 0;
    for (int s = 0; s < 4; ++s) {
      const int tangent = s < 2 ? u : v;
      side_bit[s] = s % 2 == 0 ? 1 << tangent : 0;
      side_edge[s] = feature::box_edge(3 - axis - tangent, face_bit | side_bit[s]);
    }
  }
  // The corner of the face where side planes `s` and `t` meet (the face itself when they are
  // parallel).
  std::uint16_t corner(int s, int t) const {
    const int face_bit = positive ? 1 << axis : 0;
    const std::uint16_t vertex = feature::box_vertex(face_bit | side_bit[s] | side_bit[t]);
    return s / 2 == t / 2 ? face_feature : vertex;
  }
  // Height of a point above the face.
  Real height(Real h) const { return (positive ? h : -h) - half_h; }
};

// The incident box in the reference box's frame.
struct IncidentBox {
  Vec3 centre;
  Mat3 axes;  // columns
  Vec3 half;
};

// The incident face (the face most anti-parallel to the reference normal) as a polygon in the
// reference face's coordinates.
void incident_face(const IncidentBox& box, const ReferenceFace& reference,
                   std::uint16_t& face_feature, ClipVertices& vertices, ClipLoop& polygon) {
  // The normal's component along incident axis k is axes(reference.axis, k) (up to its sign).
  int axis = 0;
  Real best = -1;
  for (int k = 0; k < 3; ++k) {
    const Real alignment = std::abs(box.axes(reference.axis, k));
    if (alignment > best) {
      best = alignment;
      axis = k;
    }
  }
  const Real along_normal = box.axes(reference.axis, axis);
  const bool positive = reference.positive ? along_normal < 0 : along_normal > 0;
  face_feature = feature::box_face(axis, positive);
  const int a = (axis + 1) % 3;
  const int b = (axis + 2) % 3;
  const Vec3 face_centre =
      box.centre + box.axes.col(axis) * (positive ? box.half[axis] : -box.half[axis]);
  const Vec3 along_a = box.axes.col(a) * box.half[a];
  const Vec3 along_b = box.axes.col(b) * box.half[b];
  // Corners in cyclic order (+a,+b), (-a,+b), (-a,-b), (+a,-b); edges alternate along a, b.
  const int face_bits = positive ? 1 << axis : 0;
  const std::array<Vec3, 4> corners = {
      face_centre + along_a + along_b, face_centre - along_a + along_b,
      face_centre - along_a - along_b, face_centre + along_a - along_b};
  constexpr std::array<int, 4> a_positive = {1, 0, 0, 1};
  constexpr std::array<int, 4> b_positive = {1, 1, 0, 0};
  const int u = (reference.axis + 1) % 3;
  const int v = (reference.axis + 2) % 3;
  vertices.count = 4;
  polygon.count = 4;
  for (int i = 0; i < 4; ++i) {
    const int bits = face_bits | (a_positive[i] << a) | (b_positive[i] << b);
    const int edge_direction = i % 2 == 0 ? a : b;
    vertices.coordinate[0][i] = corners[i][u];
    vertices.coordinate[1][i] = corners[i][v];
    vertices.coordinate[2][i] = corners[i][reference.axis];
    vertices.incident_feature[i] = feature::box_vertex(bits);
    vertices.reference_feature[i] = reference.face_feature;
    vertices.outgoing_edge[i] = feature::box_edge(edge_direction, bits);
    vertices.outgoing_side[i] = -1;
    polygon.vertex[i] = std::uint8_t(i);
  }
}

// GCC 12 cannot follow `count` through the passes below and warns that the buffers may be read
// uninitialised (-Wmaybe-uninitialized, a false positive: every entry below `count` was written by
// incident_face or by the previous pass).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

// One Sutherland-Hodgman pass against side plane `side` (a template, so that the coordinate and the
// sign are constants). Returns false, leaving `out` untouched, when every vertex is inside.
template <int side>
bool clip_against_side(ClipVertices& vertices, const ClipLoop& in, const ReferenceFace& reference,
                       std::uint16_t incident_face_feature, ClipLoop& out) {
  constexpr int across_index = side / 2;
  constexpr Real sign = side % 2 == 0 ? Real(1) : Real(-1);
  const Real bound = side < 2 ? reference.half_u : reference.half_v;
  auto& coordinate = vertices.coordinate;
  const auto& across = coordinate[across_index];
  const int count_in = std::min(in.count, kMaxClipVertices);
  // How far each vertex lies outside the side plane (inside when <= 0).
  std::array<Real, kMaxClipVertices> distance;
  Real farthest_out = -std::numeric_limits<Real>::infinity();
  for (int i = 0; i < count_in; ++i) {
    distance[i] = sign * across[in.vertex[i]] - bound;
    farthest_out = std::max(farthest_out, distance[i]);
  }
  if (farthest_out <= 0)
    return false;

  // The new loop: each vertex inside, and after it a new vertex where the edge to the next one
  // crosses the plane. Only indices are written here; the crossings (two, for a convex polygon)
  // are computed after the loop, so that the division and the interpolation run once per
  // crossing rather than once per vertex.
  const int first_new = vertices.count;
  std::array<std::uint8_t, kMaxClipVertices> crossing_edge;
  int count = 0;
  int crossing_count = 0;
  for (int i = 0; i < count_in; ++i) {
    const int next = i + 1 == count_in ? 0 : i + 1;
    const bool p_inside = distance[i] <= 0;
    const bool crosses = p_inside != (distance[next] <= 0);
    out.vertex[count] = in.vertex[i];
    count += p_inside;
    out.vertex[count] = std::uint8_t(first_new + crossing_count);
    crossing_edge[crossing_count] = std::uint8_t(i);
    count += crosses;
    crossing_count += crosses;
  }
  out.count = count;

  const std::uint16_t side_edge = reference.side_edge[side];
  for (int m = 0; m < crossing_count; ++m) {
    // Edge from p to q, the next vertex.
    const int i = crossing_edge[m];
    const int next = i + 1 == count_in ? 0 : i + 1;
    const int p = in.vertex[i];
    const int q = in.vertex[next];
    const int c = first_new + m;
    const Real distance_p = distance[i];
    const Real fraction = distance_p / (distance_p - distance[next]);
    for (int k = 0; k < 3; ++k)
      coordinate[k][c] = coordinate[k][p] + (coordinate[k][q] - coordinate[k][p]) * fraction;
    // An incident edge crossing a side of the reference face, or a stretch along an earlier side
    // plane crossing this one: a reference corner.
    const int p_side = vertices.outgoing_side[p];
    const bool along_incident_edge = p_side < 0;
    vertices.incident_feature[c] =
        along_incident_edge ? vertices.outgoing_edge[p] : incident_face_feature;
    vertices.reference_feature[c] =
        along_incident_edge ? side_edge : reference.corner(p_side < 0 ? 0 : p_side, side);
    vertices.outgoing_edge[c] = vertices.outgoing_edge[p];
    // Leaving the prism, the polygon now runs along this side plane to where it comes back in;
    // entering it, it continues along p's edge.
    vertices.outgoing_side[c] = std::int8_t(distance_p <= 0 ? side : p_side);
  }
  vertices.count = first_new + crossing_count;
  return true;
}

// Face contact: the reference face is A's (reference_is_a) or B's, its axis `reference_axis`.
// Writes the points into `out` (pair frame) and returns their count; `closest_height` gets the
// smallest height above the reference face of any clipped point (infinity when none is left).
int face_contacts(const PairInA& pair, bool reference_is_a, int reference_axis, Real margin,
                  Manifold& out, Real& closest_height) {
  IncidentBox incident;
  if (reference_is_a) {
    incident = {pair.t, pair.r, pair.half_b};
  } else {
    // A in B's frame: its axes are the rows of r, its centre -r^T t.
    incident = {-(pair.r.transpose() * pair.t), pair.r.transpose(), pair.half_a};
  }
  const ReferenceFace reference(reference_axis, incident.centre[reference_axis] >= 0,
                                reference_is_a ? pair.half_a : pair.half_b);
  std::uint16_t incident_face_feature = 0;
  // Clip back and forth between two loops over one pool of vertices. Only entries below the counts
  // are ever read, and every pass writes those first; zeroing them per query to tell the compiler
  // so would cost more than the clipping.
  ClipVertices vertices;
  ClipLoop loops[2];
  ClipLoop* polygon = &loops[0];
  ClipLoop* scratch = &loops[1];
  incident_face(incident, reference, incident_face_feature, vertices, *polygon);
  const auto clip = [&](auto pass) {
    if (polygon->count > 0 && pass(vertices, *polygon, reference, incident_face_feature, *scratch))
      std::swap(polygon, scratch);
  };
  clip(clip_against_side<0>);
  clip(clip_against_side<1>);
  clip(clip_against_side<2>);
  clip(clip_against_side<3>);

  // The manifold normal (from B to A) is -+ the reference face's outward normal; in the reference
  // frame it is +-e_axis. The contact plane's coordinates are (u, v), or (v, u), so that their
  // cross product is the manifold normal, as reduce_manifold measures areas.
  const Real face_sign = reference.positive ? Real(1) : Real(-1);
  const Real normal_sign = reference_is_a ? -face_sign : face_sign;
  const int first_planar = normal_sign > 0 ? 0 : 1;

  std::array<PlanarCandidate, kMaxClipVertices> candidates;
  std::array<int, kMaxClipVertices> sources;  // indices into `vertices`
  int candidate_count = 0;
  closest_height = std::numeric_limits<Real>::infinity();
  const auto add_candidate = [&](int vertex, Real separation) {
    candidates[candidate_count] = {vertices.coordinate[first_planar][vertex],
                                   vertices.coordinate[1 - first_planar][vertex], -separation};
    sources[candidate_count++] = vertex;
  };
  const int clipped_count = std::min(polygon->count, kMaxClipVertices);
  for (int i = 0; i < clipped_count; ++i) {
    // Height of the incident point above the reference face; depth is its negative.
    const int vertex = polygon->vertex[i];
    const Real separation = reference.height(vertices.coordinate[2][vertex]);
    closest_height = std::min(closest_height, separation);
    if (-separation >= -margin)
      add_candidate(vertex, separation);
  }
  if (candidate_count == 0) {
    // Rounding clipped everything away, or the clipped face lies above the margin while a corner
    // outside the reference face is deep (a face kept by the hysteresis over a slightly better edge
    // axis): keep the deepest incident corner (the pool's first four vertices), so that boxes that
    // touch never go without a point.
    int deepest = 0;
    for (int i = 1; i < 4; ++i) {
      if (reference.height(vertices.coordinate[2][i]) <
          reference.height(vertices.coordinate[2][deepest])) {
        deepest = i;
      }
    }
    const Real separation = reference.height(vertices.coordinate[2][deepest]);
    if (-separation >= -margin)
      add_candidate(deepest, separation);
  }

  const Vec3& reference_centre = reference_is_a ? pair.centre_a : pair.centre_b;
  const Mat3 reference_axes = reference_is_a ? pair.axes_a : pair.axes_b();
  out.normal = reference_axes.col(reference_axis) * normal_sign;
  const int u = (reference_axis + 1) % 3;
  const int v = (reference_axis + 2) % 3;
  std::array<int, kMaxManifoldPoints> kept{};
  const int kept_count =
      reduce_planar_manifold(std::span(candidates.data(), std::size_t(candidate_count)), kept);
  for (int i = 0; i < kept_count; ++i) {
    const int vertex = sources[kept[i]];
    const Real depth = candidates[kept[i]].depth;
    // Midway between the incident point and its projection onto the reference face.
    Vec3 midway;
    midway[u] = vertices.coordinate[0][vertex];
    midway[v] = vertices.coordinate[1][vertex];
    midway[reference_axis] = vertices.coordinate[2][vertex] + face_sign * depth * Real(0.5);
    const FeatureId id =
        reference_is_a
            ? FeatureId{vertices.reference_feature[vertex], vertices.incident_feature[vertex]}
            : FeatureId{vertices.incident_feature[vertex], vertices.reference_feature[vertex]};
    out.add(reference_centre + reference_axes * midway, depth, id);
  }
  return out.count;
}

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

Vec3 corner_in_own_frame(const Vec3& half, int sign_bits) {
  return Vec3((sign_bits & 1) ? half[0] : -half[0], (sign_bits & 2) ? half[1] : -half[1],
              (sign_bits & 4) ? half[2] : -half[2]);
}

// Edge contact: the edge of A along axis i and the edge of B along axis j that are extreme along
// the normal (A's deepest towards B, B's towards A); one point at their closest points, computed in
// A's frame. Returns the count and sets `gap` to the distance between the two closest points.
int edge_contact(const PairInA& pair, const Axis& axis, Real margin, Manifold& out, Real& gap) {
  const int i = axis.index_a;
  const int j = axis.index_b;
  const Vec3& n = axis.normal_in_a;
  const Vec3 n_in_b = pair.r.transpose() * n;
  int bits_a = 0;
  int bits_b = 0;
  for (int m = 0; m < 3; ++m) {
    if (m != i && n[m] < 0)
      bits_a |= 1 << m;
    if (m != j && n_in_b[m] >= 0)
      bits_b |= 1 << m;
  }
  const Vec3 a_start = corner_in_own_frame(pair.half_a, bits_a);
  const Vec3 a_end = corner_in_own_frame(pair.half_a, bits_a | 1 << i);
  const Vec3 b_start = pair.t + pair.r * corner_in_own_frame(pair.half_b, bits_b);
  const Vec3 b_end = pair.t + pair.r * corner_in_own_frame(pair.half_b, bits_b | 1 << j);
  Real s = 0;
  Real u = 0;
  closest_parameters_between_segments(a_start, a_end, b_start, b_end, s, u);
  const Vec3 on_a = a_start + (a_end - a_start) * s;
  const Vec3 on_b = b_start + (b_end - b_start) * u;
  gap = (on_b - on_a).norm();
  const Real depth = (on_b - on_a).dot(n);
  out.normal = pair.axes_a * n;
  if (depth >= -margin) {
    out.add(pair.centre_a + pair.axes_a * (on_a + n * (depth * Real(0.5))), depth,
            {feature::box_edge(i, bits_a), feature::box_edge(j, bits_b)});
  }
  return out.count;
}

// The points of `axis`; `realised_gap` gets the distance between the two bodies' points that the
// axis's points join (the smallest for a face), an upper bound of the boxes' distance.
int contacts_for_axis(const PairInA& pair, const Axis& axis, Real margin, Manifold& out,
                      Real& realised_gap) {
  switch (axis.kind) {
    case AxisKind::face_of_a:
      return face_contacts(pair, true, axis.index_a, margin, out, realised_gap);
    case AxisKind::face_of_b:
      return face_contacts(pair, false, axis.index_b, margin, out, realised_gap);
    case AxisKind::edges:
      return edge_contact(pair, axis, margin, out, realised_gap);
  }
  return 0;
}

// ---- Exact closest features of boxes that are apart
// -------------------------------------------

struct Box {
  Vec3 centre;
  Mat3 axes;  // columns: the box's local axes in the pair frame
  Vec3 half;

  Vec3 corner(int sign_bits) const { return centre + axes * corner_in_own_frame(half, sign_bits); }
  Vec3 to_local(const Vec3& p) const { return axes.transpose() * (p - centre); }
};

struct ClosestFeatures {
  Vec3 on_a = Vec3::Zero();
  Vec3 on_b = Vec3::Zero();
  Real distance = std::numeric_limits<Real>::infinity();
  FeatureId feature;
};

void closest_corner_to_box(const Box& corners, const Box& solid, bool corners_are_a,
                           ClosestFeatures& best) {
  for (int v = 0; v < 8; ++v) {
    const Vec3 corner = corners.corner(v);
    const Vec3 local = solid.to_local(corner);
    const Vec3 clamped = local.cwiseMax(-solid.half).cwiseMin(solid.half);
    const Real distance = (local - clamped).norm();
    if (distance < best.distance) {
      const Vec3 on_solid = solid.centre + solid.axes * clamped;
      const std::uint16_t solid_feature = box_feature_of_outside_point(local, solid.half);
      best.distance = distance;
      best.on_a = corners_are_a ? corner : on_solid;
      best.on_b = corners_are_a ? on_solid : corner;
      best.feature = corners_are_a ? FeatureId{feature::box_vertex(v), solid_feature}
                                   : FeatureId{solid_feature, feature::box_vertex(v)};
    }
  }
}

ClosestFeatures closest_features(const Box& a, const Box& b) {
  ClosestFeatures best;
  closest_corner_to_box(a, b, true, best);
  closest_corner_to_box(b, a, false, best);
  const Real scale = a.half.norm() + b.half.norm() + (a.centre - b.centre).norm();
  // Each corner once (the edge loops visit every corner of B 18 times).
  std::array<Vec3, 8> corners_a, corners_b;
  for (int v = 0; v < 8; ++v) {
    corners_a[std::size_t(v)] = a.corner(v);
    corners_b[std::size_t(v)] = b.corner(v);
  }
  for (int i = 0; i < 3; ++i) {
    for (int bits_a = 0; bits_a < 8; ++bits_a) {
      if ((bits_a >> i) & 1)
        continue;  // each edge once, from its negative end
      const Vec3& a_start = corners_a[std::size_t(bits_a)];
      const Vec3& a_end = corners_a[std::size_t(bits_a | 1 << i)];
      for (int j = 0; j < 3; ++j) {
        for (int bits_b = 0; bits_b < 8; ++bits_b) {
          if ((bits_b >> j) & 1)
            continue;
          const Vec3& b_start = corners_b[std::size_t(bits_b)];
          const Vec3& b_end = corners_b[std::size_t(bits_b | 1 << j)];
          // Two segments are at least as far apart as their bounding spheres: most of the 144
          // edge pairs are farther than the closest corner found, and skipping them changes no
          // answer (the band covers the rounding of both distances).
          const Real reach = best.distance + a.half[i] + b.half[j] + kCullBand * scale;
          if ((a_start + a_end - b_start - b_end).squaredNorm() > 4 * reach * reach)
            continue;
          Real s = 0;
          Real t = 0;
          closest_parameters_between_segments(a_start, a_end, b_start, b_end, s, t);
          const Vec3 on_a = a_start + (a_end - a_start) * s;
          const Vec3 on_b = b_start + (b_end - b_start) * t;
          const Real distance = (on_a - on_b).norm();
          if (distance < best.distance) {
            best = {
                on_a, on_b, distance, {feature::box_edge(i, bits_a), feature::box_edge(j, bits_b)}};
          }
        }
      }
    }
  }
  return best;
}

// The edge axis a_i x b_j (Gottschalk et al. 1996, table 1). In A's frame its components are 0 at
// i, -r(i2, j) at i1 and r(i1, j) at i2 (i1, i2 the next two axes), so with L = a_i x b_j: t . L =
// t_i2 r(i1, j) - t_i1 r(i2, j), A's radius ha_i1 |r(i2, j)| + ha_i2 |r(i1, j)|, B's radius hb_j1
// |r(i, j2)| + hb_j2 |r(i, j1)|, and |L|^2 = r(i1, j)^2 + r(i2, j)^2 (no cancellation, unlike 1 -
// r(i, j)^2). The separation along the unit axis is excess / |L|.
struct EdgeAxisTerms {
  Real along;           // t . L
  Real excess;          // |t . L| - radius_a - radius_b
  Real squared_length;  // |L|^2
};

template <int i, int j>
EdgeAxisTerms edge_axis_terms(const PairInA& pair) {
  constexpr int i1 = (i + 1) % 3;
  constexpr int i2 = (i + 2) % 3;
  constexpr int j1 = (j + 1) % 3;
  constexpr int j2 = (j + 2) % 3;
  const Mat3& r = pair.r;
  const Mat3& abs_r = pair.abs_r;
  const Real along = pair.t[i2] * r(i1, j) - pair.t[i1] * r(i2, j);
  const Real radius_a = pair.half_a[i1] * abs_r(i2, j) + pair.half_a[i2] * abs_r(i1, j);
  const Real radius_b = pair.half_b[j1] * abs_r(i, j2) + pair.half_b[j2] * abs_r(i, j1);
  return {along, std::abs(along) - radius_a - radius_b, r(i1, j) * r(i1, j) + r(i2, j) * r(i2, j)};
}

// The edge axis a_i x b_j as the chosen axis: its unit normal from B to A, in A's frame.
Axis edge_axis(const PairInA& pair, int i, int j, Real along, Real squared_length,
               Real separation) {
  Axis axis;
  axis.kind = AxisKind::edges;
  axis.index_a = i;
  axis.index_b = j;
  axis.separation = separation;
  // Against t (B's centre seen from A) along L.
  const Real scaled_sign = (along > 0 ? Real(-1) : Real(1)) / std::sqrt(squared_length);
  axis.normal_in_a = Vec3::Zero();
  axis.normal_in_a[(i + 1) % 3] = -pair.r((i + 2) % 3, j) * scaled_sign;
  axis.normal_in_a[(i + 2) % 3] = pair.r((i + 1) % 3, j) * scaled_sign;
  return axis;
}

// The most separated edge axis, the first on ties (separation -infinity when every pair of edges is
// parallel). The lanes are ranked by the signed square of their separation, excess |excess| /
// squared_length, compared by cross multiplication (no division, no square root; box_batch does
// the same), in a tournament whose left side wins ties, so the first lane wins and the chain of
// comparisons is four deep instead of nine; only the winner's separation is computed.
Axis best_edge_axis(const PairInA& pair, const std::array<EdgeAxisTerms, 9>& terms) {
  // (signed square, squared length or 1) of each lane; -infinity for parallel edges.
  struct Entry {
    Real signed_square;
    Real length2;
    int lane;
  };
  std::array<Entry, 9> entry;
  for (int lane = 0; lane < 9; ++lane) {
    const EdgeAxisTerms& t = terms[lane];
    const bool valid = t.squared_length > kMinCrossSine * kMinCrossSine;
    entry[lane] = {valid ? t.excess * std::abs(t.excess) : -std::numeric_limits<Real>::infinity(),
                   valid ? t.squared_length : Real(1), lane};
  }
  const auto better = [](const Entry& left, const Entry& right) {
    return right.signed_square * left.length2 > left.signed_square * right.length2 ? right : left;
  };
  const Entry level1[4] = {better(entry[0], entry[1]), better(entry[2], entry[3]),
                           better(entry[4], entry[5]), better(entry[6], entry[7])};
  const Entry level2 = better(better(level1[0], level1[1]), better(level1[2], level1[3]));
  const Entry best = better(level2, entry[8]);
  if (!(best.signed_square > -std::numeric_limits<Real>::infinity())) {
    Axis none;
    none.kind = AxisKind::edges;
    return none;
  }
  const EdgeAxisTerms& t = terms[best.lane];
  return edge_axis(pair, best.lane / 3, best.lane % 3, t.along, t.squared_length,
                   t.excess / std::sqrt(t.squared_length));
}

}  // namespace

int box_box(const Shape& shape_a, const Transform& pose_a, const Shape& shape_b,
            const Transform& pose_b, Real margin, Manifold& out) {
  PairInA pair;
  pair.centre_a = pose_a.translation;
  pair.centre_b = pose_b.translation;
  pair.axes_a = pose_a.rotation.toRotationMatrix();
  pair.rotation_b = pose_b.rotation;
  pair.half_a = shape_a.half_extents;
  pair.half_b = shape_b.half_extents;
  // B's rotation relative to A's: one quaternion product instead of a second rotation matrix and a
  // matrix product.
  pair.r = (pose_a.rotation.conjugate() * pose_b.rotation).toRotationMatrix();
  pair.abs_r = pair.r.cwiseAbs();
  pair.t.noalias() = pair.axes_a.transpose() * (pair.centre_b - pair.centre_a);
  const Mat3& r = pair.r;
  const Mat3& abs_r = pair.abs_r;
  const Vec3& t = pair.t;
  const Vec3& ha = pair.half_a;
  const Vec3& hb = pair.half_b;

  // All fifteen separations are computed before any is compared: branches on them would be
  // mispredicted about half the time, and straight-line arithmetic is cheaper than that. Face axes
  // of A: the centres are |t_i| apart along a_i; of B: |(r^T t)_j| along b_j.
  const Vec3 t_in_b = r.transpose() * t;
  const Vec3 face_a_separation = t.cwiseAbs() - ha - abs_r * hb;
  const Vec3 face_b_separation = t_in_b.cwiseAbs() - hb - abs_r.transpose() * ha;
  // Edge axes, lane 3 i + j for a_i x b_j.
  const std::array<EdgeAxisTerms, 9> edge_terms = {
      edge_axis_terms<0, 0>(pair), edge_axis_terms<0, 1>(pair), edge_axis_terms<0, 2>(pair),
      edge_axis_terms<1, 0>(pair), edge_axis_terms<1, 1>(pair), edge_axis_terms<1, 2>(pair),
      edge_axis_terms<2, 0>(pair), edge_axis_terms<2, 1>(pair), edge_axis_terms<2, 2>(pair)};
  // The most separated face axis of each box, the first on ties.
  const auto best_face_of = [](const Vec3& separations, int& index) {
    index = separations[1] > separations[0] ? 1 : 0;
    const Real best = std::max(separations[1], separations[0]);
    index = separations[2] > best ? 2 : index;
    return separations[2] > best ? separations[2] : best;
  };
  Axis face_a;
  face_a.separation = best_face_of(face_a_separation, face_a.index_a);
  Axis face_b;
  face_b.kind = AxisKind::face_of_b;
  face_b.separation = best_face_of(face_b_separation, face_b.index_b);
  const Axis edges = best_edge_axis(pair, edge_terms);
  if (face_a.separation > margin || face_b.separation > margin || edges.separation > margin)
    return 0;

  const Real scale = ha.norm() + hb.norm();
  const bool b_face_wins = clearly_more_separated(face_b.separation, face_a.separation, scale);
  const Axis& best_face = b_face_wins ? face_b : face_a;
  const Axis& other_face = b_face_wins ? face_a : face_b;
  const bool edge_wins = clearly_more_separated(edges.separation, best_face.separation, scale);
  const Axis& chosen = edge_wins ? edges : best_face;

  Real realised_gap = 0;
  const int count = contacts_for_axis(pair, chosen, margin, out, realised_gap);
  if (chosen.separation <= 0)
    return count;
  // Apart, within the margin: the chosen axis stands when its own points are as far apart as its
  // separation (see the file comment); otherwise report the exact distance.
  if (count > 0 && realised_gap <= chosen.separation + kRealisesDistanceTolerance * scale)
    return count;
  out = Manifold{};

  const Box a{pair.centre_a, pair.axes_a, ha};
  const Box b{pair.centre_b, pair.axes_b(), hb};
  const ClosestFeatures closest = closest_features(a, b);
  if (closest.distance > margin)
    return 0;
  const Real realised = closest.distance - kRealisesDistanceTolerance * scale;
  for (const Axis* axis : std::array<const Axis*, 4>{&chosen, &best_face, &other_face, &edges}) {
    if (axis->separation >= realised)
      return contacts_for_axis(pair, *axis, margin, out, realised_gap);
  }
  const Vec3 normal = (closest.on_a - closest.on_b) / closest.distance;
  out.normal = normal;
  add_contact(out, closest.on_a, normal, -closest.distance, margin, closest.feature);
  return out.count;
}

}  // namespace tumble::detail
