#include "collision/broad_phase_factory.hpp"

#include <array>

#include "collision/brute_force_broad_phase.hpp"

namespace tumble {
namespace {

struct Entry {
  BroadPhaseType type;
  std::string_view name;
};

constexpr std::array<Entry, 10> kEntries{{
    {BroadPhaseType::automatic, "auto"},
    {BroadPhaseType::brute, "brute"},
    {BroadPhaseType::sap, "sap"},
    {BroadPhaseType::hash, "hash"},
    {BroadPhaseType::bvh, "bvh"},
    {BroadPhaseType::lbvh, "lbvh"},
    {BroadPhaseType::octree, "octree"},
    {BroadPhaseType::kdtree, "kdtree"},
    {BroadPhaseType::grid, "grid"},
    {BroadPhaseType::hgrid, "hgrid"},
}};

// The structures that exist so far; the others arrive with the broad-phase issue.
constexpr std::array<BroadPhaseType, 1> kConcrete{BroadPhaseType::brute};

}  // namespace

std::string_view broad_phase_name(BroadPhaseType type) {
  for (const Entry& e : kEntries) {
    if (e.type == type)
      return e.name;
  }
  return "unknown";
}

std::optional<BroadPhaseType> parse_broad_phase(std::string_view name) {
  for (const Entry& e : kEntries) {
    if (e.name == name)
      return e.type;
  }
  return std::nullopt;
}

std::span<const BroadPhaseType> concrete_broad_phases() {
  return kConcrete;
}

std::unique_ptr<BroadPhase> make_broad_phase(BroadPhaseType type) {
  switch (type) {
    default:
      return std::make_unique<BruteForceBroadPhase>();
  }
}

}  // namespace tumble
