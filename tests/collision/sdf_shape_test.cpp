// SDF shapes (collision/shapes/sdf_shape.hpp) and their contacts (sdf_pairs.cpp), against
// closed forms: the mass properties of a torus and a sphere, and the penetration depth of
// spheres, planes and fields against fields where it is known exactly (fixed seeds).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include "collision/closest_point_on_triangle.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/sdf/sdf_grid.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/shape.hpp"
#include "collision/shapes/triangle_mesh.hpp"
#include "tests/collision/sampled_grid.hpp"
#include "tests/property_scale.hpp"
#include "tumble/error.hpp"
#include "tumble/settings.hpp"

namespace tumble {
namespace {

constexpr Real kPiForFields = std::numbers::pi_v<Real>;

Quat field_test_rotation(std::mt19937_64& rng) {
  std::normal_distribution<Real> n(0, 1);
  Quat q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q;
}

// The same, drawn one value per statement, so that every compiler draws the same rotation (the
// order of a call's arguments is the compiler's choice; the tests above keep the sets their
// bounds were measured on).
Quat sequenced_field_test_rotation(std::mt19937_64& rng) {
  std::normal_distribution<Real> n(0, 1);
  const Real w = n(rng);
  const Real x = n(rng);
  const Real y = n(rng);
  const Real z = n(rng);
  return Quat(w, x, y, z).normalized();
}

// A pose `from` to `to` from `centre`'s origin in a random direction, turned at random; none when
// the direction drawn is too short to normalise.
std::optional<Transform> pose_around(const Transform& centre, Real from, Real to,
                                     std::mt19937_64& rng) {
  std::uniform_real_distribution<Real> u(-1, 1);
  Vec3 dir(u(rng), u(rng), u(rng));
  if (dir.norm() < 1e-3)
    return std::nullopt;
  dir.normalize();
  const Real distance = from + (to - from) * (u(rng) + 1) / 2;
  return Transform{centre.translation + distance * dir, field_test_rotation(rng)};
}

Real deepest_point_depth(const Manifold& m, int count) {
  Real deepest = -1e9;
  for (int i = 0; i < count; ++i)
    deepest = std::max(deepest, m.points[i].depth);
  return deepest;
}

TEST(SdfShape, TorusMassPropertiesMatchTheClosedForms) {
  // Volume 2 pi^2 R r^2; inertia per unit mass R^2 + 3/4 r^2 about the axis, R^2/2 + 5/8 r^2
  // about a diameter.
  for (const auto& [major, minor] : {std::pair{1.0, 0.25}, std::pair{0.4, 0.1}, {2.0, 1.5}}) {
    const Shape s = sdf_shape(SdfNode::torus(major, minor));
    const Real volume = 2 * kPiForFields * kPiForFields * major * minor * minor;
    EXPECT_NEAR(s.sdf->volume(), volume, 5e-4 * volume) << major << " " << minor;
    const Mat3& i = s.sdf->unit_inertia();
    const Real axial = major * major + 0.75 * minor * minor;
    const Real diameter = major * major / 2 + 0.625 * minor * minor;
    EXPECT_NEAR(i(2, 2), axial, 1e-3 * axial);
    EXPECT_NEAR(i(0, 0), diameter, 1e-3 * diameter);
    EXPECT_NEAR(i(1, 1), diameter, 1e-3 * diameter);
    EXPECT_LT(std::abs(i(0, 1)) + std::abs(i(0, 2)) + std::abs(i(1, 2)), 1e-9);
    EXPECT_EQ(i, i.transpose());
    EXPECT_LT(s.sdf->centre_in_tree().norm(), 1e-9 * major);
    // The thickest part is the tube.
    EXPECT_NEAR(s.sdf->inner_radius(), minor, s.sdf->cell_size());
  }
}

TEST(SdfShape, PlacedSphereIsCentredOnItsCentreOfMass) {
  const Vec3 where(0.3, -0.2, 0.7);
  Vec3 centre = Vec3::Zero();
  const Shape s =
      sdf_shape(SdfNode::sphere(0.5).placed(Transform{where, Quat::Identity()}), &centre);
  EXPECT_LT((centre - where).norm(), 1e-9);
  const Real volume = 4 * kPiForFields / 3 * 0.125;
  EXPECT_NEAR(s.sdf->volume(), volume, 5e-4 * volume);
  EXPECT_NEAR(s.sdf->unit_inertia()(0, 0), 0.4 * 0.25, 1e-3 * 0.1);
  // Every surface point lies on the surface, its normal the radial direction.
  for (int i = 0; i < s.sdf->surface_point_count(); ++i) {
    const Vec3& p = s.sdf->surface_point(i);
    ASSERT_NEAR(p.norm(), 0.5, 1e-9);
    ASSERT_NEAR(s.sdf->surface_normal(i).dot(p.normalized()), 1, 1e-9);
  }
  EXPECT_GE(s.sdf->bounding_radius(), 0.5);
  EXPECT_LT(s.sdf->bounding_radius(), 0.5 + s.sdf->cell_size());
}

TEST(SdfShape, UnboundedOrTinySolidsAreRefused) {
  EXPECT_THROW(sdf_shape(SdfNode::plane()), Error);
  // A needle of a capsule at the end of a long box: the grid still sees it.
  EXPECT_NO_THROW(sdf_shape(SdfNode::combine(
      SdfKind::union_of, {SdfNode::box(Vec3(1, 0.01, 0.01)), SdfNode::sphere(0.05)})));
}

// Coarser grids: the same solid within a bound that shrinks with the square of the cell, the cells
// and points as asked; out of range refused.
TEST(SdfShape, TheResolutionSetsTheCellsAndTheError) {
  const Real volume = 2 * kPiForFields * kPiForFields * 1.0 * 0.25 * 0.25;
  std::size_t points_before = 0;
  for (const int cells : {SdfShape::kMinCells, 16, 32, SdfShape::kMassCells}) {
    const Shape s = sdf_shape(SdfNode::torus(1, 0.25), nullptr, cells);
    EXPECT_NEAR(s.sdf->cell_size(), 2.5 / cells, 1e-12) << cells;
    // Second order in the cell: the sub-cells' fractions are exact for a plane, so the error is
    // the surface's bending across them, about surface x cell^2 x curvature (1 / minor radius)
    // times 0.0025 as measured (0.77% of the volume at 8 cells, 0.019% at 48); checked at 0.01.
    const Real surface = 4 * kPiForFields * kPiForFields * 1.0 * 0.25;
    const Real cell = s.sdf->cell_size();
    EXPECT_NEAR(s.sdf->volume(), volume, 0.01 * surface * cell * cell / 0.25) << cells;
    EXPECT_GT(std::size_t(s.sdf->surface_point_count()), points_before) << cells;
    points_before = std::size_t(s.sdf->surface_point_count());
    for (int i = 0; i < s.sdf->surface_point_count(); ++i)
      ASSERT_NEAR(s.sdf->distance(s.sdf->surface_point(i)), 0, 1e-6 * s.sdf->cell_size());
  }
  EXPECT_THROW(sdf_shape(SdfNode::torus(1, 0.25), nullptr, SdfShape::kMinCells - 1), Error);
  EXPECT_THROW(sdf_shape(SdfNode::torus(1, 0.25), nullptr, SdfShape::kMaxCells + 1), Error);
}

TEST(SdfContact, SphereAgainstAFieldSphereHasTheExactDepthAndNormal) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Shape field = sdf_shape(SdfNode::sphere(0.5));
  const Shape ball = Shape::sphere(0.2);
  const int cases = scaled(3000);
  int touching = 0;
  for (int i = 0; i < cases; ++i) {
    Vec3 dir(u(rng), u(rng), u(rng));
    if (dir.norm() < 1e-3)
      continue;
    dir.normalize();
    const Real distance = 0.7 + 0.1 * u(rng);  // -0.1 to 0.1 of overlap
    const Transform pose_b{Vec3(u(rng), u(rng), u(rng)), field_test_rotation(rng)};
    const Transform pose_a{pose_b.translation + distance * dir, field_test_rotation(rng)};
    Manifold m;
    const int n = collide(ball, pose_a, field, pose_b, 0.02, m);
    const Real depth = 0.7 - distance;
    if (depth < -0.02) {
      EXPECT_EQ(n, 0);
      continue;
    }
    ASSERT_EQ(n, 1);
    ++touching;
    EXPECT_NEAR(m.points[0].depth, depth, 1e-12);
    EXPECT_NEAR(m.normal.dot(dir), 1, 1e-12);
    // Swapped, the mirrored answer.
    Manifold swapped;
    ASSERT_EQ(collide(field, pose_b, ball, pose_a, 0.02, swapped), 1);
    EXPECT_NEAR(swapped.normal.dot(-dir), 1, 1e-12);
    EXPECT_NEAR(swapped.points[0].depth, depth, 1e-12);
  }
  EXPECT_GT(touching, cases / 2);
}

// A box of half extents (0.2, 0.3, 0.25) at random poses into `field`, a field of the box of
// half extents `half` at the origin, against the exact box pair, with the contact margin
// `margin`: of the poses whose exact deepest point is `from` to `to` of the field's cells deep,
// how many there were, how many the field's manifold found penetrating, and the largest
// difference of the deepest points' depths among those. Shallower than a cell, an edge crossing
// an edge can fall between the points' spacing unless a margin lets the walks reach it; deeper
// than resting contacts go, "the" depth depends on the measure (the box pair's is the least
// overlap over the separating axes, the field's the deepest point's distance).
struct BoxIntoFieldBox {
  int compared = 0;
  int found = 0;
  Real worst = 0;
};
BoxIntoFieldBox box_into_field_box(const Shape& field, const Vec3& half, std::uint64_t seed,
                                   Real from, Real to, Real margin) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Shape exact = Shape::box(half);
  const Shape box = Shape::box(Vec3(0.2, 0.3, 0.25));
  const int cases = scaled(10000);
  const Real cell = field.sdf->cell_size();
  BoxIntoFieldBox out;
  for (int i = 0; i < cases; ++i) {
    const Transform pose_b{Vec3::Zero(), sequenced_field_test_rotation(rng)};
    const Real x = u(rng);
    const Real y = u(rng);
    const Real z = u(rng);
    const Transform pose_a{Vec3(x, y, z) * 0.9, sequenced_field_test_rotation(rng)};
    Manifold reference;
    const int nr = collide(box, pose_a, exact, pose_b, 0.0, reference);
    if (nr == 0 || deepest_point_depth(reference, nr) < from * cell ||
        deepest_point_depth(reference, nr) > to * cell)
      continue;
    Manifold m;
    const int n = collide(box, pose_a, field, pose_b, margin, m);
    ++out.compared;
    if (n == 0 || !(deepest_point_depth(m, n) > 0))
      continue;
    ++out.found;
    out.worst = std::max(out.worst,
                         std::abs(deepest_point_depth(m, n) - deepest_point_depth(reference, nr)));
  }
  return out;
}

// A ball of 0.5 m and a box of half extents (0.5, 0.4, 0.3) sampled at the nodes of a dense grid
// of 2 cm cells (collision/sdf/sdf_grid.hpp), so that the exact answer is known: the ball's grid
// spans +-0.9 m (a partner's core may reach 0.8 m out), the box's reaches 0.1 m past its faces.
SdfNode sampled_grid_field(bool ball, GridInterpolation how) {
  const Real cell = 0.02;
  const Vec3 half(0.5, 0.4, 0.3);
  const Vec3 reach = ball ? Vec3::Constant(0.9) : Vec3(half + Vec3::Constant(0.1));
  const std::array<int, 3> n = {int(std::lround(2 * reach.x() / cell)) + 1,
                                int(std::lround(2 * reach.y() / cell)) + 1,
                                int(std::lround(2 * reach.z() / cell)) + 1};
  return SdfNode::from_grid(
      std::make_shared<const SdfGrid>(test::sampled_grid(
          -reach, cell, n,
          [&](const Vec3& p) { return ball ? p.norm() - 0.5 : sdf::box(p, half).distance; })),
      how);
}

// A ball against the gridded ball: the depth 0.7 - (centres' distance) and the normal along the
// centres, within what the interpolant allows at h = 2 cm cells on a ball of R = 0.5 m: depth
// errors of order h^2 / R (8e-4 m) for trilinear, a hundredth of that for tricubic; normal errors
// of order h / R (0.04 rad) for trilinear, whose gradient is piecewise constant along each axis,
// and (h / R)^2 (1.6e-3 rad) for tricubic. Measured over 2,000 contacts up to 10 cm deep:
// trilinear 1.6e-4 m and 21 mrad at worst, tricubic 1.1e-6 m and 0.22 mrad.
TEST(SdfContact, ABallAgainstAGridFieldHasTheExactDepthWithinTheGridsResolution) {
  for (const GridInterpolation how : {GridInterpolation::trilinear, GridInterpolation::tricubic}) {
    const bool cubic = how == GridInterpolation::tricubic;
    const Shape field = sdf_shape(sampled_grid_field(true, how));
    const Shape ball = Shape::sphere(0.2);
    std::mt19937_64 rng(14);
    std::uniform_real_distribution<Real> u(-1, 1);
    const int cases = scaled(2000);
    int touching = 0;
    Real worst_depth = 0, worst_angle = 0;
    for (int i = 0; i < cases; ++i) {
      Vec3 dir(u(rng), u(rng), u(rng));
      if (dir.norm() < 1e-3)
        continue;
      dir.normalize();
      const Real distance = 0.65 + 0.05 * u(rng);  // 0 to 10 cm deep
      const Transform pose_b{Vec3(u(rng), u(rng), u(rng)), field_test_rotation(rng)};
      const Transform pose_a{pose_b.translation + distance * dir, field_test_rotation(rng)};
      Manifold m;
      ASSERT_EQ(collide(ball, pose_a, field, pose_b, 0.02, m), 1) << i;
      ++touching;
      worst_depth = std::max(worst_depth, std::abs(m.points[0].depth - (0.7 - distance)));
      worst_angle =
          std::max(worst_angle, std::acos(std::clamp(m.normal.dot(dir), Real(-1), Real(1))));
    }
    std::printf("%s: %d contacts, depth within %.3g m, normal within %.3g rad\n",
                cubic ? "tricubic" : "trilinear", touching, worst_depth, worst_angle);
    const Real bound = 0.02 * 0.02 / 0.5 * (cubic ? 0.01 : 1);
    EXPECT_LT(worst_depth, bound);
    EXPECT_LT(worst_angle, cubic ? 1.6e-3 : 0.04);
  }
}

// A box into the gridded box: the deepest point agrees with the exact box-box pair within one
// cell of the shape's point spacing, as for the analytic field box below.
TEST(SdfContact, ABoxIntoAGridFieldBoxMatchesTheBoxPairWithinACell) {
  const Shape field = sdf_shape(sampled_grid_field(false, GridInterpolation::tricubic));
  const auto [compared, found, worst] =
      box_into_field_box(field, Vec3(0.5, 0.4, 0.3), 15, 1, 2, 0.0);
  std::printf("%d contacts, deepest point within %.3g m\n", compared, worst);
  EXPECT_GT(compared, scaled(10000) / 50);
  EXPECT_EQ(found, compared);
  EXPECT_LT(worst, field.sdf->cell_size()) << "largest depth error " << worst << " m";
}

// The support of a torus (axis a, ring R, tube r) along unit u: R |u - (u.a) a| + r.
Real torus_support_along(const Vec3& axis, Real major, Real minor, const Vec3& u) {
  return major * (u - u.dot(axis) * axis).norm() + minor;
}

TEST(SdfContact, TorusOnAPlaneHasTheExactDepthAtAnyTilt) {
  // The refinement walks each surface point toward the lowest point of its part of the torus, so
  // the depth is found to a few hundredths of a millimetre (measured: 2.3e-5 m at worst, the
  // walk along the flat direction of the ring being the slow one), not to the points' spacing
  // (2 cm here, which alone would leave errors of up to 0.5 mm on the tube).
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Real major = 0.4, minor = 0.1;
  const Shape torus = sdf_shape(SdfNode::torus(major, minor));
  const Shape plane = Shape::plane();
  const int cases = scaled(2000);
  Real worst = 0;
  for (int i = 0; i < cases; ++i) {
    const Quat q = field_test_rotation(rng);
    const Vec3 axis = q * Vec3::UnitZ();
    const Real lowest = torus_support_along(axis, major, minor, Vec3(0, 0, -1));
    const Real depth = 0.02 * (u(rng) + 0.5);  // -0.01 to 0.03
    const Transform pose_a{Vec3(u(rng), u(rng), lowest - depth), q};
    Manifold m;
    const int n = collide(torus, pose_a, plane, Transform{}, 0.02, m);
    ASSERT_GT(n, 0) << i;
    EXPECT_NEAR(m.normal.z(), 1, 1e-12);
    worst = std::max(worst, std::abs(deepest_point_depth(m, n) - depth));
  }
  EXPECT_LT(worst, 5e-5) << "largest depth error " << worst << " m";
}

TEST(SdfContact, BoxIntoAFieldBoxMatchesTheBoxPairWithinACell) {
  // A box is met by points on its surface (corners exact, edges and faces at the field's point
  // spacing) and by the field's surface points inside it: the deepest point agrees with the
  // exact box-box pair within one cell of the field's grid.
  const Shape field = sdf_shape(SdfNode::box(Vec3(0.5, 0.4, 0.3)));
  const auto [compared, found, worst] =
      box_into_field_box(field, Vec3(0.5, 0.4, 0.3), 13, 1, 2, 0.0);
  EXPECT_GT(compared, scaled(10000) / 50);
  EXPECT_EQ(found, compared);
  EXPECT_LT(worst, field.sdf->cell_size()) << "largest depth error " << worst << " m";
}

// Contacts shallower than half a cell, at the engine's default contact margin (5 mm): with the
// margin, the field's points near the box are walked to the deepest point too, and a shallow
// edge crossing is found though no sampled point lies inside. Measured: 208 of 213 found on the
// grid field, 179 of 185 on the analytic one, depths within 5.9 and 5.2 mm of the box pair's
// (the cell is 2.1 cm); without the margin about one in six is missed.
TEST(SdfContact, ShallowContactsOfABoxOnFieldBoxesAreFoundWithTheDefaultMargin) {
  for (const bool grid : {true, false}) {
    const Shape field = grid ? sdf_shape(sampled_grid_field(false, GridInterpolation::tricubic))
                             : sdf_shape(SdfNode::box(Vec3(0.5, 0.4, 0.3)));
    const Real margin = WorldSettings{}.contact_margin;
    const auto [compared, found, worst] =
        box_into_field_box(field, Vec3(0.5, 0.4, 0.3), grid ? 15 : 13, 0, 0.5, margin);
    std::printf("%s: %d of %d shallow contacts found, depth within %.3g m\n",
                grid ? "grid" : "analytic", found, compared, worst);
    EXPECT_GT(compared, scaled(10000) / 100);
    EXPECT_GE(found, compared - compared / 20);  // at most one in twenty missed
    EXPECT_LT(worst, field.sdf->cell_size() / 3) << "largest depth error " << worst << " m";
  }
}

// A hull against a field ball: the truth is the ball's radius less the distance from its centre
// to the hull, by brute force over the hull's faces (the nearest point of each face polygon). The
// hull meets the field through its corners and edges (sampled at the field's point spacing,
// evaluated in the exact sphere field) and the field's surface points inside it (refined in the
// hull's face-plane distance), so a face touching the ball is found by the second kind alone.
// Measured over 256 contacts (up to 5 cm deep): the normal within 0.33 rad of the true one and
// the depth within 1.5 mm (the field's cell is 2.1 cm; 0.39 rad and 2.8 mm while the field's
// points inside the hull voted for the normal of a poking corner). Both errors are the manifold's
// one normal, the depth-weighted mean of the candidates of the deepest one's kind (docs/sdf.md,
// "Not yet"): a corner poking into the ball has the exact normal and depth itself, and shallower
// hull points around it, with normals up to 60 degrees away, turn the mean; each point's depth is
// then taken along the mean.
Real distance_to_hull(const ConvexHull& hull, const Transform& pose, const Vec3& world_point,
                      Vec3& nearest) {
  const Vec3 p = pose.apply_inverse(world_point);
  Real best = std::numeric_limits<Real>::infinity();
  for (const HullFace& f : hull.faces()) {
    const auto v = [&](int k) {
      return hull.vertex(hull.face_vertices()[std::size_t(f.first_index + k)]);
    };
    for (int k = 1; k + 1 < f.count; ++k) {
      const Vec3 q = closest_point_on_triangle(p, v(0), v(k), v(k + 1));
      if ((q - p).norm() < best) {
        best = (q - p).norm();
        nearest = pose.apply(q);
      }
    }
  }
  return best;
}

TEST(SdfContact, AHullAgainstAFieldBallHasTheDepthOfItsNearestPoint) {
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Shape field = sdf_shape(SdfNode::sphere(0.5));
  const int cases = scaled(2000);
  int compared = 0;
  Real worst_depth = 0, worst_angle = 0;
  for (int i = 0; i < cases; ++i) {
    std::vector<Vec3> points(10);
    for (Vec3& q : points)
      q = 0.3 * Vec3(u(rng), u(rng), u(rng));
    const auto hull = std::make_shared<const ConvexHull>(ConvexHull::from_points(points));
    const Shape a = Shape::convex_hull(hull);
    const Transform pose_b{Vec3(u(rng), u(rng), u(rng)), field_test_rotation(rng)};
    // The hull's centre 0.5 to 0.9 from the ball's; keep the cases that touch by up to 5 cm.
    const std::optional<Transform> placed = pose_around(pose_b, 0.5, 0.9, rng);
    if (!placed)
      continue;
    const Transform& pose_a = *placed;
    Vec3 nearest = Vec3::Zero();
    const Real gap = distance_to_hull(*hull, pose_a, pose_b.translation, nearest);
    const Real depth = 0.5 - gap;
    if (depth < 0.002 || depth > 0.05)
      continue;
    Manifold m;
    const int n = collide(a, pose_a, field, pose_b, 0.0, m);
    ASSERT_GT(n, 0) << i << " depth " << depth;
    ++compared;
    worst_depth = std::max(worst_depth, std::abs(deepest_point_depth(m, n) - depth));
    const Vec3 normal = (nearest - pose_b.translation).normalized();  // from B to A
    worst_angle = std::max(worst_angle, std::acos(std::min<Real>(1, m.normal.dot(normal))));
  }
  std::printf("[ stats    ] %d hull contacts: depth within %.3g m, normal within %.3g rad\n",
              compared, worst_depth, worst_angle);
  EXPECT_GT(compared, cases / 20);
  EXPECT_LT(worst_depth, 0.002) << "largest depth error " << worst_depth << " m";
  EXPECT_LT(worst_angle, 0.35) << "largest normal error " << worst_angle << " rad";
}

// A capsule against a field ball: phi at points along the capsule's core, evaluated directly, less
// its radius (at most 17 points, about one per cell: collision/narrow_phase/pairs/sdf_pairs.cpp).
// Along the core the distance from the ball's centre is sqrt(g^2 + s^2), g the gap at the nearest
// core point, so the deepest sampled point is at most (h / 2)^2 / (2 g) shallower than the exact
// depth (h the spacing of the samples: 0.32 mm here) and never deeper. The manifold's one normal
// is the depth-weighted mean of its points' (docs/sdf.md, "Not yet"), each along the line from
// the ball's centre to its core point, and each point's depth is taken along that mean: the
// normal is within the angle of the farthest core point that touches, atan(sqrt((R + r)^2 - g^2)
// / g), and the depth a little shallower again (measured over 236 contacts up to 5 cm deep:
// within 0.48 mm, the normal within 0.14 rad; bounded at 1 mm).
TEST(SdfContact, ACapsuleAgainstAFieldBallHasTheDepthOfItsCoreWithinTheSamplesSag) {
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Shape field = sdf_shape(SdfNode::sphere(0.5));
  const Shape capsule = Shape::capsule(0.1, 0.3);
  const int cases = scaled(2000);
  int compared = 0;
  Real worst_depth = 0, worst_angle = 0;
  for (int i = 0; i < cases; ++i) {
    const Transform pose_b{Vec3(u(rng), u(rng), u(rng)), field_test_rotation(rng)};
    const std::optional<Transform> placed = pose_around(pose_b, 0.6, 0.9, rng);
    if (!placed)
      continue;
    const Transform& pose_a = *placed;
    const Vec3 axis = pose_a.rotate(Vec3::UnitZ());
    const Real t =
        std::clamp((pose_b.translation - pose_a.translation).dot(axis), Real(-0.3), Real(0.3));
    const Vec3 core = pose_a.translation + t * axis;
    const Real gap = (core - pose_b.translation).norm();
    const Real depth = 0.6 - gap;
    if (depth < 0.001 || depth > 0.05)
      continue;  // apart, or deeper than contacts go
    Manifold m;
    const int n = collide(capsule, pose_a, field, pose_b, 0.0, m);
    ASSERT_GT(n, 0) << i << " depth " << depth;
    ++compared;
    const Real found = deepest_point_depth(m, n);
    ASSERT_LE(found, depth + 1e-12) << i;
    ASSERT_GE(found, depth - 1e-3) << i;
    const Real angle =
        std::acos(std::min<Real>(1, m.normal.dot((core - pose_b.translation) / gap)));
    ASSERT_LE(angle, std::atan(std::sqrt(0.36 - gap * gap) / gap) + 1e-9) << i;
    worst_depth = std::max(worst_depth, depth - found);
    worst_angle = std::max(worst_angle, angle);
  }
  std::printf("[ stats    ] %d capsule contacts: depth within %.3g m, normal within %.3g rad\n",
              compared, worst_depth, worst_angle);
  EXPECT_GT(compared, cases / 10);
}

// A cylinder against a field ball, met like a hull (points on its surface and the field's surface
// points inside it): the depth of its nearest point within the field's point spacing.
TEST(SdfContact, ACylinderAgainstAFieldBallHasTheDepthOfItsNearestPointWithinASpacing) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Shape field = sdf_shape(SdfNode::sphere(0.5));
  const Shape cylinder = Shape::cylinder(0.15, 0.2);
  const int cases = scaled(2000);
  int compared = 0;
  Real worst_depth = 0;
  for (int i = 0; i < cases; ++i) {
    const Transform pose_b{Vec3(u(rng), u(rng), u(rng)), field_test_rotation(rng)};
    const std::optional<Transform> placed = pose_around(pose_b, 0.55, 0.8, rng);
    if (!placed)
      continue;
    const Transform& pose_a = *placed;
    // The nearest point of the solid cylinder to the ball's centre, in the cylinder's frame.
    const Vec3 c = pose_a.apply_inverse(pose_b.translation);
    Vec3 q(c.x(), c.y(), std::clamp(c.z(), Real(-0.2), Real(0.2)));
    const Real rho = std::hypot(q.x(), q.y());
    if (rho > 0.15) {
      q.x() *= 0.15 / rho;
      q.y() *= 0.15 / rho;
    }
    const Real gap = (q - c).norm();
    const Real depth = 0.5 - gap;
    if (depth < 0.002 || depth > 0.05)
      continue;
    Manifold m;
    const int n = collide(cylinder, pose_a, field, pose_b, 0.0, m);
    ASSERT_GT(n, 0) << i << " depth " << depth;
    ++compared;
    worst_depth = std::max(worst_depth, std::abs(deepest_point_depth(m, n) - depth));
  }
  std::printf("[ stats    ] %d cylinder contacts: depth within %.3g m (point spacing %.3g m)\n",
              compared, worst_depth, field.sdf->cell_size());
  EXPECT_GT(compared, cases / 20);
  EXPECT_LT(worst_depth, field.sdf->cell_size()) << "largest depth error " << worst_depth << " m";
}

TEST(SdfContact, TwoFieldSpheresHaveTheExactDepth) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Shape a = sdf_shape(SdfNode::sphere(0.3));
  const Shape b = sdf_shape(SdfNode::sphere(0.5));
  const int cases = scaled(1000);
  Real worst = 0;
  for (int i = 0; i < cases; ++i) {
    Vec3 dir(u(rng), u(rng), u(rng));
    if (dir.norm() < 1e-3)
      continue;
    dir.normalize();
    const Real depth = 0.02 * (u(rng) + 0.5);
    const Transform pose_b{Vec3(u(rng), u(rng), u(rng)), field_test_rotation(rng)};
    const Transform pose_a{pose_b.translation + (0.8 - depth) * dir, field_test_rotation(rng)};
    Manifold m;
    const int n = collide(a, pose_a, b, pose_b, 0.02, m);
    ASSERT_GT(n, 0);
    EXPECT_GT(m.normal.dot(dir), 1 - 1e-6);
    worst = std::max(worst, std::abs(deepest_point_depth(m, n) - depth));
  }
  EXPECT_LT(worst, 1e-6) << "largest depth error " << worst << " m";
}

// The surface walk's status (Manifold::refined, refine_capped): field pairs count their walks and
// the walks that stopped at the step cap with the normals still 1e-6 rad apart, the same in
// either argument order, and whether the walk that ended deepest was capped; other pairs count
// none. Of two field spheres' walks, some of those started a region away from the contact stop
// at the cap (measured: 8% of them), never the deepest one: the depth is exact
// (SdfContact.TwoFieldSpheresHaveTheExactDepth).
TEST(SdfContact, FieldPairsReportTheirWalksAndTheCappedOnes) {
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Shape a = sdf_shape(SdfNode::sphere(0.3));
  const Shape b = sdf_shape(SdfNode::sphere(0.5));
  const Shape box = Shape::box(Vec3(0.2, 0.3, 0.25));
  int refined = 0, capped = 0;
  for (int i = 0; i < scaled(200); ++i) {
    Vec3 dir(u(rng), u(rng), u(rng));
    if (dir.norm() < 1e-3)
      continue;
    dir.normalize();
    const Transform pose_b{Vec3(u(rng), u(rng), u(rng)), field_test_rotation(rng)};
    const Transform pose_a{pose_b.translation + 0.79 * dir, field_test_rotation(rng)};
    Manifold m, swapped;
    ASSERT_GT(collide(a, pose_a, b, pose_b, 0.02, m), 0);
    ASSERT_GT(collide(b, pose_b, a, pose_a, 0.02, swapped), 0);
    EXPECT_GT(m.refined, 0);
    EXPECT_LE(m.refine_capped, m.refined);
    EXPECT_EQ(swapped.refined, m.refined);
    EXPECT_EQ(swapped.refine_capped, m.refine_capped);
    EXPECT_FALSE(m.deepest_walk_capped);
    refined += m.refined;
    capped += m.refine_capped;
    Manifold plain;
    if (collide(box, pose_a, Shape::box(Vec3(0.5, 0.5, 0.5)), pose_b, 0.02, plain) > 0) {
      EXPECT_EQ(plain.refined, 0);
      EXPECT_EQ(plain.refine_capped, 0);
      EXPECT_FALSE(plain.deepest_walk_capped);
    }
  }
  std::printf("[ stats    ] %d walks, %d capped\n", refined, capped);
  EXPECT_GT(refined, 0);
  EXPECT_LT(capped, refined / 5);
}

TEST(SdfContact, AFieldOnAMeshFloorHasTheExactDepth) {
  // A field ball of radius 0.5 on a flat two-triangle mesh floor (z = 0): the contact is as deep
  // as the ball's bottom is below the floor, along the floor's normal, wherever the ball stands on
  // it and however the field is turned (the surface points near the bottom are walked to it).
  const Shape floor = Shape::triangle_mesh(std::make_shared<const TriangleMesh>(TriangleMesh::build(
      {Vec3(-3, -3, 0), Vec3(3, -3, 0), Vec3(3, 3, 0), Vec3(-3, 3, 0)}, {{0, 1, 2}, {0, 2, 3}})));
  const Shape ball = sdf_shape(SdfNode::sphere(0.5));
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<Real> u(-1, 1);
  const int cases = scaled(1000);
  Real worst = 0, worst_tilt = 0;
  for (int i = 0; i < cases; ++i) {
    const Real depth = 0.025 * (u(rng) + 1);  // 0 to 5 cm
    const Transform pose_b{Vec3(2 * u(rng), 2 * u(rng), 0.5 - depth), field_test_rotation(rng)};
    Manifold m;
    const int n = collide(floor, Transform{}, ball, pose_b, 0.01, m);
    ASSERT_GT(n, 0) << "case " << i;
    // From B (the ball) to A (the floor): down.
    worst_tilt = std::max(worst_tilt, std::acos(std::clamp(-m.normal.z(), Real(-1), Real(1))));
    worst = std::max(worst, std::abs(deepest_point_depth(m, n) - depth));
  }
  std::printf("field ball on a mesh floor: depth within %.3g m, normal within %.3g rad\n", worst,
              worst_tilt);
  EXPECT_LT(worst, 1e-10) << "largest depth error " << worst << " m";
  // The floor's own normal: the floor's points around the ball's bottom, measured in the field,
  // give their depths but not their gradients (tilted toward the ball's centre, they turned the
  // depth-weighted mean normal by up to 23 mrad); the field's points under the floor carry its
  // normal.
  EXPECT_LT(worst_tilt, 1e-6);
}

TEST(SdfContact, ABallsSeparationBendsAsTheNarrowPhaseMeasuresIt) {
  // The manifold's separation_curvature against second differences of the narrow phase's own
  // separation (minus the depth) as the ball moves, around a placed, turned torus: outside its
  // ring the surface curves away from the ball both ways, inside the hole it is a saddle.
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<Real> u(0, 1);
  const Real major = 0.6, minor = 0.3, radius = 0.1;
  const Shape field = sdf_shape(SdfNode::torus(major, minor));
  const Shape ball = Shape::sphere(radius);
  const Transform pose_b{Vec3(0.4, -0.3, 0.2), field_test_rotation(rng)};
  const auto separation = [&](const Vec3& centre) {
    Manifold m;
    const int n = collide(ball, Transform{centre, Quat::Identity()}, field, pose_b, 0.05, m);
    EXPECT_EQ(n, 1);
    return -deepest_point_depth(m, n);
  };
  const int cases = scaled(2000);
  const Real step = 1e-4;
  Real worst = 0;
  int saddles = 0;
  for (int i = 0; i < cases; ++i) {
    const Real around = 2 * kPiForFields * u(rng), tube = 2 * kPiForFields * u(rng);
    const Vec3 radial(std::cos(around), std::sin(around), 0);
    const Vec3 normal = std::cos(tube) * radial + std::sin(tube) * Vec3::UnitZ();
    const Real depth = 0.03 * u(rng) - 0.01;
    const Vec3 centre = pose_b.apply(major * radial + (minor + radius - depth) * normal);
    Manifold m;
    ASSERT_EQ(collide(ball, Transform{centre, Quat::Identity()}, field, pose_b, 0.05, m), 1);
    const std::array<Real, 6>& c = m.separation_curvature;
    Mat3 reported;
    reported << c[0], c[1], c[2], c[1], c[3], c[4], c[2], c[4], c[5];
    Mat3 measured;
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) {
        const Vec3 er = Vec3::Unit(r) * step, ek = Vec3::Unit(k) * step;
        measured(r, k) = (separation(centre + er + ek) - separation(centre + er - ek) -
                          separation(centre - er + ek) + separation(centre - er - ek)) /
                         (4 * step * step);
      }
    }
    worst = std::max(worst, (reported - measured).norm() / measured.norm());
    // No bend along the normal, where the separation grows one for one, but what the gradient's
    // differences a quarter of the radius apart make of it.
    EXPECT_LT((reported * m.normal).norm(), 5e-3 * measured.norm());
    if (std::cos(tube) < -0.5)
      ++saddles;
  }
  EXPECT_LT(worst, 0.01) << "largest relative error " << worst;
  EXPECT_GT(saddles, cases / 5);
}

// Found by tests/fuzz/fuzz_narrow_phase: two different fields at the same pose ran in argument
// order (their shapes' dimensions, all zero for fields, and their poses tied), so swapping A and B
// changed the points instead of flipping the normal. Fields are now ordered by their volume.
TEST(SdfContact, TwoDifferentFieldsAtOnePoseGiveTheSameContactsEitherWay) {
  const Shape torus = sdf_shape(SdfNode::torus(1, Real(0.25)));
  const Shape bowl = sdf_shape(SdfNode::combine(
      SdfKind::difference_of,
      {SdfNode::box({1, 1, Real(0.5)}),
       SdfNode::sphere(Real(0.9)).placed(Transform{Vec3(0, 0, Real(0.6)), Quat::Identity()})}));
  for (const Vec3& offset : {Vec3(0, 0, 0), Vec3(-4, -4, -4), Vec3(0.1, 0, 0.2)}) {
    const Transform pose{offset, Quat::Identity()};
    Manifold ab;
    Manifold ba;
    ASSERT_GT(collide(torus, pose, bowl, pose, Real(0.005), ab), 0);
    ASSERT_EQ(collide(bowl, pose, torus, pose, Real(0.005), ba), ab.count);
    EXPECT_EQ(ab.normal, Vec3(-ba.normal));
    for (int i = 0; i < ab.count; ++i) {
      EXPECT_EQ(ab.points[i].position, ba.points[i].position);
      EXPECT_EQ(ab.points[i].depth, ba.points[i].depth);
    }
  }
}

}  // namespace
}  // namespace tumble
