// Shape properties (shape.hpp) against independent truth: support maps and bounding boxes
// against sampled surface points, volume and inertia against Monte-Carlo integration and
// against numerical integration over thin slices (which checks the closed forms in shape.cpp,
// the capsule's included, without using them).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "collision/shapes/shape.hpp"
#include "tests/collision/oracle.hpp"

namespace tumble::testing {
namespace {

const std::array<Shape, 5> kShapes = {Shape::sphere(0.7), Shape::box({0.3, 0.8, 0.5}),
                                      Shape::capsule(0.4, 0.9), Shape::capsule(0.4, 0),
                                      Shape::capsule(0.05, 1.5)};

std::string name_of(const Shape& s) {
  return std::string(shape_type_name(s.type)) + " r=" + std::to_string(s.radius) +
         " a=" + std::to_string(s.half_length);
}

std::vector<Vec3> surface_samples(const Shape& shape, int count, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i)
    points.push_back(random_surface_point(rng, shape));
  return points;
}

TEST(ShapeProperties, SupportMapsMatchSampledSurfaces) {
  Rng rng(401);
  for (const Shape& shape : kShapes) {
    SCOPED_TRACE(name_of(shape));
    const std::vector<Vec3> samples = surface_samples(shape, 50000, 402);
    std::vector<Vec3> directions;
    for (int i = 0; i < 500; ++i)
      directions.push_back(random_unit_vector(rng) * uniform(rng, 0.01, 100));
    for (int k = 0; k < 3; ++k) {
      directions.push_back(Vec3::Unit(k));
      directions.push_back(-Vec3::Unit(k));
    }
    for (const Vec3& d : directions) {
      const Vec3 s = support(shape, d);
      const Vec3 u = d.normalized();
      // On the surface...
      EXPECT_NEAR(local_signed_distance(shape, s), 0, 1e-12);
      // ... and no sampled surface point is farther along d; the densest samples come close.
      Real sampled = -std::numeric_limits<Real>::infinity();
      for (const Vec3& p : samples)
        sampled = std::max(sampled, u.dot(p));
      EXPECT_GE(u.dot(s), sampled - 1e-12);
      EXPECT_LE(u.dot(s) - sampled, 0.02);
      if (shape.type == ShapeType::box) {
        Real best_corner = -std::numeric_limits<Real>::infinity();
        for (int v = 0; v < 8; ++v) {
          const Vec3 corner(v & 1 ? 0.3 : -0.3, v & 2 ? 0.8 : -0.8, v & 4 ? 0.5 : -0.5);
          best_corner = std::max(best_corner, u.dot(corner));
        }
        EXPECT_NEAR(u.dot(s), best_corner, 1e-12);
      }
    }
    EXPECT_TRUE(support(shape, Vec3::Zero()).allFinite());
  }
}

TEST(ShapeProperties, WorldAabbHoldsTheShapeAndIsTight) {
  Rng rng(403);
  for (const Shape& shape : kShapes) {
    SCOPED_TRACE(name_of(shape));
    const std::vector<Vec3> samples = surface_samples(shape, 5000, 404);
    for (int trial = 0; trial < 100; ++trial) {
      const Transform pose{random_vector_in_box(rng, 5), random_rotation(rng)};
      const Aabb box = world_aabb(shape, pose);
      Vec3 sampled_max = Vec3::Constant(-std::numeric_limits<Real>::infinity());
      Vec3 sampled_min = Vec3::Constant(std::numeric_limits<Real>::infinity());
      for (const Vec3& p : samples) {
        const Vec3 q = pose.apply(p);
        EXPECT_TRUE(box.inflated(1e-12).contains(q));
        sampled_max = sampled_max.cwiseMax(q);
        sampled_min = sampled_min.cwiseMin(q);
      }
      for (int k = 0; k < 3; ++k) {
        // Tight: the extreme surface point along each axis touches the box.
        EXPECT_NEAR(box.max[k], support_value(shape, pose, Vec3::Unit(k)), 1e-12);
        EXPECT_NEAR(box.min[k], -support_value(shape, pose, -Vec3::Unit(k)), 1e-12);
        EXPECT_LE(box.max[k] - sampled_max[k], 0.05);
        EXPECT_LE(sampled_min[k] - box.min[k], 0.05);
      }
    }
  }
  // A plane is bounded only along a world axis that is exactly its normal.
  const Real inf = std::numeric_limits<Real>::infinity();
  const Aabb floor = world_aabb(Shape::plane(), {Vec3(1, 2, 3), Quat::Identity()});
  EXPECT_EQ(floor.max.z(), 3);
  EXPECT_EQ(floor.min.z(), -inf);
  EXPECT_EQ(floor.max.x(), inf);
  const Aabb tilted =
      world_aabb(Shape::plane(), {Vec3(1, 2, 3), Quat(Eigen::AngleAxis<Real>(0.1, Vec3::UnitX()))});
  EXPECT_EQ(tilted.max.z(), inf);
  EXPECT_EQ(tilted.min.z(), -inf);
}

// A cylinder whose axis is a hair off a world axis: the box along that axis is h |u_k| plus the
// rim's r sqrt(1 - u_k^2), which cancels when written that way (up to 1e-8 r short, so a
// broad-phase or mesh query missed contacts a few nanometres away); it must still touch the
// support value.
TEST(ShapeProperties, WorldAabbOfANearlyAxisAlignedCylinderIsExact) {
  const Shape cylinder = Shape::cylinder(0.7, 0.4);
  for (const Real tilt : {Real(1e-10), Real(1e-9), Real(1e-8), Real(3e-8), Real(1e-7)}) {
    for (int axis = 0; axis < 3; ++axis) {
      // The cylinder's z axis turned onto world axis `axis`, then tilted by `tilt`.
      const Quat onto = Quat::FromTwoVectors(Vec3::UnitZ(), Vec3::Unit(axis));
      const Quat off(Eigen::AngleAxis<Real>(tilt, Vec3::Unit((axis + 1) % 3)));
      const Transform pose{Vec3(0.3, -0.2, 0.1), (off * onto).normalized()};
      const Aabb box = world_aabb(cylinder, pose);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(box.max[k], support_value(cylinder, pose, Vec3::Unit(k)), 1e-13)
            << "tilt " << tilt << " axis " << axis << " k " << k;
        EXPECT_NEAR(box.min[k], -support_value(cylinder, pose, -Vec3::Unit(k)), 1e-13)
            << "tilt " << tilt << " axis " << axis << " k " << k;
      }
    }
  }
}

TEST(ShapeProperties, BoundingRadiusHoldsEverySurfacePoint) {
  for (const Shape& shape : kShapes) {
    SCOPED_TRACE(name_of(shape));
    Real farthest = 0;
    for (const Vec3& p : surface_samples(shape, 20000, 405))
      farthest = std::max(farthest, p.norm());
    EXPECT_LE(farthest, bounding_radius(shape) + 1e-12);
    EXPECT_GE(farthest, bounding_radius(shape) - 0.02);
  }
}

// Monte-Carlo over the local bounding box: volume = box volume * fraction inside, inertia per
// unit mass = mean over inside points of |x|^2 I - x x^T.
TEST(ShapeProperties, VolumeAndInertiaMatchMonteCarlo) {
  Rng rng(406);
  const int samples = 400000;
  for (const Shape& shape : kShapes) {
    SCOPED_TRACE(name_of(shape));
    const Aabb box = world_aabb(shape, {});
    const Vec3 size = box.max - box.min;
    int inside = 0;
    Mat3 sum = Mat3::Zero();
    for (int i = 0; i < samples; ++i) {
      const Vec3 p(box.min.x() + size.x() * uniform(rng, 0, 1),
                   box.min.y() + size.y() * uniform(rng, 0, 1),
                   box.min.z() + size.z() * uniform(rng, 0, 1));
      if (local_signed_distance(shape, p) > 0)
        continue;
      ++inside;
      sum += p.squaredNorm() * Mat3::Identity() - p * p.transpose();
    }
    const Real fraction = Real(inside) / samples;
    const Real box_volume = size.prod();
    // Four standard deviations of the binomial estimate.
    const Real sigma = box_volume * std::sqrt(fraction * (1 - fraction) / samples);
    EXPECT_NEAR(volume(shape), box_volume * fraction, 4 * sigma);
    const Mat3 estimate = sum / inside;
    const Mat3 closed = unit_inertia(shape);
    const Real scale = closed.diagonal().maxCoeff();
    // The mean of a bounded quantity over ~1e5 points: 1% of the largest moment is > 4 sigma.
    EXPECT_LT((estimate - closed).cwiseAbs().maxCoeff(), 0.01 * scale) << "closed\n"
                                                                       << closed << "\nestimate\n"
                                                                       << estimate;
  }
}

// Composite Simpson rule on [low, high] with `intervals` (even) panels: exact for cubics, so
// for the piecewise polynomials below the error is rounding plus O(h^4) on the quartic.
Real simpson(const std::function<Real(Real)>& f, Real low, Real high, int intervals) {
  if (!(high > low))
    return 0;
  const Real h = (high - low) / intervals;
  Real sum = f(low) + f(high);
  for (int i = 1; i < intervals; ++i)
    sum += f(low + i * h) * (i % 2 == 1 ? 4 : 2);
  return sum * h / 3;
}

// A solid of revolution about z cut into discs of radius rho(z): a disc has area pi rho^2,
// polar moment pi rho^4 / 2 and moment pi rho^4 / 4 about a diameter.
struct Moments {
  Real volume;
  Real axial;       // per unit mass
  Real transverse;  // per unit mass, about the x axis through the centre
};

Moments integrate_by_slices(const std::function<Real(Real)>& rho_squared,
                            const std::vector<Real>& breaks) {
  constexpr Real pi = std::numbers::pi;
  Real v = 0;
  Real polar = 0;
  Real transverse = 0;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
    const int panels = 20000;
    v += simpson([&](Real z) { return pi * rho_squared(z); }, breaks[i], breaks[i + 1], panels);
    polar += simpson([&](Real z) { return pi * rho_squared(z) * rho_squared(z) / 2; }, breaks[i],
                     breaks[i + 1], panels);
    transverse += simpson(
        [&](Real z) {
          return pi * rho_squared(z) * rho_squared(z) / 4 + z * z * pi * rho_squared(z);
        },
        breaks[i], breaks[i + 1], panels);
  }
  return {v, polar / v, transverse / v};
}

TEST(ShapeProperties, ClosedFormsMatchIntegrationBySlices) {
  // Capsules, including the sphere (a = 0) and a long thin one; each cap is a separate piece so
  // the integrand is a polynomial on every piece.
  for (const auto& [radius, half_length] :
       std::vector<std::pair<Real, Real>>{{0.4, 0.9}, {0.4, 0.0}, {0.05, 1.5}, {1.3, 0.2}}) {
    // Copies: clang before 16 cannot capture a structured binding in a lambda.
    const Real r = radius, a = half_length;
    SCOPED_TRACE("capsule r=" + std::to_string(r) + " a=" + std::to_string(a));
    const Shape capsule = Shape::capsule(r, a);
    const auto rho_squared = [&](Real z) {
      const Real beyond = std::max(std::abs(z) - a, Real(0));
      return std::max(r * r - beyond * beyond, Real(0));
    };
    const Moments m = integrate_by_slices(rho_squared, {-a - r, -a, a, a + r});
    EXPECT_NEAR(volume(capsule), m.volume, 1e-10 * m.volume);
    const Mat3 inertia = unit_inertia(capsule);
    EXPECT_NEAR(inertia(2, 2), m.axial, 1e-10 * m.transverse);
    EXPECT_NEAR(inertia(0, 0), m.transverse, 1e-10 * m.transverse);
    EXPECT_NEAR(inertia(1, 1), m.transverse, 1e-10 * m.transverse);
    EXPECT_EQ(inertia(0, 1), 0);
    if (a == 0) {
      const Shape sphere = Shape::sphere(r);
      EXPECT_NEAR(volume(sphere), m.volume, 1e-10 * m.volume);
      EXPECT_NEAR(unit_inertia(sphere)(0, 0), m.transverse, 1e-10 * m.transverse);
      EXPECT_NEAR(unit_inertia(sphere)(2, 2), m.axial, 1e-10 * m.transverse);
    }
  }
  // Box: slices along z are rectangles 2hx x 2hy with moments (2hx)(2hy)(hx^2 + hy^2)/3 about z.
  const Vec3 h(0.3, 0.8, 0.5);
  const Shape box = Shape::box(h);
  const Real area = 4 * h.x() * h.y();
  const Real v = simpson([&](Real) { return area; }, -h.z(), h.z(), 100);
  const Real about_z = simpson([&](Real) { return area * (h.x() * h.x() + h.y() * h.y()) / 3; },
                               -h.z(), h.z(), 100) /
                       v;
  const Real about_x =
      simpson([&](Real z) { return area * (h.y() * h.y() / 3 + z * z); }, -h.z(), h.z(), 100) / v;
  EXPECT_NEAR(volume(box), v, 1e-12);
  EXPECT_NEAR(unit_inertia(box)(2, 2), about_z, 1e-12);
  EXPECT_NEAR(unit_inertia(box)(0, 0), about_x, 1e-12);
}

}  // namespace
}  // namespace tumble::testing
