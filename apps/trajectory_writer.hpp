// Trajectory CSV: header `time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz` (README.md, "Using
// it"), one row per listed body per recorded step, body by name. Written atomically on finish().
#pragma once

#include <filesystem>
#include <vector>

#include "apps/atomic_file.hpp"
#include "engine/state.hpp"
#include "tumble/scene.hpp"

namespace tumble::app {

inline constexpr const char* kTrajectoryHeader = "time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";

class TrajectoryWriter {
 public:
  // `bodies`: the scene indices written, in order (trajectory_bodies()).
  TrajectoryWriter(const std::filesystem::path& path, const Scene& scene, std::vector<int> bodies);
  void record(const State& state);
  void finish() { file_.commit(); }

 private:
  AtomicFile file_;
  const Scene& scene_;
  std::vector<int> bodies_;
};

// The bodies a trajectory lists: every body that can move, and the static ones only when asked
// (they never move, and repeating them in every row only grows the file).
std::vector<int> trajectory_bodies(const Scene& scene, bool with_static);

}  // namespace tumble::app
