// The boundary between VdbLevelSet (collision/sdf/vdb_level_set.hpp) and the module that holds
// tumble's OpenVDB code, libtumble_openvdb.so, which VdbLevelSet loads (dlopen) the first time a
// level set is read or built.
//
// Why a module: libopenvdb and what it brings (Boost, log4cplus, Blosc, TBB) cost each start of
// a program that links them about 80 ms of symbol resolution, whether a scene has a level set
// or not; a scene should pay only for what it uses. Only the module includes OpenVDB's headers.
//
// Both sides are built by the same build with the same compiler, so the boundary is plain C++
// (an abstract class, std::unique_ptr, tumble::Error thrown through it). kInterface, the SHA-256
// of this header that the build computes (collision/CMakeLists.txt), keeps a module built from
// another version of it from being used.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "collision/math.hpp"
#include "collision/sdf/grid_interpolation.hpp"
#include "collision/sdf/sdf_primitives.hpp"

namespace tumble::openvdb_module {

constexpr const char* kInterface = TUMBLE_OPENVDB_INTERFACE;

// The module's entry point, looked up by this name: `extern "C" const Functions*
// tumble_openvdb_functions()`.
constexpr const char* kEntryPoint = "tumble_openvdb_functions";

// A level set in double precision, checked when made (voxels are axis-aligned cubes, a positive
// finite background, at least one active voxel, at most `max_active_voxels`, every value
// finite).
class Grid {
 public:
  virtual ~Grid() = default;

  Real voxel = 1;               // m, the voxels' edge
  Real band = 0;                // m, the value beyond the band (the grid's background)
  Vec3 origin = Vec3::Zero();   // world position of voxel (0, 0, 0)
  std::array<int, 3> lowest{};  // the active voxels' box, in voxel coordinates
  std::array<int, 3> highest{};
  std::int64_t active_voxels = 0;
  std::size_t bytes = 0;

  // The interpolant in the cell whose lowest node is `cell`, at fractions `t` (in [0, 1]).
  virtual sdf::Sample sample_cell(const int cell[3], const Real t[3],
                                  GridInterpolation how) const = 0;

  // Writes the grid named "surface" to `file` (not atomically: the caller renames).
  virtual void write(const std::filesystem::path& file, bool single_precision) const = 0;
};

struct Functions {
  const char* interface = nullptr;  // kInterface as the module was built
  // The first level set of floats or doubles in `file`, or the grid named `name`. Throws
  // tumble::Error (without the file's name: the caller adds it).
  std::unique_ptr<Grid> (*load)(const std::filesystem::path& file, const std::string& name,
                                std::int64_t max_active_voxels) = nullptr;
  // OpenVDB's mesh-to-level-set conversion of a mesh the caller has checked. Throws tumble::Error.
  std::unique_ptr<Grid> (*from_mesh)(std::span<const Vec3> vertices,
                                     std::span<const std::array<std::int32_t, 3>> triangles,
                                     Real voxel, Real band_voxels,
                                     std::int64_t max_active_voxels) = nullptr;
};

}  // namespace tumble::openvdb_module
