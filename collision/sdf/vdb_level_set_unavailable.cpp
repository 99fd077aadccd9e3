// VdbLevelSet in a build without OpenVDB (collision/sdf/vdb_level_set.hpp): nothing can make one,
// and every way to try says why.
#include "collision/sdf/vdb_level_set.hpp"

#include "tumble/error.hpp"

namespace tumble {

struct VdbLevelSet::Impl {};

namespace {
[[noreturn]] void refuse() {
  throw Error(
      "OpenVDB level sets need a build with OpenVDB (Debian libopenvdb-dev, the CMake option "
      "TUMBLE_WITH_OPENVDB), which this one does not have");
}
}  // namespace

bool VdbLevelSet::available() {
  return false;
}
VdbLevelSet::VdbLevelSet(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
VdbLevelSet::~VdbLevelSet() = default;
std::shared_ptr<const VdbLevelSet> VdbLevelSet::load(const std::filesystem::path&,
                                                     const std::string&) {
  refuse();
}
std::shared_ptr<const VdbLevelSet> VdbLevelSet::from_mesh(
    std::span<const Vec3>, std::span<const std::array<std::int32_t, 3>>, Real, Real, BuildReport*) {
  refuse();
}
void VdbLevelSet::save(const std::filesystem::path&, bool) const {
  refuse();
}
sdf::Sample VdbLevelSet::sample(const Vec3&, GridInterpolation) const {
  refuse();
}

}  // namespace tumble
