// What `tumble compare`, `report` and `bench` measure when they put two engines side by side:
// per-body pose errors, and for chaotic scenes the statistics that stay comparable when single
// paths do not (centre of mass, pile height, bodies at rest, energy).
#pragma once

#include <string>
#include <vector>

#include "dynamics/rigid_body.hpp"
#include "tumble/scene.hpp"

namespace tumble::app {

// Angle of the rotation that takes orientation a to orientation b [rad], in [0, pi].
Real orientation_error(const Quat& a, const Quat& b);

// Summary statistics of the dynamic bodies of one state.
struct PileStatistics {
  Vec3 centre_of_mass = Vec3::Zero();  // mass-weighted [m]
  Real pile_height = 0;                // highest point of any dynamic body along -gravity [m]
  int bodies_at_rest = 0;              // speed < 0.05 m/s and angular speed < 0.1 rad/s
};

PileStatistics pile_statistics(const Scene& scene, const std::vector<BodyState>& bodies);

// Whether per-body paths are meaningful to compare, or only statistics. Paths are compared
// when at most 10 bodies move and none starts spinning while another dynamic body can hit it;
// a scene of many bodies that collide with speed diverges between any two engines (or one
// engine and one rounding change) after a few impacts, so only statistics can agree.
bool scene_is_chaotic(const Scene& scene);

// A one-line verdict from the largest position error and the scene's size.
std::string position_verdict(Real max_position_error, Real scene_size);

// Length of the diagonal of the box around the dynamic bodies' start positions, plus 1 m [m].
Real scene_size(const Scene& scene);

}  // namespace tumble::app
