// Trajectory CSV: header `time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz` (README.md, "Using
// it"), one row per body per recorded step, body by name. Written atomically on finish().
#pragma once

#include <filesystem>

#include "apps/atomic_file.hpp"
#include "engine/state.hpp"
#include "tumble/scene.hpp"

namespace tumble::app {

inline constexpr const char* kTrajectoryHeader = "time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";

class TrajectoryWriter {
 public:
  TrajectoryWriter(const std::filesystem::path& path, const Scene& scene);
  void record(const State& state);
  void finish() { file_.commit(); }

 private:
  AtomicFile file_;
  const Scene& scene_;
};

}  // namespace tumble::app
