// Internal to the narrow phase: the pair functions that the dispatch table in narrow_phase.cpp
// calls, the feature numbering they share, and the small geometric helpers they have in common.
//
// Every pair function has the contract of `collide()` for one order of one pair of shape types
// (the order of its name): `a` and `b` arrive with their poses already moved into the
// pair-local frame, it writes at most kMaxManifoldPoints points with depth >= -margin into `out`
// (which arrives empty) with the normal pointing from b to a, and it returns out.count. The table
// builds the other order by flipping, so no pair function is ever written twice.
#pragma once

#include <cstdint>

#include "collision/contact.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/shapes/shape.hpp"

namespace tumble::detail {

using PairFunction = int (*)(const Shape& a, const Transform& pose_a, const Shape& b,
                             const Transform& pose_b, Real margin, Manifold& out);

// sphere_pairs.cpp. sphere_sphere is symmetric in A and B by construction and works in world
// coordinates: the table calls it directly, and collide_sphere_pairs (sphere_batch.cpp) repeats
// its arithmetic lane by lane.
int sphere_sphere(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                  Real margin, Manifold& out);
int sphere_capsule(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                   Real margin, Manifold& out);
int sphere_box(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
               Real margin, Manifold& out);
int sphere_plane(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                 Real margin, Manifold& out);

// capsule_pairs.cpp
int capsule_capsule(const Shape& a, const Transform& pose_a, const Shape& b,
                    const Transform& pose_b, Real margin, Manifold& out);
int capsule_plane(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                  Real margin, Manifold& out);

// capsule_box.cpp
int capsule_box(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                Real margin, Manifold& out);

// box_plane.cpp
int box_plane(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
              Real margin, Manifold& out);

// sdf_pairs.cpp: any shape but a compound (sphere, box, capsule, plane, cylinder, hull, mesh)
// against a signed distance field, and two fields.
int any_sdf(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out);
int sdf_sdf(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out);

// narrow_phase.cpp: whether `a` goes first when two shapes of one type meet (the order collide()
// runs their pair function in, and collide_box_pairs too).
bool runs_first(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b);
// The same for two boxes given by their half extents (collide_box_pairs).
bool boxes_run_first(const Vec3& half_a, const Transform& pose_a, const Vec3& half_b,
                     const Transform& pose_b);

// box_box.cpp
int box_box(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out);

// convex_pairs.cpp: cylinder and hull against every convex shape through GJK/EPA and feature
// clipping, and their analytic plane pairs.
int convex_convex(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                  Real margin, Manifold& out);
// The same with GJK started from `cache` (null: from the centres' offset); GJK leaves its last
// separating axis there (collision/narrow_phase/gjk_epa/gjk.hpp).
int convex_convex_cached(const Shape& a, const Transform& pose_a, const Shape& b,
                         const Transform& pose_b, Real margin, Manifold& out, GjkCache* cache);
int cylinder_plane(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                   Real margin, Manifold& out);
int sphere_cylinder(const Shape& a, const Transform& pose_a, const Shape& b,
                    const Transform& pose_b, Real margin, Manifold& out);
int capsule_cylinder(const Shape& a, const Transform& pose_a, const Shape& b,
                     const Transform& pose_b, Real margin, Manifold& out);
int hull_plane(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
               Real margin, Manifold& out);

// hull_hull_sat.cpp: two hulls by the separating-axis test with face clipping (Gregorius, GDC
// 2013); hulls too big for its buffers go to convex_convex.
int hull_hull(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
              Real margin, Manifold& out);

// mesh_pairs.cpp: a convex shape (sphere, box, capsule) against a static triangle mesh.
int convex_mesh(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                Real margin, Manifold& out);

// ---------------------------------------------------------------------------------------------
// Feature ids. Each shape numbers its own features so that a contact point keeps its id while
// the bodies move a little, and the solver can match it with last step's point.
//   sphere:  0
//   plane:   0 (its one face)
//   capsule: 0 = the end cap at local z = -half_length, 1 = the cap at +half_length,
//            2 = the cylindrical side between them
//   box:     vertices 0..7, bit k set when the vertex has a positive coordinate k;
//            edges 8..19, 8 + 4 * axis + two sign bits of the other two axes (lower axis first);
//            faces 20..25, 20 + 2 * axis + (1 on the positive side)
//   mesh:    0xffff for a point inside a triangle's face (any triangle: a point sliding across
//            a flat mesh keeps its id); else 8 * triangle + region (1..3 edges, 4..6 corners),
//            modulo 2^16 (unique up to 8191 triangles; beyond, the solver's nearest-point
//            fallback matches points)
//   compound: (part index << 8) | (the part's own feature & 0xff)
namespace feature {

inline constexpr std::uint16_t kSphere = 0;
inline constexpr std::uint16_t kPlane = 0;
inline constexpr std::uint16_t kCapsuleEnd0 = 0;
inline constexpr std::uint16_t kCapsuleEnd1 = 1;
inline constexpr std::uint16_t kCapsuleSide = 2;

inline constexpr std::uint16_t kBoxFirstEdge = 8;
inline constexpr std::uint16_t kBoxFirstFace = 20;

// `sign_bits`: bit k set when coordinate k is positive.
constexpr std::uint16_t box_vertex(int sign_bits) {
  return std::uint16_t(sign_bits & 7);
}

// The edge parallel to `axis` through the vertex with `sign_bits` (the bit of `axis` is ignored).
constexpr std::uint16_t box_edge(int axis, int sign_bits) {
  const int lower = axis == 0 ? 1 : 0;
  const int upper = axis == 2 ? 1 : 2;
  const int bits = ((sign_bits >> lower) & 1) | (((sign_bits >> upper) & 1) << 1);
  return std::uint16_t(kBoxFirstEdge + 4 * axis + bits);
}

constexpr std::uint16_t box_face(int axis, bool positive) {
  return std::uint16_t(kBoxFirstFace + 2 * axis + (positive ? 1 : 0));
}

// The capsule feature at parameter t along its core segment (t = 0 at end 0, t = 1 at end 1).
constexpr std::uint16_t capsule_feature_at(Real t) {
  return t <= 0 ? kCapsuleEnd0 : (t >= 1 ? kCapsuleEnd1 : kCapsuleSide);
}

inline constexpr std::uint16_t kMeshFace = 0xffff;

constexpr std::uint16_t mesh_feature(int triangle, int region) {
  return std::uint16_t((triangle * 8 + region) & 0xffff);
}

constexpr std::uint16_t compound_feature(int part, std::uint16_t part_feature) {
  return std::uint16_t(((part & 0xff) << 8) | (part_feature & 0xff));
}

}  // namespace feature

// ---------------------------------------------------------------------------------------------
// Shared geometry (geometry.cpp).

// The two world end points of a capsule's core segment: end 0 at local -z, end 1 at local +z.
struct Segment {
  Vec3 start;
  Vec3 end;
};
Segment capsule_segment(const Shape& capsule, const Transform& pose);

// Parameter in [0, 1] of the point of segment [start, end] closest to `point`. A segment too
// short to define a direction counts as its start point (t = 0).
Real closest_parameter_on_segment(const Vec3& point, const Vec3& start, const Vec3& end);

// Parameters s, t in [0, 1] of the closest points p0 + s (p1 - p0) and q0 + t (q1 - q0) of two
// segments (Ericson, Real-Time Collision Detection, 2005, section 5.1.9). Parallel segments
// take s = 0 first and then the best t, so the answer is deterministic when it is not unique.
void closest_parameters_between_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                         const Vec3& q1, Real& s, Real& t);

// Signed distance from a point to the box [-h, h] in the box's frame: negative inside (Quilez,
// "Distance functions", iquilezles.org: |max(q, 0)| + min(max_k q_k, 0) with q = |p| - h).
Real box_signed_distance(const Vec3& point, const Vec3& half_extents);

// The feature of box [-h, h] whose Voronoi region holds `point` (box frame) when the point is
// outside: the face, edge or vertex selected by the coordinates that lie outside the slabs. A
// point inside or on the surface gets no outside coordinate; it returns the face feature of the
// slab it is closest to leaving, which is what the inside case uses.
std::uint16_t box_feature_of_outside_point(const Vec3& point, const Vec3& half_extents);

// A unit vector along v, or `fallback` when v is too short to have a direction. The fallback
// is what keeps every pair free of NaN for coincident centres and touching cores.
Vec3 normalized_or(const Vec3& v, const Vec3& fallback);

// Separating-axis choice with hysteresis (Box2D, b2CollidePolygons: k_relativeTol 0.98 and
// k_absoluteTol): a candidate axis (an edge axis against a face axis, or B's face against A's)
// replaces the incumbent only when its separation is clearly larger, by 2% of the incumbent's
// magnitude plus 1e-5 of the pair's size. Edge axes that equal a face axis up to rounding then
// never win, and the chosen feature does not flip between steps from noise alone.
inline bool clearly_more_separated(Real candidate, Real incumbent, Real scale) {
  constexpr Real kRelative = Real(0.02);
  constexpr Real kAbsolute = Real(1e-5);
  return candidate >
         incumbent + kRelative * (incumbent < 0 ? -incumbent : incumbent) + kAbsolute * scale;
}

// Writes a contact from its two surface points' description: the point on A, the normal (B to
// A) and the depth, so that point_on_a() gives back `point_on_a` and point_on_b() lies `depth`
// further along the normal. Drops the point when depth < -margin; returns whether it was kept.
bool add_contact(Manifold& out, const Vec3& point_on_a, const Vec3& normal, Real depth, Real margin,
                 FeatureId feature);

}  // namespace tumble::detail
