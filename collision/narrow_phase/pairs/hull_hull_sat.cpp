// Hull against hull by the separating-axis test with face clipping.
//
// Axis (Dirk Gregorius, "The Separating Axis Test between Convex Polyhedra", GDC 2013):
//   * face queries: for every face of A, B's deepest vertex against its plane (B's support along
//     the reversed normal, by hill climbing on B's vertex graph), and the same for B's faces;
//   * edge query: an edge is an arc on the Gauss map between the normals of its two faces; an
//     edge pair's cross product is a face normal of the Minkowski difference A - B exactly when
//     the arc of A's edge crosses the arc of B's edge reversed (arcs_intersect: Gregorius' triple
//     products). Only those pairs are tested; for them the edges are the supports along the axis,
//     so the separation is one dot product. The axis is turned away from A's centre, and
//     near-parallel edges are skipped (their cross product would be mostly rounding; the face
//     axes cover them).
//   * bounds (ours, exact): a face's separation is the minimum over the other hull's vertices,
//     so at most its value at any one point of the other hull (we take its support point towards
//     this hull) and at most n.c - offset - r (c, r: the other hull's centre of mass and the
//     radius of its largest inscribed ball about it). For an axis n in the arc of A's edge from
//     point p the separation is likewise at most n.(q - p) and n.(c - p) - r; the largest n.v
//     over an arc between unit normals a and b is at most max(a.v, b.v) / cos(half the arc)
//     (when positive). A face or an edge whose bound cannot beat the best face so far is never
//     evaluated: it could never be chosen, so the answer is the same as without the bounds
//     (tested), and a shallow contact tests a few percent of the edge pairs.
// The axis of least penetration is chosen with a bias towards faces, A's face first
// (clearly_more_separated in pairs.hpp: 2 % of the incumbent plus 1e-5 of the pair's size, as
// box_box), so the manifold does not flip between a face and a nearly equal edge from step to
// step. The biased choice is kept only when its deepest point reaches the penetration its own
// axis measures (so that pushing A out by that depth along the normal separates the hulls);
// otherwise the exactly best axis answers. The reported depth is thus never below the true
// depth, and above it by at most the bias.
//
// Points, face axis (Gregorius, "Robust Contact Creation for Physics Simulations", GDC 2015;
// Catto, "Contact Manifolds", GDC 2007): the reference face is the chosen face; the incident face
// is, among the faces around the other hull's deepest vertex (from the face query), the one most
// anti-parallel to the reference normal. (The most anti-parallel face of the whole hull can lie
// away from that vertex and miss the reference face.) The incident polygon is clipped against
// the side planes of the reference face (Sutherland-Hodgman, fixed buffers), the points below the
// reference plane, or above it by at most the margin, are kept with their depth along the
// reference normal, and more than four are reduced (manifold_reduction). Each point carries the
// features that made it: an incident vertex inside the reference face, an incident edge crossing
// a reference side edge, or a reference corner inside the incident face.
// Points, edge axis: one point at the closest points of the two edge segments.
//
// Margin: the engine keeps points down to depth -margin (speculative contacts). An axis that
// separates by more than the margin proves the hulls farther apart than that: no contact. When
// the best axis separates by less (apart within the margin), its separation can be smaller than
// the true distance (two hulls vertex to vertex); then GJK measures the distance, and the SAT
// manifold is kept only when its axis realises it, otherwise the generic GJK pair
// (convex_convex) answers, as box_box does with its exact closest features. Hulls too big for
// the fixed buffers (more than kSatMaxEdges edges, or a face of more than 64 vertices) also go to
// convex_convex.
#include "collision/narrow_phase/pairs/hull_hull_sat.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/pairs/manifold_reduction.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"

namespace tumble::detail {
namespace {

// Edge pairs whose cross product is shorter than this (sine of the angle between the edges) are
// not tested: near-parallel edges, covered by the face axes.
constexpr Real kMinCrossSine = Real(1e-6);
// A separating axis realises the distance of hulls that are apart when its separation is within
// this fraction of the pair's size of GJK's distance.
constexpr Real kRealisesDistanceTolerance = Real(1e-9);
// Polygons from clipping: an incident face of up to kMaxClipInput vertices gains at most one
// vertex per reference side; bigger faces fall back to the generic pair.
constexpr int kMaxClipInput = 64;
constexpr int kMaxClipVertices = 2 * kMaxClipInput + 8;

// Hull feature ids, the same numbering as the generic pair (convex_pairs.cpp): vertices by
// index; a face flagged with kFaceFlag; an edge flagged with kEdgeFlag and named by the vertex
// it leaves from along the face loop that owns it.
constexpr std::uint16_t kFaceFlag = 0x8000;
constexpr std::uint16_t kEdgeFlag = 0x4000;
constexpr std::uint16_t vertex_id(int v) {
  return std::uint16_t(v & 0x3fff);
}
constexpr std::uint16_t face_id(int f) {
  return std::uint16_t(kFaceFlag | (f & 0x3fff));
}
constexpr std::uint16_t edge_id(int start_vertex) {
  return std::uint16_t(kEdgeFlag | (start_vertex & 0x3fff));
}

// ---- Queries --------------------------------------------------------------------------------

// Radius of the largest ball about the centre of mass (the local origin) inside the hull.
Real inscribed_radius(const ConvexHull& hull) {
  Real r = std::numeric_limits<Real>::infinity();
  for (const HullFace& f : hull.faces())
    r = std::min(r, f.offset);
  return std::max(r, Real(0));
}

// The separation of face f of `faces` against `other`, both in `faces`' frame through
// `other_pose` (other's local -> faces' local). `start` is the hill climb's first vertex and
// receives the support found.
Real face_separation(const ConvexHull& faces, int f, const ConvexHull& other,
                     const Transform& other_pose, int& start) {
  const HullFace& face = faces.faces()[std::size_t(f)];
  const Vec3 normal = other_pose.rotate_inverse(face.normal);  // other's frame
  // Climbed, not scanned: successive face normals are close, so from the last support the
  // climb takes a step or two where a scan reads every vertex.
  start = other.climb_support_index(-normal, start);
  return face.normal.dot(other_pose.apply(other.vertex(start))) - face.offset;
}

// Faces of `faces` against the vertices of `other` placed by `other_pose` in faces' frame. The
// separation over a face is the minimum over other's vertices, so it is at most its value at
// other's vertex `near` (other's support towards the faces' hull), and at most n.c - offset - r
// (c, r: other's centre and inscribed radius). A face whose bound is not above `beat` or the
// best so far cannot be the best one and is skipped; the face with the best bound is tried
// first so that the bound bites early. Stops at the first face separating by more than
// `stop_above`. Returns face -1 when no face beat `beat`.
SatFaceQuery query_faces(const ConvexHull& faces, const ConvexHull& other,
                         const Transform& other_pose, Real other_inscribed, int near, Real beat,
                         Real stop_above) {
  const Vec3& centre = other_pose.translation;
  const Vec3 near_point = other_pose.apply(other.vertex(near));
  const int count = int(faces.faces().size());
  const auto bound = [&](const HullFace& face) {
    return std::min(face.normal.dot(centre) - other_inscribed, face.normal.dot(near_point)) -
           face.offset;
  };
  int first = 0;
  Real first_bound = -std::numeric_limits<Real>::infinity();
  for (int f = 0; f < count; ++f) {
    const Real b = bound(faces.faces()[std::size_t(f)]);
    if (b > first_bound) {
      first_bound = b;
      first = f;
    }
  }
  SatFaceQuery best;
  int start = near;
  const Real first_separation = face_separation(faces, first, other, other_pose, start);
  if (first_separation > beat)
    best = {first, start, first_separation};
  if (first_separation > stop_above)
    return best;
  for (int f = 0; f < count; ++f) {
    const Real to_beat = std::max(beat, best.separation);
    if (f == first || !(bound(faces.faces()[std::size_t(f)]) > to_beat))
      continue;
    const Real separation = face_separation(faces, f, other, other_pose, start);
    if (separation > to_beat) {
      best = {f, start, separation};
      if (separation > stop_above)
        return best;
    }
  }
  return best;
}

// An edge's arc on the Gauss map, A's frame (80 bytes: two of these buffers are the query's
// stack).
struct EdgeArc {
  Vec3 a;      // normal of the edge's first face (B's: reversed)
  Vec3 b;      // normal of its second face (B's: reversed)
  Vec3 b_x_a;  // b x a
  int index;   // HullEdge index
};

// n . v over the arc between unit normals a and b is at most max(a.v, b.v) / cos(half the arc)
// when positive, and at most max(a.v, b.v) otherwise (see the header comment). `scale` is
// 1 / cos(half the arc), computed once per edge and only when needed.
Real arc_bound(Real m, Real& scale, const Vec3& a, const Vec3& b) {
  if (m <= 0)
    return m;
  if (scale == 0) {
    const Real twice_cos_half = (a + b).norm();
    scale = twice_cos_half > Real(1e-6) ? Real(2) / twice_cos_half
                                        : std::numeric_limits<Real>::infinity();
  }
  return m * scale;
}

// The other hull as the edge bound sees it, in the frame of the hull whose edges are collected.
struct OtherHull {
  Vec3 centre;  // its centre of mass
  Real inscribed = 0;
  Vec3 near;  // its support point towards this hull
};

// The arcs of `hull`'s edges (placed by `pose` in A's frame; normals reversed for B) that can
// still beat `threshold`. For n in the arc of an edge from point p, the separation is at most
// n.(c - p) - r and at most n.(q - p) (c, r, q: the other hull's centre, inscribed radius and
// support point towards this hull; for B's edges the same holds with B's own, unreversed
// normals). The bound is evaluated in the hull's own frame, so only the kept edges are rotated.
int collect_arcs(const ConvexHull& hull, const Transform& pose, bool is_b, const OtherHull& other,
                 Real threshold, bool use_bound, std::array<EdgeArc, kSatMaxEdges>& out) {
  const Mat3 rotation = pose.rotation.toRotationMatrix();
  const Real sign = is_b ? Real(-1) : Real(1);
  int count = 0;
  const int edges = int(hull.edges().size());
  for (int e = 0; e < edges; ++e) {
    const HullEdge& edge = hull.edges()[std::size_t(e)];
    if (edge.face[0] == edge.face[1])
      continue;
    const Vec3& local_a = hull.faces()[std::size_t(edge.face[0])].normal;
    const Vec3& local_b = hull.faces()[std::size_t(edge.face[1])].normal;
    const Vec3& local_start = hull.vertex(edge.vertex[0]);
    if (use_bound) {
      const Vec3 to_near = other.near - local_start;
      Real scale = 0;
      const Real by_near =
          arc_bound(std::max(local_a.dot(to_near), local_b.dot(to_near)), scale, local_a, local_b);
      if (!(by_near > threshold))
        continue;
      const Vec3 to_centre = other.centre - local_start;
      const Real by_centre = arc_bound(std::max(local_a.dot(to_centre), local_b.dot(to_centre)),
                                       scale, local_a, local_b) -
                             other.inscribed;
      if (!(by_centre > threshold))
        continue;
    }
    const Vec3 a = sign * (rotation * local_a);
    const Vec3 b = sign * (rotation * local_b);
    out[std::size_t(count++)] = {a, b, b.cross(a), e};
  }
  return count;
}

SatEdgeQuery query_edges(const ConvexHull& a, const ConvexHull& b, const Transform& b_in_a,
                         const OtherHull& b_seen_from_a, const OtherHull& a_seen_from_b,
                         Real threshold, SatEdgePruning pruning, int& pairs_tested) {
  const bool use_bound = pruning == SatEdgePruning::gauss_map_and_bound;
  std::array<EdgeArc, kSatMaxEdges> arcs_a;
  std::array<EdgeArc, kSatMaxEdges> arcs_b;
  const int count_a =
      collect_arcs(a, Transform{}, false, b_seen_from_a, threshold, use_bound, arcs_a);
  const int count_b =
      count_a == 0 ? 0 : collect_arcs(b, b_in_a, true, a_seen_from_b, threshold, use_bound, arcs_b);
  pairs_tested = count_a * count_b;
  SatEdgeQuery best;
  const Mat3 rotation = b_in_a.rotation.toRotationMatrix();
  for (int j = 0; j < count_b; ++j) {
    const EdgeArc& eb = arcs_b[std::size_t(j)];
    const HullEdge& edge_b = b.edges()[std::size_t(eb.index)];
    const Vec3 start_b = rotation * b.vertex(edge_b.vertex[0]) + b_in_a.translation;
    const Vec3 direction_b = rotation * (b.vertex(edge_b.vertex[1]) - b.vertex(edge_b.vertex[0]));
    for (int i = 0; i < count_a; ++i) {
      const EdgeArc& ea = arcs_a[std::size_t(i)];
      if (!arcs_intersect(ea.a, ea.b, ea.b_x_a, eb.a, eb.b, eb.b_x_a))
        continue;
      const HullEdge& edge_a = a.edges()[std::size_t(ea.index)];
      const Vec3& start_a = a.vertex(edge_a.vertex[0]);
      const Vec3 direction_a = a.vertex(edge_a.vertex[1]) - start_a;
      Vec3 axis = direction_a.cross(direction_b);
      const Real length = axis.norm();
      if (!(length > kMinCrossSine * direction_a.norm() * direction_b.norm()))
        continue;
      axis /= length;
      // Away from A's centre (the local origin).
      if (axis.dot(start_a) < 0)
        axis = -axis;
      const Real separation = axis.dot(start_b - start_a);
      if (separation > best.separation)
        best = {ea.index, eb.index, axis, separation};
    }
  }
  return best;
}

}  // namespace

SatResult hull_sat_query(const ConvexHull& a, const ConvexHull& b, const Transform& b_in_a,
                         Real stop_above, SatEdgePruning pruning) {
  SatResult result;
  if (int(a.edges().size()) > kSatMaxEdges || int(b.edges().size()) > kSatMaxEdges) {
    result.status = SatStatus::too_big;
    return result;
  }
  const Real lowest = -std::numeric_limits<Real>::infinity();
  // Each hull as the other sees it: centre, inscribed radius, and support point towards it.
  const Transform a_in_b{b_in_a.apply_inverse(Vec3::Zero()), b_in_a.rotation.conjugate()};
  const int near_b = b.support_index(a_in_b.translation, 0);
  const int near_a = a.support_index(b_in_a.translation, 0);
  const OtherHull b_seen_from_a{b_in_a.translation, inscribed_radius(b),
                                b_in_a.apply(b.vertex(near_b))};
  const OtherHull a_seen_from_b{a_in_b.translation, inscribed_radius(a),
                                a_in_b.apply(a.vertex(near_a))};
  result.face_a = query_faces(a, b, b_in_a, b_seen_from_a.inscribed, near_b, lowest, stop_above);
  if (result.face_a.separation > stop_above) {
    result.status = SatStatus::separated;
    return result;
  }
  // B's faces against A, in B's frame: the separation above B's plane is the separation along
  // the reversed normal, from A to B. With the bound, only a face better than A's best is
  // looked for; without it (tests) B's best face is found whatever A's is.
  const bool use_bound = pruning == SatEdgePruning::gauss_map_and_bound;
  result.face_b = query_faces(b, a, a_in_b, a_seen_from_b.inscribed, near_a,
                              use_bound ? result.face_a.separation : lowest, stop_above);
  if (result.face_b.separation > stop_above) {
    result.status = SatStatus::separated;
    return result;
  }
  const Real threshold = std::max(result.face_a.separation, result.face_b.separation);
  result.edges = query_edges(a, b, b_in_a, b_seen_from_a, a_seen_from_b, threshold, pruning,
                             result.edge_pairs_tested);
  result.status =
      result.edges.separation > stop_above ? SatStatus::separated : SatStatus::overlapping;
  return result;
}

namespace {

// ---- Clipping -------------------------------------------------------------------------------

struct ClipVertex {
  Vec3 position;
  std::uint16_t incident_feature;
  std::uint16_t reference_feature;
  // The polygon edge leaving this vertex runs along an incident edge (`outgoing_edge`) or, after
  // a clip, along a reference side plane (`outgoing_side` >= 0).
  std::uint16_t outgoing_edge;
  int outgoing_side;
};

struct ClipPolygon {
  std::array<ClipVertex, kMaxClipVertices> vertices;
  int count = 0;
  void push(const ClipVertex& v) {
    if (count < kMaxClipVertices)
      vertices[std::size_t(count++)] = v;
  }
};

// A hull placed in A's frame.
struct PlacedHull {
  const ConvexHull* hull;
  Transform pose;  // local -> A's frame
  Vec3 vertex(int v) const { return pose.apply(hull->vertex(v)); }
  Vec3 normal(int f) const { return pose.rotate(hull->faces()[std::size_t(f)].normal); }
  int loop_vertex(const HullFace& face, int k) const {
    return hull->face_vertices()[std::size_t(face.first_index + k % face.count)];
  }
};

// Face contact in A's frame; -1 when a face is too big for the fixed buffers.
int face_contacts(const PlacedHull& reference, int reference_face, const PlacedHull& incident,
                  int support_vertex, bool reference_is_a, Real margin, Manifold& out) {
  const HullFace& ref = reference.hull->faces()[std::size_t(reference_face)];
  const Vec3 ref_normal = reference.normal(reference_face);
  // The incident face: of the faces around the incident hull's deepest vertex (from the face
  // query), the one most anti-parallel to the reference normal. The most anti-parallel face of
  // the whole hull can lie away from that vertex when the vertex's normal cone is wide, and
  // then it misses the reference face; a face through the deepest vertex holds the point whose
  // projection the best face axis puts inside the reference face.
  const Vec3 local_ref_normal = incident.pose.rotate_inverse(ref_normal);
  int incident_face = -1;
  Real most_opposed = std::numeric_limits<Real>::infinity();
  for (const HullEdge& edge : incident.hull->edges()) {
    if (edge.vertex[0] != support_vertex && edge.vertex[1] != support_vertex)
      continue;
    for (const int f : edge.face) {
      const Real alignment = incident.hull->faces()[std::size_t(f)].normal.dot(local_ref_normal);
      if (alignment < most_opposed) {
        most_opposed = alignment;
        incident_face = f;
      }
    }
  }
  if (incident_face < 0)
    return -1;
  const HullFace& inc = incident.hull->faces()[std::size_t(incident_face)];
  if (inc.count > kMaxClipInput || ref.count > kMaxClipInput)
    return -1;

  ClipPolygon polygon;
  for (int k = 0; k < inc.count; ++k) {
    const int v = incident.loop_vertex(inc, k);
    polygon.push({incident.vertex(v), vertex_id(v), face_id(reference_face), edge_id(v), -1});
  }
  ClipPolygon clipped;
  for (int s = 0; s < ref.count && polygon.count > 0; ++s) {
    const int v0 = reference.loop_vertex(ref, s);
    const int v1 = reference.loop_vertex(ref, s + 1);
    const Vec3 r0 = reference.vertex(v0);
    // Outward from the face: the loop runs counter-clockwise about the outward normal.
    const Vec3 side = (reference.vertex(v1) - r0).cross(ref_normal);
    const Real side_offset = side.dot(r0);
    clipped.count = 0;
    for (int k = 0; k < polygon.count; ++k) {
      const ClipVertex& p = polygon.vertices[std::size_t(k)];
      const ClipVertex& q = polygon.vertices[std::size_t((k + 1) % polygon.count)];
      const Real dp = side.dot(p.position) - side_offset;
      const Real dq = side.dot(q.position) - side_offset;
      const bool p_inside = dp <= 0;
      const bool q_inside = dq <= 0;
      if (p_inside)
        clipped.push(p);
      if (p_inside == q_inside)
        continue;
      ClipVertex crossing = p;
      crossing.position = p.position + (q.position - p.position) * (dp / (dp - dq));
      if (p.outgoing_side < 0) {
        // An incident edge crossing a side edge of the reference face.
        crossing.incident_feature = p.outgoing_edge;
        crossing.reference_feature = edge_id(v0);
      } else {
        // A stretch along an earlier side plane crossing this one: the reference corner between
        // them when the sides are adjacent, else the face.
        crossing.incident_feature = face_id(incident_face);
        const int previous = p.outgoing_side;
        crossing.reference_feature =
            (previous + 1) % ref.count == s
                ? vertex_id(v0)
                : ((s + 1) % ref.count == previous ? vertex_id(v1) : face_id(reference_face));
      }
      // Leaving the face's prism, the polygon now runs along this side plane until it comes
      // back in; entering it, it continues along p's edge (or p's side plane).
      if (p_inside)
        crossing.outgoing_side = s;
      clipped.push(crossing);
    }
    std::swap(polygon, clipped);
  }

  const Real plane = ref.offset + ref_normal.dot(reference.pose.translation);
  const Vec3 normal = reference_is_a ? Vec3(-ref_normal) : ref_normal;
  std::array<ContactPoint, kMaxClipVertices> candidates;
  int count = 0;
  for (int k = 0; k < polygon.count; ++k) {
    const ClipVertex& v = polygon.vertices[std::size_t(k)];
    const Real separation = ref_normal.dot(v.position) - plane;
    if (!(-separation >= -margin))
      continue;
    const FeatureId id = reference_is_a ? FeatureId{v.reference_feature, v.incident_feature}
                                        : FeatureId{v.incident_feature, v.reference_feature};
    candidates[std::size_t(count++)] = {v.position - ref_normal * (separation * Real(0.5)),
                                        -separation, id};
  }
  return write_reduced_manifold(normal, std::span(candidates.data(), std::size_t(count)), out);
}

int edge_contact(const ConvexHull& a, const PlacedHull& b, const SatEdgeQuery& query, Real margin,
                 Manifold& out) {
  const HullEdge& ea = a.edges()[std::size_t(query.edge_a)];
  const HullEdge& eb = b.hull->edges()[std::size_t(query.edge_b)];
  const Vec3 a0 = a.vertex(ea.vertex[0]);
  const Vec3 a1 = a.vertex(ea.vertex[1]);
  const Vec3 b0 = b.vertex(eb.vertex[0]);
  const Vec3 b1 = b.vertex(eb.vertex[1]);
  Real s = 0;
  Real t = 0;
  closest_parameters_between_segments(a0, a1, b0, b1, s, t);
  const Vec3 on_a = a0 + (a1 - a0) * s;
  const Vec3 on_b = b0 + (b1 - b0) * t;
  const Vec3 normal = -query.axis;  // from B to A
  out.normal = normal;
  add_contact(out, on_a, normal, (on_b - on_a).dot(normal), margin,
              {edge_id(ea.vertex[0]), edge_id(eb.vertex[0])});
  return out.count;
}

// Moves a manifold from A's frame into the pair frame (A's rotation; A sits at the origin).
int to_pair_frame(const Transform& pose_a, Manifold& out) {
  out.normal = pose_a.rotate(out.normal);
  for (int i = 0; i < out.count; ++i)
    out.points[std::size_t(i)].position = pose_a.apply(out.points[std::size_t(i)].position);
  return out.count;
}

}  // namespace

enum class Kind { face_of_a, face_of_b, edges };

int hull_hull(const Shape& shape_a, const Transform& pose_a, const Shape& shape_b,
              const Transform& pose_b, Real margin, Manifold& out) {
  const ConvexHull& a = *shape_a.hull;
  const ConvexHull& b = *shape_b.hull;
  // B in A's frame.
  const Transform b_in_a{pose_a.apply_inverse(pose_b.translation),
                         pose_a.rotation.conjugate() * pose_b.rotation};
  const SatResult sat = hull_sat_query(a, b, b_in_a, margin);
  if (sat.status == SatStatus::too_big)
    return convex_convex(shape_a, pose_a, shape_b, pose_b, margin, out);
  if (sat.status == SatStatus::separated)
    return 0;

  // The axis: A's face, B's face when clearly better, an edge pair when clearly better still.
  const Real scale = a.bounding_radius() + b.bounding_radius();
  Kind kind = Kind::face_of_a;
  Real chosen = sat.face_a.separation;
  if (clearly_more_separated(sat.face_b.separation, chosen, scale)) {
    kind = Kind::face_of_b;
    chosen = sat.face_b.separation;
  }
  if (sat.edges.edge_a >= 0 && clearly_more_separated(sat.edges.separation, chosen, scale)) {
    kind = Kind::edges;
    chosen = sat.edges.separation;
  }
  const Real best = sat.max_separation();
  if (!std::isfinite(best))
    return 0;  // non-finite poses: no contact rather than NaN
  // The axis that realises the largest separation exactly (faces first on ties).
  Kind best_kind = Kind::face_of_a;
  if (sat.face_b.separation > sat.face_a.separation)
    best_kind = Kind::face_of_b;
  if (sat.edges.edge_a >= 0 &&
      sat.edges.separation > std::max(sat.face_a.separation, sat.face_b.separation))
    best_kind = Kind::edges;

  if (best > 0) {
    // Apart within the margin: the best axis may underestimate the distance (vertex to vertex).
    const GjkResult g = gjk(ConvexSupport::of(shape_a, pose_a), ConvexSupport::of(shape_b, pose_b));
    if (g.status != GjkStatus::intersecting &&
        best < g.distance - kRealisesDistanceTolerance * scale) {
      return convex_convex(shape_a, pose_a, shape_b, pose_b, margin, out);
    }
  }

  const PlacedHull placed_a{&a, Transform{}};
  const PlacedHull placed_b{&b, b_in_a};
  const auto contacts = [&](Kind k) {
    out = Manifold{};
    switch (k) {
      case Kind::face_of_a:
        return face_contacts(placed_a, sat.face_a.face, placed_b, sat.face_a.vertex, true, margin,
                             out);
      case Kind::face_of_b:
        return face_contacts(placed_b, sat.face_b.face, placed_a, sat.face_b.vertex, false, margin,
                             out);
      case Kind::edges:
        return edge_contact(a, placed_b, sat.edges, margin, out);
    }
    return 0;
  };
  int count = contacts(kind);
  if (kind != best_kind) {
    // The biased choice must see its own whole penetration: its deepest point as deep as its
    // axis says, so that moving A by that depth along the normal separates the hulls. A face
    // kept over a slightly better axis can fail that when its clipped polygon misses the deepest
    // part (or is empty); the best axis then answers (its deepest point always reaches its
    // depth). The reported depth is so never below the true one, and above it by at most the
    // bias.
    Real deepest = -std::numeric_limits<Real>::infinity();
    for (int i = 0; i < count; ++i)
      deepest = std::max(deepest, out.points[std::size_t(i)].depth);
    if (count <= 0 || deepest < -chosen - kRealisesDistanceTolerance * scale)
      count = contacts(best_kind);
  }
  if (count <= 0) {
    // A face too big for the clipping buffers, or no point within the margin: the generic pair
    // answers.
    out = Manifold{};
    return convex_convex(shape_a, pose_a, shape_b, pose_b, margin, out);
  }
  return to_pair_frame(pose_a, out);
}

}  // namespace tumble::detail
