// Internal to the narrow phase: the separating-axis query between two convex hulls that the
// hull-hull pair (hull_hull_sat.cpp) is built on, exposed so that tests can compare it with brute
// force and with its own unpruned form.
//
// Source: Dirk Gregorius, "The Separating Axis Test between Convex Polyhedra", GDC 2013. The
// candidate axes of two polytopes are the face normals of each, and the cross products of edge
// pairs; of the edge pairs only those whose arcs on the Gauss map intersect (the pairs that build
// a face of the Minkowski difference) can realise the minimum penetration, so only they are
// tested.
#pragma once

#include <limits>

#include "collision/math.hpp"
#include "collision/shapes/convex_hull.hpp"

namespace tumble::detail {

// Which edge pairs the query tests.
enum class SatEdgePruning {
  // Gauss-map arcs that intersect, and of those only the edges whose separation can still beat
  // the best face (a bound from the inscribed radius of the other hull): the production setting.
  gauss_map_and_bound,
  // Every pair whose Gauss-map arcs intersect (no bound): for tests of the bound.
  gauss_map,
};

// Axes point from A to B: separation along n = min over B of n.x - max over A of n.x (positive:
// the hulls are that far apart along n; negative: they overlap by that much along n).
struct SatFaceQuery {
  int face = -1;    // face of the hull whose normal is the axis
  int vertex = -1;  // the other hull's deepest vertex against that face's plane
  Real separation = -std::numeric_limits<Real>::infinity();
};

struct SatEdgeQuery {
  int edge_a = -1;  // edges of A and B (HullEdge indices); -1 when no pair was found
  int edge_b = -1;
  Vec3 axis = Vec3::Zero();  // unit, A's frame, from A to B
  Real separation = -std::numeric_limits<Real>::infinity();
};

enum class SatStatus {
  separated,    // some axis separates by more than the stop distance; the query stopped there
  overlapping,  // no axis separates by more than the stop distance; all three queries are done
  too_big,      // a hull has more edges or faces than the fixed buffers hold; nothing was tested
};

struct SatResult {
  SatStatus status = SatStatus::too_big;
  SatFaceQuery face_a;  // A's faces against B's vertices
  SatFaceQuery face_b;  // B's faces (normal turned into A's frame) against A's vertices
  SatEdgeQuery edges;
  int edge_pairs_tested = 0;  // arc tests run (a measure of the pruning)

  Real max_separation() const {
    const Real faces =
        face_a.separation > face_b.separation ? face_a.separation : face_b.separation;
    return edges.separation > faces ? edges.separation : faces;
  }
};

// The buffers of the edge query hold this many edges per hull; bigger hulls get SatStatus::
// too_big and the caller uses GJK/EPA instead.
inline constexpr int kSatMaxEdges = 384;

// Separating-axis query of hull `b` placed by `b_in_a` in the frame of hull `a`. Stops as soon
// as an axis separates by more than `stop_above` (pass +infinity to get every query complete).
SatResult hull_sat_query(const ConvexHull& a, const ConvexHull& b, const Transform& b_in_a,
                         Real stop_above,
                         SatEdgePruning pruning = SatEdgePruning::gauss_map_and_bound);

// Whether the arc a-b and the arc c-d (unit vectors, each arc shorter than a half circle) cross
// on the unit sphere. `b_x_a` = b x a and `d_x_c` = d x c are passed in because the caller keeps
// them per edge.
inline bool arcs_intersect(const Vec3& a, const Vec3& b, const Vec3& b_x_a, const Vec3& c,
                           const Vec3& d, const Vec3& d_x_c) {
  // c and d on opposite sides of the plane of a-b, a and b on opposite sides of the plane of
  // c-d, and the crossings on the same side (not antipodal): the last sign test picks the
  // hemisphere.
  const Real cba = c.dot(b_x_a);
  const Real dba = d.dot(b_x_a);
  const Real adc = a.dot(d_x_c);
  const Real bdc = b.dot(d_x_c);
  return cba * dba < 0 && adc * bdc < 0 && cba * bdc > 0;
}

}  // namespace tumble::detail
