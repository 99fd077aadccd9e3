// The harness itself, run on the reference: it must hold trivially, and it must produce enough
// overlapping pairs in every layout to make the comparison meaningful.
#include "tests/broad_phase/broad_phase_property.hpp"

namespace tumble::test {
namespace {

TEST(BroadPhaseHarness, BruteForceAgreesWithItself) {
  check_every_layout([] { return std::make_unique<BruteForceBroadPhase>(); },
                     {.bodies = 100, .steps = 50});
}

}  // namespace
}  // namespace tumble::test
