// The hull-hull separating-axis test (collision/narrow_phase/pairs/hull_hull_sat.cpp) against
// independent truth:
//   * the Gauss-map arc predicate against arcs sampled point by point;
//   * the query's largest separation against brute force over every face normal and every edge
//     pair's cross product (no pruning, separations by projecting every vertex), and against
//     EPA's depth; the Gauss-map pruning and the bound never lose the best edge pair;
//   * the manifold: points on both surfaces, depths no deeper than the true depth (plus the face
//     bias), mirrored exactly when A and B are swapped, feature ids that persist under small
//     motion;
//   * degenerate input: touching exactly, coplanar faces, 1e-6 m and 1e4 m hulls, 1e6 m from the
//     origin: finite answers and a status.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <vector>

#include "collision/narrow_phase/gjk_epa/epa.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/narrow_phase/pairs/hull_hull_sat.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"
#include "tests/collision/oracle.hpp"
#include "tests/property_scale.hpp"

namespace tumble::testing {
namespace {

using detail::hull_sat_query;
using detail::SatEdgePruning;
using detail::SatResult;
using detail::SatStatus;

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

Shape hull_from(std::vector<Vec3> points) {
  return Shape::convex_hull(std::make_shared<const ConvexHull>(ConvexHull::from_points(points)));
}

Shape box_hull(const Vec3& half) {
  std::vector<Vec3> corners;
  for (int v = 0; v < 8; ++v)
    corners.push_back(Vec3(v & 1 ? half.x() : -half.x(), v & 2 ? half.y() : -half.y(),
                           v & 4 ? half.z() : -half.z()));
  return hull_from(corners);
}

// B's placement in A's frame.
Transform relative(const Transform& pose_a, const Transform& pose_b) {
  return {pose_a.apply_inverse(pose_b.translation), pose_a.rotation.conjugate() * pose_b.rotation};
}

// Separation along unit n (A's frame, from A to B) by projecting every vertex.
Real separation_by_projection(const ConvexHull& a, const ConvexHull& b, const Transform& b_in_a,
                              const Vec3& n) {
  Real max_a = -kInfinity;
  for (const Vec3& v : a.vertices())
    max_a = std::max(max_a, n.dot(v));
  Real min_b = kInfinity;
  for (const Vec3& v : b.vertices())
    min_b = std::min(min_b, n.dot(b_in_a.apply(v)));
  return min_b - max_a;
}

struct BruteForce {
  Real faces = -kInfinity;  // best over both hulls' face normals
  Real edges = -kInfinity;  // best over every edge pair's cross product
  Real best() const { return std::max(faces, edges); }
};

// Every face normal and every edge pair, no pruning. Near-parallel pairs are skipped as in the
// query (their axis is mostly rounding; the faces cover them).
BruteForce brute_force(const ConvexHull& a, const ConvexHull& b, const Transform& b_in_a) {
  BruteForce out;
  for (const HullFace& f : a.faces())
    out.faces = std::max(out.faces, separation_by_projection(a, b, b_in_a, f.normal));
  for (const HullFace& f : b.faces())
    out.faces =
        std::max(out.faces, separation_by_projection(a, b, b_in_a, -b_in_a.rotate(f.normal)));
  for (const HullEdge& ea : a.edges()) {
    const Vec3 da = a.vertex(ea.vertex[1]) - a.vertex(ea.vertex[0]);
    for (const HullEdge& eb : b.edges()) {
      const Vec3 db = b_in_a.rotate(b.vertex(eb.vertex[1]) - b.vertex(eb.vertex[0]));
      const Vec3 cross = da.cross(db);
      if (!(cross.norm() > 1e-6 * da.norm() * db.norm()))
        continue;
      const Vec3 n = cross.normalized();
      // Both orientations: the better one is the axis's separation.
      out.edges = std::max({out.edges, separation_by_projection(a, b, b_in_a, n),
                            separation_by_projection(a, b, b_in_a, -n)});
    }
  }
  return out;
}

void random_poses(Rng& rng, const Shape& a, const Shape& b, Real low, Real high, Transform& pose_a,
                  Transform& pose_b) {
  pose_a = {random_vector_in_box(rng, 3), random_rotation(rng)};
  pose_b = {pose_a.translation + random_unit_vector(rng) * uniform(rng, low, high) *
                                     (bounding_radius(a) + bounding_radius(b)),
            random_rotation(rng)};
}

bool finite(const Manifold& m) {
  if (!m.normal.allFinite())
    return false;
  for (int i = 0; i < m.count; ++i)
    if (!m.points[std::size_t(i)].position.allFinite() ||
        !std::isfinite(m.points[std::size_t(i)].depth))
      return false;
  return true;
}

// ---- The Gauss-map predicate ----------------------------------------------------------------

// Whether arcs a-b and c-d cross, by walking along c-d: where the walk crosses the plane of a-b,
// is the crossing point between a and b?
bool arcs_cross_by_sampling(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 plane = a.cross(b);
  constexpr int kSteps = 4000;
  Vec3 previous = c;
  for (int k = 1; k <= kSteps; ++k) {
    const Real t = Real(k) / kSteps;
    const Vec3 p = (c * (1 - t) + d * t).normalized();
    if ((previous.dot(plane) <= 0) != (p.dot(plane) <= 0)) {
      // p is on the great circle of a-b (up to a step); between a and b when both
      // a x p and p x b point along a x b.
      return a.cross(p).dot(plane) >= 0 && p.cross(b).dot(plane) >= 0;
    }
    previous = p;
  }
  return false;
}

TEST(HullHullSat, ArcPredicateMatchesSampledArcs) {
  Rng rng(7001);
  int crossing = 0;
  int judged = 0;
  const int cases = scaled(3000);
  for (int i = 0; i < cases; ++i) {
    const Vec3 a = random_unit_vector(rng);
    const Vec3 b = (a + random_unit_vector(rng) * uniform(rng, 0.1, 1.2)).normalized();
    // c near the middle of a-b, so that both answers are common.
    const Vec3 c = (a + b + random_unit_vector(rng) * uniform(rng, 0, 1.2)).normalized();
    const Vec3 d = (c + random_unit_vector(rng) * uniform(rng, 0.1, 1.2)).normalized();
    // Skip near-touching configurations that the sampling cannot decide.
    const Real margin = std::min({std::abs(c.dot(b.cross(a))), std::abs(d.dot(b.cross(a))),
                                  std::abs(a.dot(d.cross(c))), std::abs(b.dot(d.cross(c)))});
    if (margin < 1e-2)
      continue;
    ++judged;
    const bool expected = arcs_cross_by_sampling(a, b, c, d);
    crossing += expected ? 1 : 0;
    EXPECT_EQ(detail::arcs_intersect(a, b, b.cross(a), c, d, d.cross(c)), expected) << "case " << i;
  }
  EXPECT_GT(judged, cases / 2);
  EXPECT_GT(crossing, judged / 10);  // both answers are exercised
  EXPECT_GT(judged - crossing, judged / 10);
}

// ---- The query against brute force ----------------------------------------------------------

TEST(HullHullSat, SeparationMatchesBruteForceAndEpaAndPruningLosesNothing) {
  Rng rng(7002);
  int penetrating = 0;
  int separated = 0;
  int edge_wins = 0;
  long pairs_with_bound = 0;
  long pairs_gauss_only = 0;
  long pairs_all = 0;
  Real worst_brute = 0;
  Real worst_epa = 0;
  const int cases = scaled(1500);
  for (int i = 0; i < cases; ++i) {
    const Shape a = random_shape(rng, ShapeType::hull);
    const Shape b = random_shape(rng, ShapeType::hull);
    Transform pose_a;
    Transform pose_b;
    random_poses(rng, a, b, 0, 1.2, pose_a, pose_b);
    const Transform b_in_a = relative(pose_a, pose_b);
    const Real scale = bounding_radius(a) + bounding_radius(b);
    const Real tolerance = 1e-9 * scale;
    SCOPED_TRACE(::testing::Message() << "case " << i);

    const SatResult pruned = hull_sat_query(*a.hull, *b.hull, b_in_a, kInfinity);
    const SatResult gauss =
        hull_sat_query(*a.hull, *b.hull, b_in_a, kInfinity, SatEdgePruning::gauss_map);
    ASSERT_EQ(pruned.status, SatStatus::overlapping);
    ASSERT_EQ(gauss.status, SatStatus::overlapping);
    const BruteForce brute = brute_force(*a.hull, *b.hull, b_in_a);
    pairs_with_bound += pruned.edge_pairs_tested;
    pairs_gauss_only += gauss.edge_pairs_tested;
    pairs_all += long(a.hull->edges().size() * b.hull->edges().size());

    // The bound only drops edges that cannot win: the same answer, bit for bit.
    EXPECT_EQ(pruned.max_separation(), gauss.max_separation());

    // Every reported separation is the true separation along its axis.
    if (pruned.edges.edge_a >= 0) {
      EXPECT_NEAR(pruned.edges.separation,
                  separation_by_projection(*a.hull, *b.hull, b_in_a, pruned.edges.axis), tolerance);
    }
    const Vec3 face_a_normal = a.hull->faces()[std::size_t(pruned.face_a.face)].normal;
    EXPECT_NEAR(pruned.face_a.separation,
                separation_by_projection(*a.hull, *b.hull, b_in_a, face_a_normal), tolerance);

    const Real best = pruned.max_separation();
    if (brute.best() <= 0) {
      // Penetrating: the largest separation over all axes is attained at a face of the
      // Minkowski difference, which the pruned query tests.
      ++penetrating;
      EXPECT_NEAR(best, brute.best(), tolerance);
      worst_brute = std::max(worst_brute, std::abs(best - brute.best()) / scale);
      // An edge pair is the true optimum: the Gauss map kept it.
      if (brute.edges > brute.faces + tolerance) {
        ++edge_wins;
        EXPECT_NEAR(gauss.edges.separation, brute.edges, tolerance);
      }
      const ConvexSupport sa = ConvexSupport::of(a, pose_a);
      const ConvexSupport sb = ConvexSupport::of(b, pose_b);
      const GjkResult g = gjk(sa, sb);
      if (g.status == GjkStatus::intersecting && brute.best() < -tolerance) {
        const EpaResult e = epa(sa, sb, g);
        EXPECT_NEAR(-e.depth, best, 1e-9 * scale);
        worst_epa = std::max(worst_epa, std::abs(-e.depth - best) / scale);
      }
    } else {
      // Separated: both see a separating axis; the Minkowski faces alone may give a smaller
      // (still positive) separation than an arbitrary edge cross, never a larger one.
      ++separated;
      EXPECT_GT(best, 0);
      EXPECT_LE(best, brute.best() + tolerance);
    }
  }
  std::printf(
      "hull SAT: %d penetrating (%d edge optima), %d separated; worst |SAT - brute| %.3g, "
      "|SAT - EPA| %.3g (of the size); edge pairs tested: %.1f%% with bound, %.1f%% Gauss map "
      "only\n",
      penetrating, edge_wins, separated, worst_brute, worst_epa,
      100.0 * Real(pairs_with_bound) / Real(pairs_all),
      100.0 * Real(pairs_gauss_only) / Real(pairs_all));
  EXPECT_GT(penetrating, cases / 4);
  EXPECT_GT(separated, cases / 10);
  EXPECT_GT(edge_wins, cases / 50);
}

// ---- The manifold ---------------------------------------------------------------------------

TEST(HullHullSat, ManifoldPointsLieOnBothHullsAndMatchTheDepth) {
  Rng rng(7003);
  int with_points = 0;
  const int cases = scaled(1500);
  for (int i = 0; i < cases; ++i) {
    const Shape a = random_shape(rng, ShapeType::hull);
    const Shape b = random_shape(rng, ShapeType::hull);
    Transform pose_a;
    Transform pose_b;
    random_poses(rng, a, b, 0.2, 1.1, pose_a, pose_b);
    const Real scale = bounding_radius(a) + bounding_radius(b);
    const Real margin = 0.02 * scale;
    const Real tolerance = 1e-9 * scale;
    SCOPED_TRACE(::testing::Message() << "case " << i);
    Manifold m;
    const int count = collide(a, pose_a, b, pose_b, margin, m);
    ASSERT_TRUE(finite(m));
    const Real truth = brute_force_signed_distance(a, pose_a, b, pose_b);
    if (truth > margin + tolerance) {
      EXPECT_EQ(count, 0);
      continue;
    }
    if (truth < -tolerance) {
      EXPECT_GE(count, 1);  // penetrating hulls always get a point
    }
    if (count == 0)
      continue;
    ++with_points;
    EXPECT_NEAR(m.normal.norm(), 1, 1e-12);
    const Real true_depth = -truth;
    // The face bias may keep a face whose depth exceeds the best axis by 2 % of its own depth
    // plus 1e-5 of the pair's size (clearly_more_separated): by up to that over 1 - 2 % of the
    // best axis's depth.
    const Real allowed =
        true_depth + (0.02 * std::abs(true_depth) + 1e-5 * scale) / (1 - 0.02) + tolerance;
    for (int k = 0; k < count; ++k) {
      const ContactPoint& p = m.points[std::size_t(k)];
      EXPECT_LE(p.depth, allowed);
      EXPECT_GE(p.depth, -margin - tolerance);
      const Vec3 on_a = p.point_on_a(m.normal);
      const Vec3 on_b = p.point_on_b(m.normal);
      EXPECT_LE(signed_distance_to_shape(a, pose_a, on_a), tolerance);
      EXPECT_LE(signed_distance_to_shape(b, pose_b, on_b), tolerance);
      // On the surfaces, not deep inside: a point's surface point is within the depth of the
      // other hull's surface.
      EXPECT_GE(signed_distance_to_shape(a, pose_a, on_a),
                -std::max(true_depth, Real(0)) * 1.05 - 1e-5 * scale - tolerance);
    }
  }
  EXPECT_GT(with_points, cases / 3);
}

TEST(HullHullSat, SwappingAAndBMirrorsTheManifoldExactly) {
  Rng rng(7004);
  const int cases = scaled(1000);
  int compared = 0;
  for (int i = 0; i < cases; ++i) {
    const Shape a = random_shape(rng, ShapeType::hull);
    const Shape b = random_shape(rng, ShapeType::hull);
    Transform pose_a;
    Transform pose_b;
    random_poses(rng, a, b, 0, 1.1, pose_a, pose_b);
    Manifold ab;
    Manifold ba;
    const int n_ab = collide(a, pose_a, b, pose_b, 0.01, ab);
    const int n_ba = collide(b, pose_b, a, pose_a, 0.01, ba);
    ASSERT_EQ(n_ab, n_ba) << "case " << i;
    if (n_ab == 0)
      continue;
    ++compared;
    EXPECT_EQ(ab.normal, Vec3(-ba.normal)) << "case " << i;
    for (int k = 0; k < n_ab; ++k) {
      EXPECT_EQ(ab.points[std::size_t(k)].position, ba.points[std::size_t(k)].position);
      EXPECT_EQ(ab.points[std::size_t(k)].depth, ba.points[std::size_t(k)].depth);
      EXPECT_EQ(ab.points[std::size_t(k)].feature, ba.points[std::size_t(k)].feature.swapped());
    }
  }
  EXPECT_GT(compared, cases / 3);
}

TEST(HullHullSat, CubeOnCubeGivesFourPointsAtTheExactDepth) {
  // Two unit cubes as hulls, B on top of A turned 45 degrees about z, sunk by 0.01: the face
  // contact is an octagon, reduced to four points, every one 0.01 deep, normal +z... from B to A
  // that is -z.
  const Shape cube = box_hull(Vec3(0.5, 0.5, 0.5));
  const Transform pose_a{Vec3(0.3, -0.2, 0.1), Quat::Identity()};
  const Transform pose_b{pose_a.translation + Vec3(0, 0, 0.99),
                         Quat(Eigen::AngleAxis<Real>(0.785398, Vec3::UnitZ()))};
  Manifold m;
  ASSERT_EQ(detail::hull_hull(cube, pose_a, cube, pose_b, 0, m), 4);
  EXPECT_NEAR((m.normal - Vec3(0, 0, -1)).norm(), 0, 1e-12);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(m.points[std::size_t(k)].depth, 0.01, 1e-12);
    EXPECT_NEAR(m.points[std::size_t(k)].position.z() - pose_a.translation.z(), 0.495, 1e-12);
  }
}

TEST(HullHullSat, FeatureIdsPersistUnderSmallMotion) {
  // A resting box hull nudged by 1e-4 m and 1e-4 rad keeps the same points: the solver can warm
  // start them.
  Rng rng(7005);
  const Shape lower = box_hull(Vec3(1.0, 1.0, 0.25));
  const int cases = scaled(200);
  int same = 0;
  for (int i = 0; i < cases; ++i) {
    const Shape upper = random_shape(rng, ShapeType::hull);
    const Transform pose_a{Vec3::Zero(), Quat::Identity()};
    // The upper hull rests on its best face pointing down.
    const ConvexHull& hull = *upper.hull;
    const HullFace& face =
        hull.faces()[std::size_t(int(uniform(rng, 0, 0.999) * Real(hull.faces().size())))];
    const Quat down = Quat::FromTwoVectors(face.normal, -Vec3::UnitZ());
    const Transform pose_b{
        Vec3(uniform(rng, -0.3, 0.3), uniform(rng, -0.3, 0.3), 0.25 + face.offset - 0.002), down};
    Manifold before;
    Manifold after;
    collide(upper, pose_b, lower, pose_a, 0.01, before);
    const Transform nudged{pose_b.translation + Vec3(1e-4, -1e-4, 0),
                           pose_b.rotation * Quat(Eigen::AngleAxis<Real>(1e-4, Vec3::UnitX()))};
    collide(upper, nudged, lower, pose_a, 0.01, after);
    ASSERT_GE(before.count, 1);
    if (before.count != after.count)
      continue;
    bool all = true;
    for (int k = 0; k < before.count; ++k) {
      bool found = false;
      for (int j = 0; j < after.count; ++j)
        found =
            found || after.points[std::size_t(j)].feature == before.points[std::size_t(k)].feature;
      all = all && found;
    }
    same += all ? 1 : 0;
  }
  EXPECT_GE(same, cases * 9 / 10);
}

// ---- Degenerate input -----------------------------------------------------------------------

TEST(HullHullSat, DegenerateInputGivesFiniteAnswersAndAStatus) {
  Rng rng(7006);
  const int cases = scaled(300);
  for (int i = 0; i < cases; ++i) {
    const Real size = i % 3 == 0 ? 1e-6 : (i % 3 == 1 ? 1e4 : 1.0);
    const Vec3 far = i % 2 == 0 ? Vec3(1e6, -1e6, 1e6) : Vec3::Zero();
    SCOPED_TRACE(::testing::Message() << "case " << i << " size " << size);
    const Shape cube = box_hull(Vec3(1, 0.7, 0.5) * size);
    // Touching exactly, face on face (coplanar faces).
    {
      const Transform pose_a{far, Quat::Identity()};
      const Transform pose_b{far + Vec3(0.2 * size, 0.1 * size, 1.0 * size), Quat::Identity()};
      Manifold m;
      const int count = collide(cube, pose_a, cube, pose_b, 0, m);
      EXPECT_TRUE(finite(m));
      if (far == Vec3::Zero()) {
        EXPECT_GE(count, 1);
        for (int k = 0; k < count; ++k)
          EXPECT_NEAR(m.points[std::size_t(k)].depth, 0, 1e-12 * size);
      }
      const SatResult r = hull_sat_query(*cube.hull, *cube.hull, relative(pose_a, pose_b), 0);
      EXPECT_NE(r.status, SatStatus::too_big);
      EXPECT_TRUE(std::isfinite(r.max_separation()));
    }
    // Nearly coplanar: a tilt of 1e-9 rad, random offsets, random hulls.
    {
      const Shape other = random_shape(rng, ShapeType::hull);
      std::vector<Vec3> points;
      for (const Vec3& v : other.hull->vertices())
        points.push_back(v * size);
      const Shape scaled_hull = hull_from(points);
      const Quat tilt(Eigen::AngleAxis<Real>(1e-9, random_unit_vector(rng)));
      const Transform pose_a{far + random_vector_in_box(rng, size), random_rotation(rng)};
      const Transform pose_b{pose_a.translation + random_unit_vector(rng) * uniform(rng, 0, 1.5) *
                                                      bounding_radius(scaled_hull),
                             tilt * pose_a.rotation};
      Manifold m;
      const int count = collide(scaled_hull, pose_a, scaled_hull, pose_b, 1e-3 * size, m);
      EXPECT_TRUE(finite(m));
      EXPECT_LE(count, kMaxManifoldPoints);
      const SatResult r =
          hull_sat_query(*scaled_hull.hull, *scaled_hull.hull, relative(pose_a, pose_b), kInfinity);
      EXPECT_EQ(r.status, SatStatus::overlapping);
      EXPECT_TRUE(std::isfinite(r.max_separation()));
      // The depth agrees with brute force at every scale (relative to the size).
      const BruteForce brute =
          brute_force(*scaled_hull.hull, *scaled_hull.hull, relative(pose_a, pose_b));
      if (brute.best() <= 0) {
        EXPECT_NEAR(r.max_separation(), brute.best(), 1e-9 * size);
      }
    }
  }
  // Non-finite poses: no contact, no NaN.
  const Shape cube = box_hull(Vec3(1, 1, 1));
  Manifold m;
  const Transform bad{Vec3(std::nan(""), 0, 0), Quat::Identity()};
  EXPECT_EQ(collide(cube, Transform{}, cube, bad, 0.1, m), 0);
  EXPECT_TRUE(finite(m));
}

}  // namespace
}  // namespace tumble::testing
