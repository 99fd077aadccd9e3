// The narrow-phase dispatch (collision/narrow_phase/narrow_phase.hpp) on every pair of shape
// types, from fuzzed shape parameters and poses. Its contract, checked on each input:
//   * collide() returns the manifold's count, at most kMaxManifoldPoints;
//   * every point, depth and the normal are finite, the normal unit, each depth at least -margin;
//   * with A and B swapped the normal flips and the points and depths are the same, bit for bit
//     (the normal's sign is free only for twins: the same solid at the same pose).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "tests/fuzz/fuzz_input.hpp"

namespace {

// The pair's types, for the report.
const char* type_a = "";
const char* type_b = "";

[[noreturn]] void finding(const char* what) {
  std::fprintf(stderr, "narrow phase, %s against %s: %s\n", type_a, type_b, what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tumble;
  FuzzedDataProvider in(data, size);
  const std::optional<Shape> a = fuzz::shape(in);
  const std::optional<Shape> b = fuzz::shape(in);
  if (!a || !b)
    return 0;
  type_a = shape_type_name(a->type).data();
  type_b = shape_type_name(b->type).data();
  const Real spread = in.ConsumeBool() ? Real(1) : Real(4);
  const Transform pose_a = fuzz::pose(in, spread);
  const Transform pose_b = fuzz::pose(in, spread);
  const Real margin = in.ConsumeBool() ? Real(0.005) : in.ConsumeFloatingPointInRange<Real>(0, 1);

  Manifold ab;
  Manifold ba;
  const int count_ab = collide(*a, pose_a, *b, pose_b, margin, ab);
  const int count_ba = collide(*b, pose_b, *a, pose_a, margin, ba);
  if (count_ab != ab.count || count_ba != ba.count)
    finding("the returned count is not the manifold's");
  if (ab.count < 0 || ab.count > kMaxManifoldPoints)
    finding("count out of range");
  if (ab.count != ba.count)
    finding("swapping A and B changed the number of points");
  if (ab.count == 0)
    return 0;
  if (!ab.normal.allFinite() || std::abs(ab.normal.norm() - 1) > Real(1e-9))
    finding("normal not finite or not unit");
  // Nothing tells A from B when both are the same solid in the same place: then the normal
  // need not flip (narrow_phase.hpp).
  const bool same = twins(*a, pose_a, *b, pose_b);
  if (!same && !(ab.normal == -ba.normal))
    finding("swapping A and B did not flip the normal exactly");
  if (same && !(ab.normal == ba.normal))
    finding("twins gave two normals");
  const Real extent = std::max(bounding_radius(*a), bounding_radius(*b));
  for (int i = 0; i < ab.count; ++i) {
    const ContactPoint& p = ab.points[static_cast<std::size_t>(i)];
    const ContactPoint& q = ba.points[static_cast<std::size_t>(i)];
    if (!p.position.allFinite() || !std::isfinite(p.depth))
      finding("point or depth not finite");
    if (!(p.position == q.position) || !(p.depth == q.depth))
      finding("swapping A and B moved a point or changed a depth");
    if (p.depth < -margin - Real(1e-9) * (1 + extent))
      finding("a point farther apart than the margin");
  }
  return 0;
}
