// Box against box.
//
// Axis: the separating-axis test over the 15 candidate axes of two oriented boxes, the 3 + 3
// face normals and the 9 cross products of edge directions (Gottschalk, Lin and Manocha,
// "OBBTree: A Hierarchical Structure for Rapid Interference Detection", SIGGRAPH 1996; Ericson,
// Real-Time Collision Detection, 2005, 4.4.1 and 5.2.1). Near-zero cross products (near-parallel
// edges) are skipped: the face axes cover them. Face axes win over edge axes, and A's faces over
// B's, unless the other is clearly more separated (clearly_more_separated in pairs.hpp), so the
// manifold does not flip between features from rounding.
//
// Points, face axis: the face of the other box most anti-parallel to the reference face's
// normal is the incident face; it is clipped against the four side planes of the reference face
// (Sutherland-Hodgman; Ericson 8.3.4; Catto, "Contact Manifolds", GDC 2007), and every clipped
// point below the reference face, or above it by less than the margin, is kept with its depth
// measured along the normal. More than four are reduced by manifold_reduction. Each clipped
// point carries the features that made it: an incident vertex inside the reference face, an
// incident edge crossing a reference side edge, or a reference corner inside the incident face.
//
// Points, edge axis: one point at the closest points of the two edges that are extreme along the
// axis.
//
// Apart but within the margin, the separation along the best axis can be smaller than the true
// distance (two boxes corner to corner). Then the exact closest features are found by brute
// force over the 8 + 8 corners against the other box and the 12 x 12 edge pairs; the axis is
// kept when it realises that distance (face-face, face-edge and edge-edge contacts), otherwise
// the single closest pair is the point and its direction the normal.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "collision/manifold_reduction.hpp"
#include "collision/pairs/pairs.hpp"

namespace tumble::detail {
namespace {

// Cross products of edge directions shorter than this (sine of the angle between the edges)
// are not tested: their direction would be mostly rounding.
constexpr Real kMinCrossSine = Real(1e-6);
// A separating axis "realises" the distance of boxes that are apart when its separation is
// within this fraction of the pair's size of the exact distance.
constexpr Real kRealisesDistanceTolerance = Real(1e-9);

struct Box {
  Vec3 centre;
  Mat3 axes;  // columns: the box's local axes in the pair frame
  Vec3 half;

  Vec3 axis(int k) const { return axes.col(k); }
  Vec3 corner(int sign_bits) const {
    Vec3 local;
    for (int k = 0; k < 3; ++k)
      local[k] = (sign_bits >> k) & 1 ? half[k] : -half[k];
    return centre + axes * local;
  }
  // Half the length of the box's projection on a unit direction.
  Real radius_along(const Vec3& direction) const {
    return half.dot((axes.transpose() * direction).cwiseAbs());
  }
  Vec3 to_local(const Vec3& p) const { return axes.transpose() * (p - centre); }
};

enum class AxisKind { face_of_a, face_of_b, edges };

struct Axis {
  AxisKind kind = AxisKind::face_of_a;
  int index_a = 0;              // A's face axis, or A's edge direction
  int index_b = 0;              // B's face axis, or B's edge direction
  Vec3 normal = Vec3::UnitZ();  // unit, from B to A
  Real separation = -std::numeric_limits<Real>::infinity();
};

// Separation of the boxes along a unit direction, turning the direction to point from B to A.
Real separation_along(const Box& a, const Box& b, Vec3& direction) {
  const Real centre_distance = direction.dot(a.centre - b.centre);
  if (centre_distance < 0)
    direction = -direction;
  return std::abs(centre_distance) - a.radius_along(direction) - b.radius_along(direction);
}

// ---- Clipping -------------------------------------------------------------------------------

struct ClipVertex {
  Vec3 position;
  std::uint16_t incident_feature;
  std::uint16_t reference_feature;
  // The polygon edge that leaves this vertex runs along an incident box edge
  // (`outgoing_edge`) or, after a clip, along a reference side plane (`outgoing_side` >= 0).
  std::uint16_t outgoing_edge;
  int outgoing_side;
};

// Sutherland-Hodgman on a quadrilateral against four planes adds at most one vertex per plane;
// the slack covers rounding at grazing angles.
constexpr int kMaxClipVertices = 16;

struct ClipPolygon {
  std::array<ClipVertex, kMaxClipVertices> vertices;
  int count = 0;
  void push(const ClipVertex& v) {
    if (count < kMaxClipVertices)
      vertices[count++] = v;
  }
};

struct SidePlane {
  Vec3 normal;  // outward from the reference face's prism
  Real offset;  // inside when normal . x <= offset
  int tangent_axis;
  bool positive;
};

struct ReferenceFace {
  const Box* box;
  int axis;
  bool positive;
  Vec3 normal;  // outward, towards the incident box
  std::array<SidePlane, 4> sides;

  std::uint16_t face_feature() const { return feature::box_face(axis, positive); }
  int face_bit() const { return positive ? 1 << axis : 0; }
  // The edge of the reference face that lies in side plane `s`.
  std::uint16_t side_edge(int s) const {
    const SidePlane& side = sides[s];
    return feature::box_edge(3 - axis - side.tangent_axis,
                             face_bit() | (side.positive ? 1 << side.tangent_axis : 0));
  }
  // The corner of the reference face where side planes `s` and `t` meet.
  std::uint16_t corner(int s, int t) const {
    const SidePlane& u = sides[s];
    const SidePlane& v = sides[t];
    if (u.tangent_axis == v.tangent_axis)
      return face_feature();  // parallel: no corner
    return feature::box_vertex(face_bit() | (u.positive ? 1 << u.tangent_axis : 0) |
                               (v.positive ? 1 << v.tangent_axis : 0));
  }
};

ReferenceFace make_reference_face(const Box& box, int axis, const Vec3& towards_other) {
  ReferenceFace face;
  face.box = &box;
  face.axis = axis;
  face.positive = box.axis(axis).dot(towards_other) >= 0;
  face.normal = box.axis(axis) * (face.positive ? Real(1) : Real(-1));
  int s = 0;
  for (const int tangent : {(axis + 1) % 3, (axis + 2) % 3}) {
    for (const bool positive : {true, false}) {
      const Vec3 n = box.axis(tangent) * (positive ? Real(1) : Real(-1));
      face.sides[s++] = {n, n.dot(box.centre) + box.half[tangent], tangent, positive};
    }
  }
  return face;
}

// The incident face as a polygon whose corners start out inside the reference face.
ClipPolygon incident_face(const Box& box, const ReferenceFace& reference,
                          std::uint16_t& face_feature) {
  const Vec3& reference_normal = reference.normal;
  // The face whose outward normal is most anti-parallel to the reference normal.
  int axis = 0;
  Real best = -1;
  for (int k = 0; k < 3; ++k) {
    const Real alignment = std::abs(box.axis(k).dot(reference_normal));
    if (alignment > best) {
      best = alignment;
      axis = k;
    }
  }
  const bool positive = box.axis(axis).dot(reference_normal) < 0;
  face_feature = feature::box_face(axis, positive);
  const int a = (axis + 1) % 3;
  const int b = (axis + 2) % 3;
  // Corners in cyclic order (+a,+b), (-a,+b), (-a,-b), (+a,-b); edges alternate along a, b.
  constexpr std::array<bool, 4> a_positive = {true, false, false, true};
  constexpr std::array<bool, 4> b_positive = {true, true, false, false};
  ClipPolygon polygon;
  for (int i = 0; i < 4; ++i) {
    const int bits =
        (positive ? 1 << axis : 0) | (a_positive[i] ? 1 << a : 0) | (b_positive[i] ? 1 << b : 0);
    const int edge_direction = i % 2 == 0 ? a : b;
    polygon.push({box.corner(bits), feature::box_vertex(bits), reference.face_feature(),
                  feature::box_edge(edge_direction, bits), -1});
  }
  return polygon;
}

ClipPolygon clip_against_side(const ClipPolygon& in, const ReferenceFace& reference, int side,
                              std::uint16_t incident_face_feature) {
  const SidePlane& plane = reference.sides[side];
  ClipPolygon out;
  for (int i = 0; i < in.count; ++i) {
    const ClipVertex& p = in.vertices[i];
    const ClipVertex& q = in.vertices[(i + 1) % in.count];
    const Real distance_p = plane.normal.dot(p.position) - plane.offset;
    const Real distance_q = plane.normal.dot(q.position) - plane.offset;
    const bool p_inside = distance_p <= 0;
    const bool q_inside = distance_q <= 0;
    if (p_inside)
      out.push(p);
    if (p_inside == q_inside)
      continue;
    ClipVertex crossing = p;
    crossing.position =
        p.position + (q.position - p.position) * (distance_p / (distance_p - distance_q));
    if (p.outgoing_side < 0) {
      // An incident edge crossing a side of the reference face.
      crossing.incident_feature = p.outgoing_edge;
      crossing.reference_feature = reference.side_edge(side);
    } else {
      // A stretch along an earlier side plane crossing this one: a reference corner.
      crossing.incident_feature = incident_face_feature;
      crossing.reference_feature = reference.corner(p.outgoing_side, side);
    }
    // Leaving the prism, the polygon now runs along this side plane to where it comes back in;
    // entering it, it continues along p's edge.
    if (p_inside)
      crossing.outgoing_side = side;
    out.push(crossing);
  }
  return out;
}

// Face contact: the reference face is A's (reference_is_a) or B's.
int face_contacts(const Box& a, const Box& b, bool reference_is_a, int reference_axis, Real margin,
                  Manifold& out) {
  const Box& reference_box = reference_is_a ? a : b;
  const Box& incident_box = reference_is_a ? b : a;
  const ReferenceFace reference = make_reference_face(reference_box, reference_axis,
                                                      incident_box.centre - reference_box.centre);
  std::uint16_t incident_face_feature = 0;
  ClipPolygon polygon = incident_face(incident_box, reference, incident_face_feature);
  for (int side = 0; side < 4 && polygon.count > 0; ++side) {
    polygon = clip_against_side(polygon, reference, side, incident_face_feature);
  }

  const Vec3 normal = reference_is_a ? Vec3(-reference.normal) : reference.normal;
  out.normal = normal;
  const Real face_offset =
      reference.normal.dot(reference_box.centre) + reference_box.half[reference_axis];

  std::array<ContactPoint, kMaxClipVertices> candidates;
  int candidate_count = 0;
  for (int i = 0; i < polygon.count; ++i) {
    const ClipVertex& v = polygon.vertices[i];
    // Height of the incident point above the reference face; depth is its negative.
    const Real separation = reference.normal.dot(v.position) - face_offset;
    if (!(-separation >= -margin))
      continue;
    const FeatureId id = reference_is_a ? FeatureId{v.reference_feature, v.incident_feature}
                                        : FeatureId{v.incident_feature, v.reference_feature};
    // Midway between the incident point and its projection onto the reference face.
    candidates[candidate_count++] = {v.position - reference.normal * (separation * Real(0.5)),
                                     -separation, id};
  }
  if (candidate_count == 0) {
    // Rounding clipped everything away, or the clipped face lies above the margin while a
    // corner outside the reference face is deep (a face kept by the hysteresis over a slightly
    // better edge axis): keep the deepest incident corner, so that boxes that touch never go
    // without a point.
    const ClipPolygon corners = incident_face(incident_box, reference, incident_face_feature);
    int deepest = 0;
    for (int i = 1; i < 4; ++i) {
      if (reference.normal.dot(corners.vertices[i].position) <
          reference.normal.dot(corners.vertices[deepest].position)) {
        deepest = i;
      }
    }
    const ClipVertex& v = corners.vertices[deepest];
    const Real separation = reference.normal.dot(v.position) - face_offset;
    if (-separation >= -margin) {
      const FeatureId id = reference_is_a ? FeatureId{v.reference_feature, v.incident_feature}
                                          : FeatureId{v.incident_feature, v.reference_feature};
      candidates[candidate_count++] = {v.position - reference.normal * (separation * Real(0.5)),
                                       -separation, id};
    }
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

// Edge contact: the edge of A along axis i and the edge of B along axis j that are extreme
// along the normal (A's deepest towards B, B's towards A); one point at their closest points.
int edge_contact(const Box& a, const Box& b, int i, int j, const Vec3& normal, Real margin,
                 Manifold& out) {
  int bits_a = 0;
  int bits_b = 0;
  for (int m = 0; m < 3; ++m) {
    if (m != i && a.axis(m).dot(normal) < 0)
      bits_a |= 1 << m;
    if (m != j && b.axis(m).dot(normal) >= 0)
      bits_b |= 1 << m;
  }
  const Vec3 a_start = a.corner(bits_a);
  const Vec3 a_end = a.corner(bits_a | 1 << i);
  const Vec3 b_start = b.corner(bits_b);
  const Vec3 b_end = b.corner(bits_b | 1 << j);
  Real s = 0;
  Real t = 0;
  closest_parameters_between_segments(a_start, a_end, b_start, b_end, s, t);
  const Vec3 on_a = a_start + (a_end - a_start) * s;
  const Vec3 on_b = b_start + (b_end - b_start) * t;
  out.normal = normal;
  add_contact(out, on_a, normal, (on_b - on_a).dot(normal), margin,
              {feature::box_edge(i, bits_a), feature::box_edge(j, bits_b)});
  return out.count;
}

// ---- Exact closest features of boxes that are apart -------------------------------------------

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
  for (int i = 0; i < 3; ++i) {
    for (int bits_a = 0; bits_a < 8; ++bits_a) {
      if ((bits_a >> i) & 1)
        continue;  // each edge once, from its negative end
      const Vec3 a_start = a.corner(bits_a);
      const Vec3 a_end = a.corner(bits_a | 1 << i);
      for (int j = 0; j < 3; ++j) {
        for (int bits_b = 0; bits_b < 8; ++bits_b) {
          if ((bits_b >> j) & 1)
            continue;
          const Vec3 b_start = b.corner(bits_b);
          const Vec3 b_end = b.corner(bits_b | 1 << j);
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

int contacts_for_axis(const Box& a, const Box& b, const Axis& axis, Real margin, Manifold& out) {
  switch (axis.kind) {
    case AxisKind::face_of_a:
      return face_contacts(a, b, true, axis.index_a, margin, out);
    case AxisKind::face_of_b:
      return face_contacts(a, b, false, axis.index_b, margin, out);
    case AxisKind::edges:
      return edge_contact(a, b, axis.index_a, axis.index_b, axis.normal, margin, out);
  }
  return 0;
}

}  // namespace

int box_box(const Shape& shape_a, const Transform& pose_a, const Shape& shape_b,
            const Transform& pose_b, Real margin, Manifold& out) {
  const Box a{pose_a.translation, pose_a.rotation.toRotationMatrix(), shape_a.half_extents};
  const Box b{pose_b.translation, pose_b.rotation.toRotationMatrix(), shape_b.half_extents};
  const Real scale = a.half.norm() + b.half.norm();

  // Face axes.
  Axis face_a;
  Axis face_b;
  for (int k = 0; k < 3; ++k) {
    Vec3 direction = a.axis(k);
    const Real separation = separation_along(a, b, direction);
    if (separation > margin)
      return 0;
    if (separation > face_a.separation)
      face_a = {AxisKind::face_of_a, k, 0, direction, separation};
  }
  for (int k = 0; k < 3; ++k) {
    Vec3 direction = b.axis(k);
    const Real separation = separation_along(a, b, direction);
    if (separation > margin)
      return 0;
    if (separation > face_b.separation)
      face_b = {AxisKind::face_of_b, 0, k, direction, separation};
  }
  // Edge axes.
  Axis edges;
  edges.kind = AxisKind::edges;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Vec3 cross = a.axis(i).cross(b.axis(j));
      const Real length = cross.norm();
      if (!(length > kMinCrossSine))
        continue;
      Vec3 direction = cross / length;
      const Real separation = separation_along(a, b, direction);
      if (separation > margin)
        return 0;
      if (separation > edges.separation)
        edges = {AxisKind::edges, i, j, direction, separation};
    }
  }

  const bool b_face_wins = clearly_more_separated(face_b.separation, face_a.separation, scale);
  const Axis& best_face = b_face_wins ? face_b : face_a;
  const Axis& other_face = b_face_wins ? face_a : face_b;
  const bool edge_wins = clearly_more_separated(edges.separation, best_face.separation, scale);
  const Axis& chosen = edge_wins ? edges : best_face;

  if (chosen.separation <= 0)
    return contacts_for_axis(a, b, chosen, margin, out);

  // Apart, within the margin: report the exact distance (see the file comment).
  const ClosestFeatures closest = closest_features(a, b);
  if (closest.distance > margin)
    return 0;
  const Real realised = closest.distance - kRealisesDistanceTolerance * scale;
  for (const Axis* axis : std::array<const Axis*, 4>{&chosen, &best_face, &other_face, &edges}) {
    if (axis->separation >= realised)
      return contacts_for_axis(a, b, *axis, margin, out);
  }
  const Vec3 normal = (closest.on_a - closest.on_b) / closest.distance;
  out.normal = normal;
  add_contact(out, closest.on_a, normal, -closest.distance, margin, closest.feature);
  return out.count;
}

}  // namespace tumble::detail
