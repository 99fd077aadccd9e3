// Ray casts and signed distances of the cylinder, hull, triangle mesh and compound
// (collision/ccd/ray_cast.cpp), against truth that shares no code with them:
//   - signed distances: the cylinder against the oracle's closed form (Quilez), the hull against
//     the oracle's enumeration over faces (largest face-plane distance inside, nearest face
//     triangle outside), the mesh (a closed box surface) against |signed distance| of the solid
//     box, the compound against the smallest of its parts' oracle distances;
//   - ray casts: the segment is sampled with the oracle's signed distance; the first sample
//     inside is refined by bisection to the surface crossing, which must equal the reported
//     fraction; a reported miss must have no sample inside. A hit that the sampling misses is
//     only allowed for a grazing ray (every sample within one step of the surface).
// The ray-cast harness of tests/ccd/ray_cast_test.cpp, extended; it lives here because it needs
// the collision tests' oracle (tests/collision/oracle.hpp).
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "collision/ccd/ray_cast.hpp"
#include "collision/shapes/compound_shape.hpp"
#include "tests/collision/mesh_fixtures.hpp"
#include "tests/collision/oracle.hpp"

namespace tumble::testing {
namespace {

using Truth = std::function<Real(const Vec3&)>;  // world point -> signed distance

Shape random_compound(Rng& rng) {
  std::vector<CompoundPart> parts;
  const ShapeType types[] = {ShapeType::sphere, ShapeType::box, ShapeType::capsule,
                             ShapeType::cylinder, ShapeType::hull};
  const int count = 1 + int(uniform(rng, 0, 3));
  for (int i = 0; i < count; ++i) {
    const ShapeType t = types[int(uniform(rng, 0, 5 - 1e-9))];
    parts.push_back({random_shape(rng, t), {random_vector_in_box(rng, 0.8), random_rotation(rng)}});
  }
  return Shape::compound_of(std::make_shared<const CompoundShape>(CompoundShape::build(parts)));
}

// Oracle signed distance of a compound (local point): the union's is the smallest part's.
Real compound_truth(const Shape& compound, const Vec3& local) {
  Real best = std::numeric_limits<Real>::infinity();
  for (const CompoundPart& part : compound.compound->parts())
    best = std::min(best, signed_distance_to_shape(part.shape, part.pose, local));
  return best;
}

enum class Kind { cylinder, hull, mesh, compound };
const char* kind_name(Kind k) {
  switch (k) {
    case Kind::cylinder:
      return "cylinder";
    case Kind::hull:
      return "hull";
    case Kind::mesh:
      return "mesh";
    default:
      return "compound";
  }
}

// A random shape of the kind with its independent truth (local point -> signed distance).
// The mesh is the closed surface of a random box, with the box's solid distance as truth.
void random_case(Rng& rng, Kind kind, Shape& shape, std::function<Real(const Vec3&)>& local) {
  switch (kind) {
    case Kind::cylinder:
    case Kind::hull: {
      shape = random_shape(rng, kind == Kind::cylinder ? ShapeType::cylinder : ShapeType::hull);
      local = [shape](const Vec3& p) { return local_signed_distance(shape, p); };
      return;
    }
    case Kind::mesh: {
      const Vec3 h(uniform(rng, 0.1, 1), uniform(rng, 0.1, 1), uniform(rng, 0.1, 1));
      shape = mesh_shape(box_mesh(h));
      const Shape box = Shape::box(h);
      local = [box](const Vec3& p) { return local_signed_distance(box, p); };
      return;
    }
    case Kind::compound:
      shape = random_compound(rng);
      local = [shape](const Vec3& p) { return compound_truth(shape, p); };
      return;
  }
}

TEST(RayCastNewShapes, SignedDistanceMatchesTheOracle) {
  Rng rng(601);
  Real worst[4] = {0, 0, 0, 0};
  for (int c = 0; c < scaled(400); ++c) {
    for (const Kind kind : {Kind::cylinder, Kind::hull, Kind::mesh, Kind::compound}) {
      Shape shape;
      std::function<Real(const Vec3&)> local;
      random_case(rng, kind, shape, local);
      const Transform pose{random_vector_in_box(rng, 1), random_rotation(rng)};
      const Real reach = bounding_radius(shape);
      for (int k = 0; k < 10; ++k) {
        // Half of the points near the surface, half anywhere around the shape.
        Vec3 local_point = random_vector_in_box(rng, 1.5 * reach);
        if (k % 2 == 0 && kind != Kind::compound && kind != Kind::mesh)
          local_point = random_surface_point(rng, shape) + random_vector_in_box(rng, 0.05);
        const Vec3 world = pose.apply(local_point);
        const Real truth = kind == Kind::mesh ? std::abs(local(local_point)) : local(local_point);
        const Real got = signed_distance(shape, pose, world);
        SCOPED_TRACE(std::string(kind_name(kind)) + " case " + std::to_string(c));
        // A compound's inside value is its deepest part's, as the oracle's; exact either way.
        EXPECT_NEAR(got, truth, 1e-9 * (1 + reach));
        worst[int(kind)] = std::max(worst[int(kind)], std::abs(got - truth));
      }
    }
  }
  std::printf(
      "[ stats    ] signed distance worst error: cylinder %.3g, hull %.3g, mesh %.3g, "
      "compound %.3g m\n",
      worst[0], worst[1], worst[2], worst[3]);
}

TEST(RayCastNewShapes, RayCastsAgreeWithSampling) {
  Rng rng(602);
  const int kSamples = 2000;
  int hits[4] = {0, 0, 0, 0};
  int misses[4] = {0, 0, 0, 0};
  int grazing = 0;
  Real worst_fraction_error = 0;
  const int cases = scaled(2000);
  for (int i = 0; i < cases; ++i) {
    const Kind kind = Kind(i % 4);
    Shape shape;
    std::function<Real(const Vec3&)> local;
    random_case(rng, kind, shape, local);
    const Transform pose{random_vector_in_box(rng, 1), random_rotation(rng)};
    const Truth truth = [&](const Vec3& w) { return local(pose.apply_inverse(w)); };
    const Real reach = bounding_radius(shape);
    // From outside (rays starting inside are the fraction-0 case, tested elsewhere).
    Vec3 origin;
    do {
      origin = pose.translation + random_vector_in_box(rng, 3);
    } while (truth(origin) <= 0);
    const Vec3 delta = (pose.translation - origin) * 1.5 + random_vector_in_box(rng, 1.2 * reach);
    const ShapeRayHit hit = ray_cast(shape, pose, origin, delta);
    SCOPED_TRACE(std::string(kind_name(kind)) + " case " + std::to_string(i));
    int first_inside = -1;
    Real closest = std::numeric_limits<Real>::infinity();
    for (int k = 0; k <= kSamples; ++k) {
      const Real d = truth(origin + delta * (Real(k) / kSamples));
      closest = std::min(closest, d);
      if (d <= 0) {
        first_inside = k;
        break;
      }
    }
    const Real step = delta.norm() / kSamples;
    if (first_inside < 0) {
      if (hit.hit) {
        // Only a ray that grazes the shape between two samples.
        EXPECT_LT(closest, step) << "hit at " << hit.fraction << " but no sample inside";
        ++grazing;
      } else {
        ++misses[int(kind)];
      }
      continue;
    }
    ASSERT_TRUE(hit.hit) << "sample " << first_inside << " is inside";
    ++hits[int(kind)];
    // The crossing, by bisection between the last sample outside and the first inside.
    Real lo = Real(first_inside - 1) / kSamples;
    Real hi = Real(first_inside) / kSamples;
    for (int b = 0; b < 60; ++b) {
      const Real mid = (lo + hi) / 2;
      (truth(origin + delta * mid) <= 0 ? hi : lo) = mid;
    }
    // A ray may also enter and leave between two samples before first_inside (grazing); then
    // the reported fraction is earlier, with the ray within one step of the surface there.
    const Real crossing = hi;
    const Real error = std::abs(hit.fraction - crossing) * delta.norm();
    if (hit.fraction < lo - 1e-12) {
      EXPECT_LT(std::abs(truth(origin + delta * hit.fraction)), 1e-9);
      ++grazing;
      continue;
    }
    worst_fraction_error = std::max(worst_fraction_error, error);
    EXPECT_LT(error, 1e-9 * (1 + reach)) << "fraction " << hit.fraction << " vs " << crossing;
  }
  std::printf(
      "[ stats    ] rays: hits/misses cylinder %d/%d, hull %d/%d, mesh %d/%d, compound "
      "%d/%d; %d grazing; worst hit-point error %.3g m\n",
      hits[0], misses[0], hits[1], misses[1], hits[2], misses[2], hits[3], misses[3], grazing,
      worst_fraction_error);
  for (int t = 0; t < 4; ++t) {
    EXPECT_GT(hits[t], cases / 20) << kind_name(Kind(t));
    EXPECT_GT(misses[t], cases / 40) << kind_name(Kind(t));
  }
}

}  // namespace
}  // namespace tumble::testing
