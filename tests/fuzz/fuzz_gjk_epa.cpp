// GJK and EPA (collision/narrow_phase/gjk_epa/) on degenerate point sets: one to eight points,
// often coincident, collinear or coplanar (lattice coordinates), with or without rounding.
// Checked on each input, from the contracts in gjk.hpp and epa.hpp:
//   * every status is set, every number finite, every normal unit;
//   * separated: the distance is no more than that of any two input points (less the radii),
//     and the witnesses are that distance apart;
//   * EPA converged: moving A by the depth along the normal (and a hair more) separates the two.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "collision/narrow_phase/gjk_epa/epa.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "tests/fuzz/fuzz_input.hpp"

namespace {

using namespace tumble;

[[noreturn]] void finding(const char* what) {
  fuzz::finding("gjk/epa", what);
}

std::vector<Vec3> points(FuzzedDataProvider& in, Real size) {
  const int count = in.ConsumeIntegralInRange<int>(1, 8);
  std::vector<Vec3> p;
  for (int i = 0; i < count; ++i)
    p.push_back(fuzz::point(in, size));
  return p;
}

Real radius(FuzzedDataProvider& in, Real size) {
  return in.ConsumeBool() ? Real(0) : in.ConsumeFloatingPointInRange<Real>(0, size);
}

bool unit(const Vec3& n) {
  return n.allFinite() && std::abs(n.norm() - 1) <= Real(1e-9);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const Real scale = fuzz::length(in);
  const std::vector<Vec3> pa = points(in, scale);
  const std::vector<Vec3> pb = points(in, scale);
  const Real ra = radius(in, scale);
  const Real rb = radius(in, scale);
  const Transform pose_a = fuzz::pose(in, scale);
  const Transform pose_b = fuzz::pose(in, scale);
  const ConvexSupport a = ConvexSupport::of_points(pa.data(), int(pa.size()), pose_a, ra);
  const ConvexSupport b = ConvexSupport::of_points(pb.data(), int(pb.size()), pose_b, rb);

  const GjkResult g = gjk(a, b);
  if (!std::isfinite(g.distance) || !g.point_a.allFinite() || !g.point_b.allFinite() ||
      !unit(g.normal))
    finding("GJK result not finite, or its normal not unit");
  // The extent of the problem, for the tolerances.
  Real extent = ra + rb;
  for (const Vec3& p : pa)
    extent = std::max(extent, pose_a.apply(p).norm());
  for (const Vec3& p : pb)
    extent = std::max(extent, pose_b.apply(p).norm());
  const Real tolerance = Real(1e-7) * (1 + extent);
  // A distance may stop short of a touch by up to 1e-5 of the size when slivers of
  // near-coincident vertices touch (gjk.hpp); elsewhere it is exact to 1e-7.
  const Real distance_tolerance = Real(1e-5) * (1 + extent);

  if (g.status == GjkStatus::separated) {
    Real nearest_pair = std::numeric_limits<Real>::infinity();
    for (const Vec3& p : pa)
      for (const Vec3& q : pb)
        nearest_pair = std::min(nearest_pair, (pose_a.apply(p) - pose_b.apply(q)).norm());
    if (g.distance > nearest_pair - ra - rb + distance_tolerance)
      finding("GJK distance above that of two input points");
    if (std::abs((g.point_a - g.point_b).norm() - std::abs(g.distance)) > tolerance)
      finding("GJK witnesses are not the distance apart");
    return 0;
  }
  if (g.status != GjkStatus::intersecting)
    return 0;  // max_iterations, degenerate: a finite estimate, checked above
  const EpaResult e = epa(a, b, g);
  if (!std::isfinite(e.depth) || !(e.depth >= 0) || !unit(e.normal) || !e.point_a.allFinite() ||
      !e.point_b.allFinite())
    finding("EPA result not finite, negative, or its normal not unit");
  if (e.status != EpaStatus::converged)
    return 0;
  if (e.depth > 2 * extent + tolerance)
    finding("EPA depth larger than the two objects");
  Transform moved = pose_a;
  moved.translation += (e.depth + tolerance) * e.normal;
  const ConvexSupport a_moved = ConvexSupport::of_points(pa.data(), int(pa.size()), moved, ra);
  const GjkResult after = gjk(a_moved, b);
  if (after.status == GjkStatus::intersecting || after.distance < -tolerance)
    finding("moving A by EPA's depth along its normal does not separate the two");
  return 0;
}
