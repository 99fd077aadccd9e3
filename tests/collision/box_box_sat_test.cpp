// Box-box against a brute-force separating-axis test (the fast SAT of box_box.cpp).
// For thousands of random poses (fixed seed, TUMBLE_PROPERTY_SCALE scales the count) the test
// builds the 15 candidate axes in the world frame from the poses, measures each separation from
// the support maps of the oracle (min over A minus max over B, never box_box's own algebra),
// applies the documented choice rule of box_box (called directly, so that A is its first box) (face
// axes over edge axes and A's faces over B's unless the other is more separated by 2% of the
// incumbent's magnitude plus 1e-5 of the pair's size), and checks collide():
//   - no contact exactly when some axis separates the boxes by more than the margin,
//   - the normal is the chosen axis, pointing from B to A,
//   - penetrating: no point is deeper than the overlap along that axis, and the deepest point's
//     depth equals it (within 1e-9 of the pair's size) for an edge axis and for a face axis
//     whose incident box's deepest corner lies over the reference face (otherwise clipping
//     removes that corner and the depth is smaller); every point_on_a / point_on_b lies in
//     A / B, and the deepest on both surfaces,
//   - apart within the margin: the depth is minus the exact distance (oracle brute force),
//   - feature ids name box features (0..25) and no two points share one.
// Poses whose choice sits within 1e-9 of a threshold of the rule are counted and skipped (the
// rule is then decided by rounding); there must be few of them.
// A second test checks that the planar manifold reduction that box_box uses keeps the same
// points as the projecting one on random point clouds.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "collision/narrow_phase/pairs/manifold_reduction.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"
#include "tests/collision/oracle.hpp"
#include "tests/property_scale.hpp"

namespace tumble::testing {
namespace {

struct BruteAxis {
  Vec3 direction = Vec3::Zero();  // unit, from B to A
  Real separation = -std::numeric_limits<Real>::infinity();
  bool valid = false;
};

// The separation of the boxes along the line of `axis`, oriented from B to A: the larger of the
// two orientations' support-map separations.
BruteAxis measure(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                  const Vec3& axis) {
  BruteAxis out;
  out.valid = true;
  const Real plus = separation_along(a, pose_a, b, pose_b, axis);
  const Real minus = separation_along(a, pose_a, b, pose_b, -axis);
  out.direction = plus >= minus ? axis : Vec3(-axis);
  out.separation = std::max(plus, minus);
  return out;
}

// The documented preference: `candidate` replaces `incumbent` when it is more separated by 2%
// of the incumbent's magnitude plus 1e-5 of the pair's size. `margin_to_rule` gets how far the
// decision is from flipping.
bool clearly_more(Real candidate, Real incumbent, Real scale, Real& margin_to_rule) {
  const Real bar = incumbent + 0.02 * std::abs(incumbent) + 1e-5 * scale;
  margin_to_rule = std::min(margin_to_rule, std::abs(candidate - bar));
  return candidate > bar;
}

// The best axis of a group, the first on ties; `margin_to_rule` gets the gap to the runner-up.
BruteAxis best_of(const std::vector<BruteAxis>& axes, Real& margin_to_rule) {
  BruteAxis best;
  for (const BruteAxis& axis : axes) {
    if (axis.valid && axis.separation > best.separation)
      best = axis;
  }
  for (const BruteAxis& axis : axes) {
    if (axis.valid && axis.direction != best.direction &&
        std::abs(axis.direction.dot(best.direction)) < 1 - 1e-12) {
      margin_to_rule = std::min(margin_to_rule, best.separation - axis.separation);
    }
  }
  return best;
}

enum class Kind { face_of_a, face_of_b, edges };

struct Expected {
  BruteAxis chosen;
  Kind kind = Kind::face_of_a;
  Real largest_separation = -std::numeric_limits<Real>::infinity();
  bool is_face = true;
  Real margin_to_rule = std::numeric_limits<Real>::infinity();
};

Expected brute_force_choice(const Shape& a, const Transform& pose_a, const Shape& b,
                            const Transform& pose_b) {
  const Mat3 ra = pose_a.rotation.toRotationMatrix();
  const Mat3 rb = pose_b.rotation.toRotationMatrix();
  std::vector<BruteAxis> faces_a;
  std::vector<BruteAxis> faces_b;
  std::vector<BruteAxis> edges;
  for (int k = 0; k < 3; ++k) {
    faces_a.push_back(measure(a, pose_a, b, pose_b, ra.col(k)));
    faces_b.push_back(measure(a, pose_a, b, pose_b, rb.col(k)));
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Vec3 cross = ra.col(i).cross(rb.col(j));
      // Near-parallel edges (sine below 1e-6) have no axis of their own; the faces cover them.
      if (cross.norm() > 1e-6)
        edges.push_back(measure(a, pose_a, b, pose_b, cross.normalized()));
    }
  }
  Expected e;
  const Real scale = a.half_extents.norm() + b.half_extents.norm();
  const BruteAxis face_a = best_of(faces_a, e.margin_to_rule);
  const BruteAxis face_b = best_of(faces_b, e.margin_to_rule);
  const BruteAxis edge = best_of(edges, e.margin_to_rule);
  const bool b_face_wins =
      clearly_more(face_b.separation, face_a.separation, scale, e.margin_to_rule);
  const BruteAxis best_face = b_face_wins ? face_b : face_a;
  e.is_face =
      !(edge.valid && clearly_more(edge.separation, best_face.separation, scale, e.margin_to_rule));
  e.chosen = e.is_face ? best_face : edge;
  e.kind = !e.is_face ? Kind::edges : (b_face_wins ? Kind::face_of_b : Kind::face_of_a);
  e.largest_separation = std::max({face_a.separation, face_b.separation, edge.separation});
  return e;
}

Transform random_pose_near(Rng& rng, const Shape& a, const Transform& pose_a, const Shape& b) {
  Transform pose_b;
  pose_b.translation = pose_a.translation + random_unit_vector(rng) * uniform(rng, 0, 1.05) *
                                                (bounding_radius(a) + bounding_radius(b));
  const Real kind = uniform(rng, 0, 1);
  if (kind < 0.1) {
    pose_b.rotation = pose_a.rotation;  // face to face, parallel edges
  } else if (kind < 0.3) {
    pose_b.rotation = pose_a.rotation *
                      Quat(Eigen::AngleAxis<Real>(uniform(rng, 0, 0.05), random_unit_vector(rng)));
  } else {
    pose_b.rotation = random_rotation(rng);
  }
  return pose_b;
}

TEST(BoxBoxSat, ManifoldFollowsTheBruteForceFifteenAxisTest) {
  Rng rng(4242);
  const int poses = scaled(12000);
  int on_a_threshold = 0;
  int separated = 0;
  int penetrating = 0;
  int apart_within_margin = 0;
  int edge_chosen = 0;
  int depth_compared = 0;
  Real worst_depth_error = 0;
  Real worst_distance_error = 0;
  for (int i = 0; i < poses; ++i) {
    const Shape a = random_shape(rng, ShapeType::box);
    const Shape b = random_shape(rng, ShapeType::box);
    const Transform pose_a{random_vector_in_box(rng, 3), random_rotation(rng)};
    const Transform pose_b = random_pose_near(rng, a, pose_a, b);
    const Real margin = uniform(rng, 0, 1) < 0.3 ? Real(0) : uniform(rng, 0, 0.3);
    const Real scale = bounding_radius(a) + bounding_radius(b);
    const Real tolerance = 1e-9 * scale;
    SCOPED_TRACE("pose " + std::to_string(i));

    const Expected expected = brute_force_choice(a, pose_a, b, pose_b);
    if (expected.margin_to_rule < tolerance ||
        std::abs(expected.largest_separation - margin) < tolerance ||
        std::abs(expected.chosen.separation) < tolerance) {
      ++on_a_threshold;
      continue;
    }
    // box_box itself, so that A is the box whose faces the rule prefers (collide() puts the
    // two boxes in an order of its own).
    Manifold m;
    const int count = detail::box_box(a, pose_a, b, pose_b, margin, m);
    if (expected.largest_separation > margin) {
      EXPECT_EQ(count, 0) << "an axis separates the boxes by more than the margin";
      ++separated;
      continue;
    }
    // No axis separates by more than the margin; apart, the boxes may still be farther than
    // the margin (corner to corner), which the exact distance decides.
    const Real distance = expected.chosen.separation > 0
                              ? brute_force_signed_distance(a, pose_a, b, pose_b)
                              : expected.chosen.separation;
    if (std::abs(distance - margin) < tolerance) {
      ++on_a_threshold;
      continue;
    }
    if (distance > margin) {
      EXPECT_EQ(count, 0) << "a contact farther apart than the margin";
      ++separated;
      continue;
    }
    ASSERT_GT(count, 0) << "no contact, yet the boxes are within the margin";
    ASSERT_LE(count, kMaxManifoldPoints);
    const int deepest = deepest_point(m);
    const Real depth = m.points[deepest].depth;
    const Vec3& n = m.normal;
    ASSERT_TRUE(n.allFinite());
    EXPECT_NEAR(n.norm(), 1, 1e-12);

    for (int p = 0; p < count; ++p) {
      EXPECT_LT(m.points[p].feature.a, 26);
      EXPECT_LT(m.points[p].feature.b, 26);
      for (int q = 0; q < p; ++q)
        EXPECT_NE(m.points[p].feature, m.points[q].feature) << "two points share features";
    }

    if (expected.chosen.separation < 0) {
      ++penetrating;
      if (!expected.is_face)
        ++edge_chosen;
      // The normal is the chosen axis, from B to A, and the depth its overlap.
      EXPECT_GT(n.dot(expected.chosen.direction), 1 - 1e-9)
          << "normal " << n.transpose() << " expected " << expected.chosen.direction.transpose();
      // No point is deeper than the overlap along the axis. An edge axis's point joins the two
      // edges extreme along it, so its depth is that overlap; so is a face axis's deepest point
      // when the incident box's deepest corner lies over the reference face (strictly inside
      // its rectangle), since that corner survives the clipping.
      const Real overlap = -expected.chosen.separation;
      EXPECT_LE(depth, overlap + tolerance);
      bool depth_is_overlap = expected.kind == Kind::edges;
      if (expected.kind != Kind::edges) {
        const bool reference_is_a = expected.kind == Kind::face_of_a;
        const Shape& reference = reference_is_a ? a : b;
        const Transform& reference_pose = reference_is_a ? pose_a : pose_b;
        const Shape& incident = reference_is_a ? b : a;
        const Transform& incident_pose = reference_is_a ? pose_b : pose_a;
        // Towards the reference box: +n for B's corners (n points from B to A), -n for A's.
        const Vec3 towards = reference_is_a ? n : Vec3(-n);
        Vec3 deepest_corner = Vec3::Zero();
        Real best = -std::numeric_limits<Real>::infinity();
        for (int c = 0; c < 8; ++c) {
          const Vec3 local((c & 1) ? incident.half_extents.x() : -incident.half_extents.x(),
                           (c & 2) ? incident.half_extents.y() : -incident.half_extents.y(),
                           (c & 4) ? incident.half_extents.z() : -incident.half_extents.z());
          const Vec3 corner = incident_pose.apply(local);
          if (corner.dot(towards) > best) {
            best = corner.dot(towards);
            deepest_corner = corner;
          }
        }
        const Vec3 in_reference = reference_pose.apply_inverse(deepest_corner);
        const Vec3 normal_in_reference = reference_pose.rotate_inverse(towards);
        bool over_face = true;
        for (int k = 0; k < 3; ++k) {
          if (std::abs(normal_in_reference[k]) < 0.5)  // a tangent axis of the reference face
            over_face &= std::abs(in_reference[k]) < reference.half_extents[k] - 1e-6;
        }
        depth_is_overlap = over_face;
      }
      if (depth_is_overlap) {
        ++depth_compared;
        const Real depth_error = std::abs(depth - overlap);
        worst_depth_error = std::max(worst_depth_error, depth_error);
        EXPECT_LE(depth_error, tolerance)
            << "depth " << depth << " overlap along the axis " << overlap << " kind "
            << int(expected.kind) << " count " << count << " margin " << margin << " ha "
            << a.half_extents.transpose() << " hb " << b.half_extents.transpose() << " n "
            << n.transpose();
      }
      for (int p = 0; p < count; ++p) {
        const ContactPoint& point = m.points[p];
        EXPECT_LE(point.depth, depth + 1e-15);
        EXPECT_LE(signed_distance_to_shape(a, pose_a, point.point_on_a(n)), tolerance);
        EXPECT_LE(signed_distance_to_shape(b, pose_b, point.point_on_b(n)), tolerance);
      }
      EXPECT_LE(std::abs(signed_distance_to_shape(a, pose_a, m.points[deepest].point_on_a(n))),
                tolerance);
      EXPECT_LE(std::abs(signed_distance_to_shape(b, pose_b, m.points[deepest].point_on_b(n))),
                tolerance);
    } else {
      ++apart_within_margin;
      const Real distance_error = std::abs(-depth - distance);
      worst_distance_error = std::max(worst_distance_error, distance_error);
      EXPECT_LE(distance_error, tolerance) << "reported gap " << -depth << " distance " << distance;
      // The normal separates the boxes by that distance.
      EXPECT_NEAR(separation_along(a, pose_a, b, pose_b, n), distance, tolerance);
    }
    if (::testing::Test::HasFatalFailure())
      return;
  }
  std::printf(
      "[ stats    ] box-box vs brute-force SAT: %d poses, %d separated, %d penetrating (%d on "
      "an edge axis, %d depths compared), %d apart within the margin, %d skipped on a "
      "threshold; worst |depth error| %.2e, worst |distance error| %.2e\n",
      poses, separated, penetrating, edge_chosen, depth_compared, apart_within_margin,
      on_a_threshold, worst_depth_error, worst_distance_error);
  // The sample exercises every case, and few poses sit on a threshold of the rule.
  EXPECT_GT(penetrating, poses / 4);
  EXPECT_GT(edge_chosen, poses / 50);
  EXPECT_GT(depth_compared, penetrating / 2);
  EXPECT_GT(apart_within_margin, poses / 50);
  EXPECT_GT(separated, poses / 50);
  EXPECT_LT(on_a_threshold, poses / 100);
}

TEST(ManifoldReduction, PlanarChoiceEqualsTheProjectedChoice) {
  Rng rng(4243);
  const int clouds = scaled(4000);
  for (int c = 0; c < clouds; ++c) {
    const Vec3 normal = random_unit_vector(rng);
    Vec3 u;
    Vec3 v;
    orthonormal_basis(normal, u, v);  // u x v = normal
    const int count = 5 + int(uniform(rng, 0, 12));
    std::vector<ContactPoint> points;
    std::vector<PlanarCandidate> planar;
    for (int i = 0; i < count; ++i) {
      const Real x = uniform(rng, -1, 1);
      const Real y = uniform(rng, -1, 1);
      const Real depth = uniform(rng, 0, 0.1);
      // Off the plane by a random amount along the normal: the projection ignores it.
      points.push_back({u * x + v * y + normal * uniform(rng, -0.1, 0.1), depth, {}});
      planar.push_back({x, y, depth});
    }
    std::array<int, kMaxManifoldPoints> projected{};
    std::array<int, kMaxManifoldPoints> in_plane{};
    ASSERT_EQ(reduce_manifold(normal, points, projected), kMaxManifoldPoints);
    ASSERT_EQ(reduce_planar_manifold(planar, in_plane), kMaxManifoldPoints);
    EXPECT_EQ(projected, in_plane) << "cloud " << c;
  }
}

}  // namespace
}  // namespace tumble::testing
