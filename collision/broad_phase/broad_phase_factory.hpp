// Names and construction of the broad-phase structures, so the engine, the CLI, tests and
// benchmarks all choose a structure the same way.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string_view>

#include "collision/broad_phase/broad_phase.hpp"

namespace tumble {

std::string_view broad_phase_name(BroadPhaseType type);
std::optional<BroadPhaseType> parse_broad_phase(std::string_view name);

// Every concrete structure, in a fixed order (not `automatic`).
std::span<const BroadPhaseType> concrete_broad_phases();

// A new, empty structure of the given type. `automatic` must be resolved first
// (choose_broad_phase in engine/); asking for it here returns brute force.
std::unique_ptr<BroadPhase> make_broad_phase(BroadPhaseType type);

}  // namespace tumble
