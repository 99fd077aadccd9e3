// Box-box face contacts against the exact overlap polygon (the clipper of box_box.cpp).
// Box B rests on A's +z face, turned about A's z axis by an angle (random, or exactly 0, 45 or 90
// degrees), shifted sideways and sunk by a depth d, sometimes with the same half extents as A
// (corners then lie exactly on the other face's sides) and sometimes 1e6 m from the origin. The
// faces are parallel, so the contact region is the intersection of two rectangles in A's face
// plane; the test computes its vertices on its own (the corners of each rectangle inside the
// other and the crossings of their edges) and checks that collide() reports:
//   - the normal along A's face axis, from B to A, and every depth equal to d,
//   - every point at a vertex of that polygon (no point inside it or on an edge between
//     vertices), no two points at the same vertex,
//   - as many points as the polygon has distinct vertices, up to four.
// A second test feeds non-finite poses and checks that the answer stays a valid manifold.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "tests/collision/oracle.hpp"
#include "tests/property_scale.hpp"

namespace tumble::testing {
namespace {

using Vec2 = Eigen::Matrix<Real, 2, 1>;

// A rectangle in the plane: centre, unit axis along its first half extent, half extents.
struct Rectangle {
  Vec2 centre;
  Vec2 axis;
  Real half_x;
  Real half_y;

  Vec2 other_axis() const { return Vec2(-axis.y(), axis.x()); }
  std::array<Vec2, 4> corners() const {
    const Vec2 x = axis * half_x;
    const Vec2 y = other_axis() * half_y;
    return {centre + x + y, centre - x + y, centre - x - y, centre + x - y};
  }
  bool contains(const Vec2& p, Real tolerance) const {
    const Vec2 d = p - centre;
    return std::abs(d.dot(axis)) <= half_x + tolerance &&
           std::abs(d.dot(other_axis())) <= half_y + tolerance;
  }
};

// The vertices of the intersection of two rectangles, each once (within `tolerance`).
std::vector<Vec2> overlap_vertices(const Rectangle& a, const Rectangle& b, Real tolerance) {
  std::vector<Vec2> points;
  for (const Vec2& c : a.corners()) {
    if (b.contains(c, tolerance))
      points.push_back(c);
  }
  for (const Vec2& c : b.corners()) {
    if (a.contains(c, tolerance))
      points.push_back(c);
  }
  const auto ca = a.corners();
  const auto cb = b.corners();
  for (int i = 0; i < 4; ++i) {
    const Vec2 p = ca[i];
    const Vec2 e = ca[(i + 1) % 4] - p;
    for (int j = 0; j < 4; ++j) {
      const Vec2 q = cb[j];
      const Vec2 f = cb[(j + 1) % 4] - q;
      const Real det = e.x() * f.y() - e.y() * f.x();
      if (std::abs(det) < 1e-12)
        continue;  // parallel edges: their overlap's ends are corners, found above
      const Vec2 w = q - p;
      const Real s = (w.x() * f.y() - w.y() * f.x()) / det;
      const Real t = (w.x() * e.y() - w.y() * e.x()) / det;
      if (s >= 0 && s <= 1 && t >= 0 && t <= 1)
        points.push_back(p + e * s);
    }
  }
  std::vector<Vec2> distinct;
  for (const Vec2& p : points) {
    const bool seen = std::any_of(distinct.begin(), distinct.end(),
                                  [&](const Vec2& d) { return (d - p).norm() <= tolerance; });
    if (!seen)
      distinct.push_back(p);
  }
  return distinct;
}

TEST(BoxBoxFaceClip, PointsAreTheVerticesOfTheExactOverlap) {
  Rng rng(2611);
  const int cases = scaled(6000);
  int four_or_more = 0;
  int exact_coincidence = 0;
  for (int i = 0; i < cases; ++i) {
    SCOPED_TRACE("case " + std::to_string(i));
    const Vec3 ha(uniform(rng, 0.1, 1), uniform(rng, 0.1, 1), uniform(rng, 0.1, 1));
    const bool same_size = i % 4 == 0;
    const Vec3 hb =
        same_size ? ha : Vec3(uniform(rng, 0.1, 1), uniform(rng, 0.1, 1), uniform(rng, 0.1, 1));
    const int angle_kind = i % 5;
    const Real angle = angle_kind == 0   ? Real(0)
                       : angle_kind == 1 ? Real(M_PI / 2)
                       : angle_kind == 2 ? Real(M_PI / 4)
                                         : uniform(rng, -M_PI, M_PI);
    const Real depth = uniform(rng, 0.001, 0.05) * std::min(ha.z(), hb.z());
    // A sideways shift that keeps the faces overlapping by more than the depth on every side
    // axis, so that A's face axis is the axis of least penetration.
    const Vec2 axis(std::cos(angle), std::sin(angle));
    Vec2 shift = Vec2::Zero();
    const auto overlaps_enough = [&](const Vec2& s) {
      const Real c = std::abs(axis.x());
      const Real n = std::abs(axis.y());
      const Real need = 3 * depth + 1e-3;
      return ha.x() + c * hb.x() + n * hb.y() - std::abs(s.x()) > need &&
             ha.y() + n * hb.x() + c * hb.y() - std::abs(s.y()) > need &&
             hb.x() + c * ha.x() + n * ha.y() - std::abs(s.dot(axis)) > need &&
             hb.y() + n * ha.x() + c * ha.y() - std::abs(s.dot(Vec2(-axis.y(), axis.x()))) > need;
    };
    if (i % 3 != 0) {
      do {
        shift =
            Vec2(uniform(rng, -1, 1) * (ha.x() + hb.x()), uniform(rng, -1, 1) * (ha.y() + hb.y()));
      } while (!overlaps_enough(shift));
    }
    const bool far = i % 7 == 0;
    const Quat qa = i % 11 == 0 ? Quat::Identity() : random_rotation(rng);
    const Transform pose_a{
        random_vector_in_box(rng, 3) + (far ? Vec3(1e6, -1e6, 1e6) : Vec3::Zero()), qa};
    const Quat turn(Eigen::AngleAxis<Real>(angle, Vec3::UnitZ()));
    const Vec3 offset(shift.x(), shift.y(), ha.z() + hb.z() - depth);
    const Transform pose_b{pose_a.translation + qa * offset, qa * turn};
    const Real tolerance = (far ? 1e-8 : 1e-10) * (1 + ha.norm() + hb.norm());

    Manifold m;
    const int count = collide(Shape::box(ha), pose_a, Shape::box(hb), pose_b, 0, m);
    ASSERT_GT(count, 0);
    const Vec3 face_normal = qa * Vec3::UnitZ();
    EXPECT_GT(m.normal.dot(-face_normal), 1 - 1e-12) << "the normal is A's face axis, B to A";

    const Rectangle face_a{Vec2::Zero(), Vec2::UnitX(), ha.x(), ha.y()};
    const Rectangle face_b{shift, axis, hb.x(), hb.y()};
    const std::vector<Vec2> vertices = overlap_vertices(face_a, face_b, tolerance);
    ASSERT_GE(vertices.size(), 3u);
    std::vector<int> hit;
    for (int p = 0; p < count; ++p) {
      EXPECT_NEAR(m.points[p].depth, depth, tolerance);
      const Vec3 local = qa.conjugate() * (m.points[p].position - pose_a.translation);
      EXPECT_NEAR(local.z(), ha.z() - depth / 2, tolerance) << "midway between the faces";
      int nearest = -1;
      for (int v = 0; v < int(vertices.size()); ++v) {
        if ((vertices[v] - Vec2(local.x(), local.y())).norm() <= tolerance)
          nearest = v;
      }
      ASSERT_GE(nearest, 0) << "point " << p << " at (" << local.x() << ", " << local.y()
                            << ") is not a vertex of the overlap";
      EXPECT_EQ(std::count(hit.begin(), hit.end(), nearest), 0) << "two points at one vertex";
      hit.push_back(nearest);
    }
    EXPECT_EQ(count, std::min<int>(kMaxManifoldPoints, int(vertices.size())));
    four_or_more += vertices.size() > 4 ? 1 : 0;
    exact_coincidence += same_size && (angle_kind == 0 || angle_kind == 1) ? 1 : 0;
  }
  // The cases the test means to reach: reductions of five to eight vertices, and corners that lie
  // exactly on the other face's sides.
  EXPECT_GT(four_or_more, cases / 10);
  EXPECT_GT(exact_coincidence, cases / 20);
}

TEST(BoxBoxFaceClip, NonFinitePosesGiveAValidManifold) {
  const Shape box = Shape::box(Vec3(0.5, 0.4, 0.3));
  constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();
  constexpr Real kInfinity = std::numeric_limits<Real>::infinity();
  const Transform at_origin{Vec3::Zero(), Quat::Identity()};
  const std::array<Transform, 4> bad = {Transform{Vec3(kNaN, 0, 0.5), Quat::Identity()},
                                        Transform{Vec3(0, 0, kInfinity), Quat::Identity()},
                                        Transform{Vec3(0, 0, 0.5), Quat(kNaN, 0, 0, 0)},
                                        Transform{Vec3(0, 0, 0.5), Quat(kInfinity, 0, 1, 0)}};
  for (const Transform& pose : bad) {
    for (const bool swapped : {false, true}) {
      Manifold m;
      const int count = swapped ? collide(box, pose, box, at_origin, 0.01, m)
                                : collide(box, at_origin, box, pose, 0.01, m);
      EXPECT_GE(count, 0);
      EXPECT_LE(count, kMaxManifoldPoints);
      EXPECT_EQ(count, m.count);
      for (int p = 0; p < count; ++p) {
        EXPECT_LT(m.points[p].feature.a, 26);
        EXPECT_LT(m.points[p].feature.b, 26);
      }
    }
  }
}

}  // namespace
}  // namespace tumble::testing
