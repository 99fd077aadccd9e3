// A signed distance field held as an OpenVDB narrow-band level set (Museth, "VDB: High-resolution
// sparse volumes with dynamic topology", ACM Transactions on Graphics 32(3), 2013): voxels of one
// size stored only within a band of a few voxels around the surface, and constant tiles of
// -band or +band inside and outside. Memory grows with the surface's area, not the volume's, so
// the band can be far finer than a dense grid (collision/sdf/sdf_grid.hpp) of the same memory.
//
// Read from a .vdb file (volumes made by other tools), or built from a closed triangle mesh by
// OpenVDB's mesh-to-level-set conversion. Sampled trilinearly or tricubically with the exact
// gradient of the interpolant (collision/sdf/grid_interpolation.hpp), in double precision whatever
// the file's. Beyond the band the value is the band's edge (+-band): a lower bound of the
// distance, which sphere tracing and contacts accept (contacts happen near phi = 0, inside the
// band), with a zero gradient.
//
// OpenVDB is an optional component (the CMake option TUMBLE_WITH_OPENVDB): in a build without it,
// available() is false and every way to make one throws tumble::Error saying so. In a build with
// it, OpenVDB's code is a module (libtumble_openvdb.so, collision/sdf/openvdb_module.hpp) loaded
// when the first level set is read or built; without the module that throws tumble::Error with
// the places it looked.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "collision/aabb.hpp"
#include "collision/math.hpp"
#include "collision/sdf/grid_interpolation.hpp"
#include "collision/sdf/sdf_primitives.hpp"

namespace tumble {

class VdbLevelSet {
 public:
  static constexpr std::int64_t kMaxActiveVoxels = std::int64_t(1) << 28;

  struct BuildReport {
    std::int64_t active_voxels = 0;
    double seconds = 0;
    std::size_t bytes = 0;
  };

  // Whether this build has OpenVDB.
  static bool available();

  // The first grid of `file` that is a level set of floats or doubles (or the one named `name`).
  // Throws tumble::Error naming the file for a missing or unreadable file, no such grid, a grid
  // that is not a level set, voxels that are not cubes, an empty grid or a non-finite value.
  static std::shared_ptr<const VdbLevelSet> load(const std::filesystem::path& file,
                                                 const std::string& name = "");

  // From a closed mesh (counter-clockwise triangles seen from outside), voxels of `voxel`
  // metres, a band of `band_voxels` voxels on each side of the surface.
  static std::shared_ptr<const VdbLevelSet> from_mesh(
      std::span<const Vec3> vertices, std::span<const std::array<std::int32_t, 3>> triangles,
      Real voxel, Real band_voxels = 3, BuildReport* report = nullptr);

  // Writes the level set to `file` as a grid named "surface" of doubles, or of floats (what most
  // tools read and write) when `single_precision`; atomically (a temporary file renamed).
  void save(const std::filesystem::path& file, bool single_precision = false) const;

  sdf::Sample sample(const Vec3& p, GridInterpolation how = GridInterpolation::trilinear) const;

  Real voxel() const { return voxel_; }
  Real band() const { return band_; }  // m: the value beyond the band
  // A box holding every point with phi <= 0: the active voxels' box.
  const Aabb& bounds() const { return bounds_; }
  std::int64_t active_voxels() const { return active_voxels_; }
  std::size_t bytes() const { return bytes_; }

  ~VdbLevelSet();
  VdbLevelSet(const VdbLevelSet&) = delete;
  VdbLevelSet& operator=(const VdbLevelSet&) = delete;

  struct Impl;  // the module's grid: only the module sees OpenVDB's headers

 private:
  explicit VdbLevelSet(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
  Real voxel_ = 1;
  Real band_ = 0;
  Vec3 origin_ = Vec3::Zero();  // world position of voxel (0, 0, 0)
  Aabb bounds_;
  std::int64_t active_voxels_ = 0;
  std::size_t bytes_ = 0;
};

}  // namespace tumble
