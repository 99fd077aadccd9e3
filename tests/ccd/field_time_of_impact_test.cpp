// Conservative advancement against fields (collision/ccd/shape_distance.cpp): far from the field,
// the distance it steps by is a bound from the shapes' bounding balls (phi at the other's centre
// less its radius, or the other's distance from the field's centre less the field's radius, or
// the balls' gap), a sample or two, instead of the narrow phase's deepest candidate. Checked here:
//   - the bound is the largest of those measures, and never above the distance between the
//     shapes: below the least of phi over the other shape's surface (sampled finely, so that the
//     least over the samples is at or above the least over the surface) for exact fields, for
//     thousands of random poses of boxes, capsules and spheres about a torus, a box field and
//     non-convex CSG fields;
//   - fast shapes thrown past and into such fields stop before they overlap, and agree with the
//     advancement that asks the narrow phase at every advance (the reference below): the same
//     hits and misses, and times of impact as far apart as the motion takes to cover the
//     spacing of the field's surface points, which is how good the narrow phase's distance is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "collision/ccd/conservative_advancement.hpp"
#include "collision/ccd/ray_cast.hpp"
#include "collision/ccd/shape_distance.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/sdf/sdf_tree.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/shape.hpp"
#include "tests/ccd/ccd_test_support.hpp"
#include "tests/collision/csg_test_fields.hpp"

namespace tumble::testing {
namespace {

// The bowl, torus and blob of csg_test_fields, coarse.
std::vector<Shape> csg_fields() {
  return csg_test_fields(16);
}

// Points on the surface of a box, capsule or sphere in its local frame, about `spacing` apart.
std::vector<Vec3> surface_samples(const Shape& s, Real spacing) {
  std::vector<Vec3> out;
  if (s.type == ShapeType::box) {
    const Vec3& h = s.half_extents;
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const int nu = std::max(2, int(std::ceil(2 * h[u] / spacing)) + 1);
      const int nv = std::max(2, int(std::ceil(2 * h[v] / spacing)) + 1);
      for (const Real side : {Real(-1), Real(1)})
        for (int i = 0; i < nu; ++i)
          for (int j = 0; j < nv; ++j) {
            Vec3 p;
            p[axis] = side * h[axis];
            p[u] = -h[u] + 2 * h[u] * i / (nu - 1);
            p[v] = -h[v] + 2 * h[v] * j / (nv - 1);
            out.push_back(p);
          }
    }
    return out;
  }
  // Sphere and capsule: a sphere of `radius` whose upper half is raised by `half` along z and
  // lower half lowered by it, and the cylinder between them.
  const Real radius = s.radius;
  const Real half = s.type == ShapeType::capsule ? s.half_length : 0;
  const int rings = std::max(8, int(std::ceil(M_PI * radius / spacing)));
  const int around = 2 * rings;
  for (int i = 0; i <= rings; ++i) {
    const Real theta = M_PI * i / rings;
    for (int j = 0; j < around; ++j) {
      const Real phi = 2 * M_PI * j / around;
      const Real z = radius * std::cos(theta);
      out.emplace_back(radius * std::sin(theta) * std::cos(phi),
                       radius * std::sin(theta) * std::sin(phi), z + (z >= 0 ? half : -half));
    }
  }
  const int along = int(std::ceil(2 * half / spacing));
  for (int k = 1; k < along; ++k)
    for (int j = 0; j < around; ++j) {
      const Real phi = 2 * M_PI * j / around;
      out.emplace_back(radius * std::cos(phi), radius * std::sin(phi),
                       -half + 2 * half * k / along);
    }
  return out;
}

// The bound the function should give: the largest of the three measures of the balls, where it
// clears a quarter of the smaller radius (the same arithmetic as the function, less the hairs).
Real expected_ball_bound(const Shape& field, const Transform& pose_field, const Shape& other,
                         const Transform& pose_other) {
  const Real rf = bounding_radius(field), ro = bounding_radius(other);
  Real best = (pose_field.translation - pose_other.translation).norm() - rf - ro;
  best = std::max(
      best,
      field.sdf->distance(pose_field.apply_inverse(pose_other.translation), field.field_time) - ro);
  best = std::max(best, signed_distance(other, pose_other, pose_field.translation) - rf);
  return best > Real(0.25) * std::min(rf, ro) ? best : -std::numeric_limits<Real>::infinity();
}

TEST(FieldBallBound, IsNeverAboveTheDistanceBetweenTheShapes) {
  std::mt19937_64 rng(2611);
  // Exact fields (the distance to a torus and to a box), where the least of phi over the other's
  // surface is the distance between them, and two CSG fields, where it is at most that.
  std::vector<Shape> fields = csg_fields();
  fields.push_back(sdf_shape(SdfNode::box(Vec3(0.5, 0.2, 0.3)), nullptr, 16));
  const std::vector<Shape> others = {Shape::box(Vec3(0.2, 0.05, 0.1)), Shape::capsule(0.05, 0.15),
                                     Shape::sphere(0.1)};
  std::vector<std::vector<Vec3>> samples;
  for (const Shape& o : others)
    samples.push_back(surface_samples(o, 0.005));
  int used = 0, cases = 0;
  // A seventh of the poses under the sanitizers (TUMBLE_PROPERTY_SCALE < 1), which check the
  // memory of the same paths; every field and shape is still drawn.
  const int poses = property_scale() < 1 ? 300 : 2000;
  for (int i = 0; i < poses; ++i) {
    const Shape& field = fields[std::size_t(i) % fields.size()];
    const std::size_t k = std::size_t(i / 4) % others.size();
    const Shape& other = others[k];
    const Transform pose_field{random_vector(rng, -2, 2), random_rotation(rng)};
    const Real reach = std::uniform_real_distribution<Real>(0.3, 1.5)(rng);
    const Transform pose_other{pose_field.translation + reach * random_unit(rng),
                               random_rotation(rng)};
    // Both orders: the field as A and as B.
    const bool field_first = (i & 1) != 0;
    const DistanceBound d = field_first
                                ? shape_distance_bound(field, pose_field, other, pose_other, 1e9)
                                : shape_distance_bound(other, pose_other, field, pose_field, 1e9);
    Real least = std::numeric_limits<Real>::infinity();
    for (const Vec3& p : samples[k])
      least = std::min(least, field.sdf->distance(pose_field.apply_inverse(pose_other.apply(p)),
                                                  field.field_time));
    if (least <= 0)
      continue;  // overlapping: the narrow phase's own depth, checked elsewhere
    ++cases;
    const Real expected = expected_ball_bound(field, pose_field, other, pose_other);
    if (!(expected > -std::numeric_limits<Real>::infinity()))
      continue;  // near: the narrow phase measures (its distances are checked elsewhere)
    ++used;
    EXPECT_NEAR(d.distance, expected, 1e-8) << "case " << i;
    EXPECT_FALSE(d.separating_normal) << "case " << i;
    EXPECT_NEAR(d.normal.norm(), 1, 1e-12) << "case " << i;
    // phi at the other's centre less its radius is below phi anywhere on it; and for the exact
    // fields, whatever measure gave the bound, it is below the distance itself.
    const Real at_centre =
        field.sdf->distance(pose_field.apply_inverse(pose_other.translation), field.field_time);
    ASSERT_LE(at_centre - bounding_radius(other), least) << "case " << i;
    if (field.sdf->is_exact()) {
      ASSERT_LE(d.distance, least) << "case " << i;
    }
  }
  std::printf("ball bound used in %d of %d separated cases\n", used, cases);
  // Most cases lie far enough for the bound, and some near enough for the narrow phase.
  EXPECT_GT(used, cases / 3);
  EXPECT_LT(used, cases);
}

// The advancement that asks the narrow phase at every advance: the deepest candidate within the
// motion's reach, or the reach when there is none.
ToiResult reference_time_of_impact(const Shape& a, const RigidMotion& ma, const Shape& b,
                                   const RigidMotion& mb, const ToiSettings& settings) {
  const Real radius_a = bounding_radius(a), radius_b = bounding_radius(b);
  const Real reach = ma.centre_speed() + mb.centre_speed() +
                     ma.angular_velocity().norm() * radius_a +
                     mb.angular_velocity().norm() * radius_b + settings.tolerance + 1e-9;
  auto distance = [&](const Transform& pa, const Transform& pb) {
    Manifold m;
    DistanceBound out;
    out.separating_normal = false;
    out.distance = reach;
    if (collide(a, pa, b, pb, reach, m) > 0) {
      const auto by_depth = [](const ContactPoint& x, const ContactPoint& y) {
        return x.depth < y.depth;
      };
      out.distance =
          -std::max_element(m.points.begin(), m.points.begin() + m.count, by_depth)->depth;
      out.normal = m.normal;
    }
    return out;
  };
  return conservative_advancement(ma, radius_a, mb, radius_b, distance, settings);
}

// Whether a and b overlap (deeper than `depth`) at any of `samples` times in [0, until).
bool overlaps_before(const Shape& a, const RigidMotion& ma, const Shape& b, const RigidMotion& mb,
                     Real until, int samples, Real depth) {
  for (int k = 0; k < samples; ++k) {
    const Real s = until * k / samples;
    Manifold m;
    if (collide(a, ma.at(s), b, mb.at(s), 0, m) == 0)
      continue;
    for (int i = 0; i < m.count; ++i)
      if (m.points[i].depth > depth)
        return true;
  }
  return false;
}

TEST(FieldTimeOfImpact, FastShapesPastAndIntoFieldsAgreeWithTheNarrowPhaseAtEveryAdvance) {
  std::mt19937_64 rng(2612);
  const std::vector<Shape> fields = csg_fields();
  const std::vector<Shape> others = {Shape::box(Vec3(0.05, 0.02, 0.04)), Shape::sphere(0.03),
                                     Shape::capsule(0.02, 0.05), fields[1]};
  ToiSettings settings;
  settings.tolerance = 1e-6;
  settings.max_iterations = 64;
  int hits = 0, misses = 0, capped = 0;
  long advances = 0, reference_advances = 0;
  Real worst_gap = 0;
  const int cases = property_scale() < 1 ? 24 : 600;
  for (int i = 0; i < cases; ++i) {
    const Shape& field = fields[std::size_t(i) % fields.size()];
    const Shape& other = others[std::size_t(i / 3) % others.size()];
    const Transform pose_field{random_vector(rng, -1, 1), random_rotation(rng)};
    // From 2 to 4 m away, moving through a point near the field's centre (a hit, or a pass close
    // by) and up to 2.5 times as far over the motion, turning up to a radian; the field drifts
    // and turns a little.
    const Vec3 start =
        pose_field.translation + std::uniform_real_distribution<Real>(2, 4)(rng) * random_unit(rng);
    const Vec3 aim = pose_field.translation + random_vector(rng, -0.8, 0.8);
    const Real reach = std::uniform_real_distribution<Real>(1.0, 2.5)(rng);
    const RigidMotion mo = RigidMotion::from_velocity(
        {start, random_rotation(rng)}, (aim - start) * reach, random_vector(rng, -0.6, 0.6));
    const RigidMotion mf = RigidMotion::from_velocity(pose_field, random_vector(rng, -0.05, 0.05),
                                                      random_vector(rng, -0.05, 0.05));
    const ToiResult fast = time_of_impact(other, mo, field, mf, settings);
    const ToiResult slow = reference_time_of_impact(other, mo, field, mf, settings);
    advances += fast.iterations;
    reference_advances += slow.iterations;
    // Either stops before any overlap deeper than the tolerance (a capped one where it got to).
    ASSERT_FALSE(overlaps_before(other, mo, field, mf, fast.time_of_impact, 100, 1e-6))
        << "case " << i;
    if (fast.status == ToiStatus::max_iterations || slow.status == ToiStatus::max_iterations) {
      ++capped;
      continue;
    }
    ASSERT_EQ(fast.hit(), slow.hit()) << "case " << i << ": " << toi_status_name(fast.status)
                                      << " against " << toi_status_name(slow.status);
    if (!fast.hit()) {
      ++misses;
      continue;
    }
    ++hits;
    // Both stop where the narrow phase's distance first falls within the tolerance. That
    // distance comes from the field's surface points and is good to their spacing, not a lower
    // bound: advancing from different times, the two may stop at different touches of it, as
    // far apart as the motion takes to cover a spacing.
    const Real closing = (mo.linear_velocity() - mf.linear_velocity()).norm() +
                         mo.angular_velocity().norm() * bounding_radius(other) +
                         mf.angular_velocity().norm() * bounding_radius(field);
    const Real apart = std::abs(fast.time_of_impact - slow.time_of_impact) * closing;
    worst_gap = std::max(worst_gap, apart / field.sdf->cell_size());
    EXPECT_LE(apart, field.sdf->cell_size()) << "case " << i;
  }
  std::printf(
      "%d hits, %d misses, %d capped, times apart by up to %.3g of a spacing; %ld advances against "
      "%ld asking the "
      "narrow phase at each\n",
      hits, misses, capped, worst_gap, advances, reference_advances);
  EXPECT_GT(hits, cases / 5);
  EXPECT_GT(misses, cases / 10);
}

}  // namespace
}  // namespace tumble::testing
