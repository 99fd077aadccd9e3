// The SDF evaluators (collision/sdf/sdf_tree.hpp): trees of analytic primitives under rigid
// poses, combined by union, intersection, difference and smooth union to a fuzzed depth, sampled
// at fuzzed points. A tree is built or refused with tumble::Error; a sample of a finite point is
// finite, and its gradient is no longer than 1 (every primitive is 1-Lipschitz, and min, max and
// the log-sum-exp keep that) and unit outside a lone primitive; the distance alone (distance())
// is the sample's to the bit.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "collision/sdf/sdf_tree.hpp"
#include "tests/fuzz/fuzz_input.hpp"

namespace {

using namespace tumble;

[[noreturn]] void finding(const char* what) {
  fuzz::finding("sdf", what);
}

SdfNode node(FuzzedDataProvider& in, int depth) {
  const int kind = in.ConsumeIntegralInRange<int>(0, depth < 4 ? 9 : 5);
  SdfNode n;
  switch (kind) {
    case 0:
      n = SdfNode::sphere(fuzz::length(in));
      break;
    case 1:
      n = SdfNode::box({fuzz::length(in), fuzz::length(in), fuzz::length(in)});
      break;
    case 2:
      n = SdfNode::capsule(fuzz::length(in), fuzz::length(in));
      break;
    case 3:
      n = SdfNode::cylinder(fuzz::length(in), fuzz::length(in));
      break;
    case 4: {
      const Real major = fuzz::length(in);
      n = SdfNode::torus(major,
                         major * in.ConsumeFloatingPointInRange<Real>(Real(0.01), Real(1.2)));
      break;
    }
    case 5:
      n = SdfNode::plane();
      break;
    default: {
      static constexpr SdfKind kOperations[4] = {SdfKind::union_of, SdfKind::intersection_of,
                                                 SdfKind::difference_of, SdfKind::smooth_union_of};
      std::vector<SdfNode> operands;
      const int count = in.ConsumeIntegralInRange<int>(1, 3);
      for (int i = 0; i < count; ++i)
        operands.push_back(node(in, depth + 1));
      n = SdfNode::combine(
          kOperations[kind - 6], std::move(operands),
          in.ConsumeBool() ? Real(8) : in.ConsumeFloatingPointInRange<Real>(-1, 100));
    }
  }
  return in.ConsumeBool() ? n.placed(fuzz::pose(in, 2)) : n;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const SdfNode root = node(in, 0);
  std::optional<SdfTree> tree;
  try {
    tree.emplace(root);
  } catch (const Error&) {
    return 0;  // refused, naming the node
  }
  for (int i = 0; i < 8 && in.remaining_bytes() > 0; ++i) {
    const Vec3 p = fuzz::point(in, in.ConsumeBool() ? Real(2) : Real(1e4));
    const sdf::Sample s = tree->sample(p);
    if (!std::isfinite(s.distance) || !s.gradient.allFinite())
      finding("a sample of a finite point is not finite");
    const Real alone = tree->distance(p);
    if (!(alone == s.distance && std::signbit(alone) == std::signbit(s.distance)))
      finding("the distance alone is not the sample's distance");
    const Real g = s.gradient.norm();
    if (g > 1 + Real(1e-9))
      finding("gradient longer than 1");
    // Outside a lone primitive the nearest surface point is unique (but on a torus's axis).
    if (tree->is_exact() && root.kind != SdfKind::torus && s.distance > Real(1e-9) &&
        std::abs(g - 1) > Real(1e-6))
      finding("an exact primitive's gradient is not unit outside it");
  }
  return 0;
}
