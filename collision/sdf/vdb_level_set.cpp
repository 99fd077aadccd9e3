// OpenVDB level sets as signed distance fields (collision/sdf/vdb_level_set.hpp). OpenVDB itself
// is used only by the module libtumble_openvdb.so (collision/sdf/openvdb_module.hpp), loaded here
// the first time a level set is read or built; this file checks what it is given, samples and
// writes atomically.
#include "collision/sdf/vdb_level_set.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string_view>
#include <system_error>
#include <vector>

#include "collision/sdf/closed_mesh.hpp"
#include "collision/sdf/openvdb_module.hpp"
#include "tumble/error.hpp"

namespace tumble {

struct VdbLevelSet::Impl {
  std::unique_ptr<openvdb_module::Grid> grid;
};

namespace {

// The file holding this code, absolute, or empty when it cannot be told. dladdr names a shared
// library by the path it was loaded from, but the main program by argv[0], which may be a bare
// name found on PATH or relative to the working directory: that one is /proc/self/exe. A path
// from the working directory is never used, so a scene's folder cannot supply the module.
std::filesystem::path file_holding_this_code() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&file_holding_this_code), &info) == 0 ||
      info.dli_fname == nullptr || *info.dli_fname == '\0')
    return {};
  std::error_code failed;
  std::filesystem::path file = info.dli_fname;
  if (std::string_view(info.dli_fname) == program_invocation_name)
    file = std::filesystem::read_symlink("/proc/self/exe", failed);
  if (failed || !file.is_absolute())
    return {};
  return std::filesystem::weakly_canonical(file, failed);
}

// Where the module may be, in order. TUMBLE_OPENVDB_MODULE alone when set. For code in this
// build's tree (its tests, tools and Python module), the tree's own module. Otherwise beside the
// program or library that holds this code, as `cmake --install` lays them out (libtumble.so in
// LIBDIR with the module in LIBDIR/tumble, the tools in BINDIR, the Python package in
// LIBDIR/pythonX.Y/site-packages/tumble), then the install prefix this build was configured with.
std::vector<std::filesystem::path> module_candidates() {
  std::vector<std::filesystem::path> paths;
  if (const char* chosen = std::getenv("TUMBLE_OPENVDB_MODULE"); chosen != nullptr && *chosen) {
    paths.emplace_back(chosen);
    return paths;
  }
  const std::filesystem::path holder = file_holding_this_code();
  const std::filesystem::path build_tree = TUMBLE_BUILD_TREE;
  const auto [tree_end, holder_end] =
      std::mismatch(build_tree.begin(), build_tree.end(), holder.begin(), holder.end());
  if (!holder.empty() && tree_end == build_tree.end()) {
    paths.emplace_back(TUMBLE_OPENVDB_MODULE_BUILT);
    return paths;
  }
  const std::filesystem::path name = TUMBLE_OPENVDB_MODULE_NAME;
  if (!holder.empty()) {
    const std::filesystem::path here = holder.parent_path();
    paths.push_back(here / "tumble" / name);
    paths.push_back(here / ".." / TUMBLE_INSTALL_LIBDIR / "tumble" / name);
    paths.push_back(here / ".." / ".." / ".." / "tumble" / name);
  }
  paths.emplace_back(TUMBLE_OPENVDB_MODULE_INSTALLED);
  return paths;
}

struct ModuleLoad {
  const openvdb_module::Functions* functions = nullptr;
  std::string problem;
};

ModuleLoad load_module() {
  ModuleLoad result;
  std::string tried;
  for (const std::filesystem::path& path : module_candidates()) {
    std::error_code missing;
    if (!std::filesystem::exists(path, missing)) {
      tried += (tried.empty() ? "" : ", ") + path.string();
      continue;
    }
    // Never closed: the level sets made by the module live until the program ends.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* reason = dlerror();
      result.problem = "cannot load " + path.string() + ": " + (reason ? reason : "unknown");
      return result;
    }
    using Entry = const openvdb_module::Functions* (*)();
    const auto entry = reinterpret_cast<Entry>(dlsym(handle, openvdb_module::kEntryPoint));
    const openvdb_module::Functions* f = entry != nullptr ? entry() : nullptr;
    if (f == nullptr || f->interface == nullptr ||
        std::string_view(f->interface) != openvdb_module::kInterface) {
      result.problem = path.string() + " is not this build's OpenVDB module (rebuild or reinstall)";
      return result;
    }
    result.functions = f;
    return result;
  }
  result.problem = "this build's OpenVDB module (" TUMBLE_OPENVDB_MODULE_NAME
                   ") is not installed where it was looked for (" +
                   tried + "; TUMBLE_OPENVDB_MODULE names it)";
  return result;
}

// Loaded once, on first use; throws tumble::Error with the reason when it cannot be.
const openvdb_module::Functions& module_functions() {
  static const ModuleLoad loaded = load_module();
  if (loaded.functions == nullptr)
    throw Error("OpenVDB level set: " + loaded.problem);
  return *loaded.functions;
}

}  // namespace

bool VdbLevelSet::available() {
  return true;
}

VdbLevelSet::VdbLevelSet(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {
  const openvdb_module::Grid& g = *impl_->grid;
  voxel_ = g.voxel;
  band_ = g.band;
  origin_ = g.origin;
  active_voxels_ = g.active_voxels;
  bytes_ = g.bytes;
  const auto corner = [&](const std::array<int, 3>& c) {
    return Vec3(origin_ + voxel_ * Vec3(Real(c[0]), Real(c[1]), Real(c[2])));
  };
  bounds_ = {corner(g.lowest), corner(g.highest)};
}

VdbLevelSet::~VdbLevelSet() = default;

std::shared_ptr<const VdbLevelSet> VdbLevelSet::load(const std::filesystem::path& file,
                                                     const std::string& name) {
  const std::string where = "OpenVDB file " + file.string() + ": ";
  try {
    const openvdb_module::Functions& f = module_functions();
    return std::shared_ptr<const VdbLevelSet>(
        new VdbLevelSet(std::make_unique<Impl>(Impl{f.load(file, name, kMaxActiveVoxels)})));
  } catch (const Error& e) {
    throw Error(where + e.what());
  }
}

std::shared_ptr<const VdbLevelSet> VdbLevelSet::from_mesh(
    std::span<const Vec3> vertices, std::span<const std::array<std::int32_t, 3>> triangles,
    Real voxel, Real band_voxels, BuildReport* report) {
  const auto start_time = std::chrono::steady_clock::now();
  require_closed_mesh(vertices, triangles, "OpenVDB level set");
  if (!(voxel > 0) || !std::isfinite(voxel))
    throw Error("OpenVDB level set: the voxel size must be positive and finite");
  if (!(band_voxels >= 1 && band_voxels <= 64))
    throw Error("OpenVDB level set: the band must be 1 to 64 voxels wide");
  Aabb box;
  for (const Vec3& v : vertices)
    box.grow(v);
  const Vec3 span = (box.max - box.min) / voxel;
  // A surface of that extent has at most about 2 (xy + yz + zx) band-thick voxel layers.
  const Real estimate =
      2 * (span.x() * span.y() + span.y() * span.z() + span.z() * span.x()) * 2 * band_voxels;
  if (!(estimate < Real(kMaxActiveVoxels)))
    throw Error("OpenVDB level set: too many voxels for that voxel size; use larger voxels");
  const openvdb_module::Functions& f = module_functions();
  auto result = std::shared_ptr<const VdbLevelSet>(new VdbLevelSet(std::make_unique<Impl>(
      Impl{f.from_mesh(vertices, triangles, voxel, band_voxels, kMaxActiveVoxels)})));
  if (report != nullptr) {
    report->active_voxels = result->active_voxels();
    report->bytes = result->bytes();
    report->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  }
  return result;
}

void VdbLevelSet::save(const std::filesystem::path& file, bool single_precision) const {
  const std::filesystem::path temporary =
      file.string() + ".tmp." + std::to_string(static_cast<long>(::getpid()));
  try {
    impl_->grid->write(temporary, single_precision);
  } catch (const Error& e) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw Error("OpenVDB file " + file.string() + ": " + e.what());
  }
  std::error_code failed;
  std::filesystem::rename(temporary, file, failed);
  if (failed) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw Error("OpenVDB file " + file.string() + ": " + failed.message());
  }
}

sdf::Sample VdbLevelSet::sample(const Vec3& p, GridInterpolation how) const {
  // Beyond the active voxels' box (grown by a voxel) the value is the box's plus the way to it,
  // a lower bound of the distance that keeps sphere tracing from far away quick.
  const Aabb box{bounds_.min - Vec3::Constant(voxel_), bounds_.max + Vec3::Constant(voxel_)};
  if (!box.contains(p)) {
    const Vec3 q = p.cwiseMax(box.min).cwiseMin(box.max);
    if (!(q.allFinite() && p.allFinite()))
      return {std::numeric_limits<Real>::quiet_NaN(), Vec3::UnitZ()};
    const sdf::Sample s = sample(q, how);
    const Vec3 out = p - q;
    const Real d = out.norm();
    return {s.distance + d, Vec3(out / d)};
  }
  int cell[3];
  Real t[3];
  for (int k = 0; k < 3; ++k) {
    const Real u = (p[k] - origin_[k]) / voxel_;
    const Real f = std::floor(u);
    cell[k] = int(f);
    t[k] = u - f;
  }
  return impl_->grid->sample_cell(cell, t, how);
}

}  // namespace tumble
