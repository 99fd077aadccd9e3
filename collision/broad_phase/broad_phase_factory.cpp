#include "collision/broad_phase/broad_phase_factory.hpp"

#include <array>

#include "collision/broad_phase/brute_force_broad_phase.hpp"
#include "collision/broad_phase/dynamic_tree_broad_phase.hpp"
#include "collision/broad_phase/hierarchical_grid_broad_phase.hpp"
#include "collision/broad_phase/kd_tree_broad_phase.hpp"
#include "collision/broad_phase/linear_bvh_broad_phase.hpp"
#include "collision/broad_phase/loose_octree_broad_phase.hpp"
#include "collision/broad_phase/spatial_hash_broad_phase.hpp"
#include "collision/broad_phase/sweep_and_prune_broad_phase.hpp"
#include "collision/broad_phase/uniform_grid_broad_phase.hpp"

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

constexpr std::array<BroadPhaseType, 9> kConcrete{
    BroadPhaseType::brute,  BroadPhaseType::sap,  BroadPhaseType::hash,
    BroadPhaseType::bvh,    BroadPhaseType::lbvh, BroadPhaseType::octree,
    BroadPhaseType::kdtree, BroadPhaseType::grid, BroadPhaseType::hgrid};

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
    case BroadPhaseType::automatic:
    case BroadPhaseType::brute:
      return std::make_unique<BruteForceBroadPhase>();
    case BroadPhaseType::sap:
      return std::make_unique<SweepAndPruneBroadPhase>();
    case BroadPhaseType::hash:
      return std::make_unique<SpatialHashBroadPhase>();
    case BroadPhaseType::bvh:
      return std::make_unique<DynamicTreeBroadPhase>();
    case BroadPhaseType::lbvh:
      return std::make_unique<LinearBvhBroadPhase>();
    case BroadPhaseType::octree:
      return std::make_unique<LooseOctreeBroadPhase>();
    case BroadPhaseType::kdtree:
      return std::make_unique<KdTreeBroadPhase>();
    case BroadPhaseType::grid:
      return std::make_unique<UniformGridBroadPhase>();
    case BroadPhaseType::hgrid:
      return std::make_unique<HierarchicalGridBroadPhase>();
  }
  return std::make_unique<BruteForceBroadPhase>();
}

}  // namespace tumble
