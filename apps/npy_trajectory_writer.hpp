// Trajectory as a NumPy .npy file (format version 1.0: the magic string, a little-endian header
// length, a Python dict literal with descr '<f8', fortran_order False and the shape, then the
// data): float64 [records, bodies, 13] with px py pz qw qx qy qz vx vy vz wx wy wz per listed
// body (summary.json's trajectory_bodies), the columns of trajectory.csv. numpy.load reads it in
// one line. Written atomically on finish().
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "apps/atomic_file.hpp"
#include "engine/state.hpp"

namespace tumble::app {

class NpyTrajectoryWriter {
 public:
  // `bodies`: the scene indices written, in order.
  NpyTrajectoryWriter(const std::filesystem::path& path, std::vector<int> bodies);
  void record(const State& state);
  // Writes the final shape into the header and renames the file into place.
  void finish();

  // The header of a float64 array of `shape`, padded to `size` bytes (a multiple of 64).
  static std::string header(std::int64_t records, std::size_t bodies, std::size_t size);
  static constexpr std::size_t kHeaderSize = 128;

 private:
  AtomicFile file_;
  std::vector<int> bodies_;
  std::int64_t records_ = 0;
};

}  // namespace tumble::app
