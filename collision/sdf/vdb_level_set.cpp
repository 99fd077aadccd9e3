// OpenVDB level sets as signed distance fields (collision/sdf/vdb_level_set.hpp): reading,
// building from a mesh, writing, and sampling through an accessor.
#include "collision/sdf/vdb_level_set.hpp"

#include <unistd.h>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <system_error>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include "collision/sdf/closed_mesh.hpp"
#include "tumble/error.hpp"

namespace tumble {

struct VdbLevelSet::Impl {
  openvdb::DoubleGrid::Ptr grid;
};

namespace {

void initialise_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

// The level set in double precision: a float grid's tree converted value by value.
openvdb::DoubleGrid::Ptr as_double_grid(const openvdb::GridBase::Ptr& base) {
  if (auto g = openvdb::gridPtrCast<openvdb::DoubleGrid>(base))
    return g;
  auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
  auto tree = std::make_shared<openvdb::DoubleTree>(f->tree());
  auto g = openvdb::DoubleGrid::create(tree);
  g->setTransform(f->transform().copy());
  g->setGridClass(f->getGridClass());
  g->setName(f->getName());
  return g;
}

}  // namespace

bool VdbLevelSet::available() {
  return true;
}

VdbLevelSet::VdbLevelSet(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {
  const openvdb::DoubleGrid& grid = *impl_->grid;
  const openvdb::math::Transform& xf = grid.transform();
  const openvdb::Vec3d o = xf.indexToWorld(openvdb::Vec3d(0, 0, 0));
  const openvdb::Vec3d size = xf.voxelSize();
  voxel_ = size[0];
  // Voxels must be axis-aligned cubes: the sampler maps world to index by a scale and a shift.
  bool cubic = xf.isLinear() && voxel_ > 0 && std::isfinite(voxel_);
  for (int axis = 0; cubic && axis < 3; ++axis) {
    openvdb::Vec3d unit(0, 0, 0);
    unit[axis] = 1;
    const openvdb::Vec3d step = xf.indexToWorld(unit) - o;
    for (int k = 0; k < 3; ++k)
      cubic = cubic && std::abs(step[k] - (k == axis ? voxel_ : 0)) <= 1e-12 * voxel_;
  }
  if (!cubic)
    throw Error("OpenVDB level set: its voxels must be cubes aligned with the axes");
  origin_ = Vec3(o[0], o[1], o[2]);
  band_ = grid.background();
  if (!(band_ > 0) || !std::isfinite(band_))
    throw Error("OpenVDB level set: its background (the band's half width) must be positive");
  active_voxels_ = std::int64_t(grid.activeVoxelCount());
  if (active_voxels_ == 0)
    throw Error("OpenVDB level set: the grid has no active voxels (no surface)");
  if (active_voxels_ > kMaxActiveVoxels)
    throw Error("OpenVDB level set: more than " + std::to_string(kMaxActiveVoxels) +
                " active voxels");
  for (auto it = grid.cbeginValueOn(); it; ++it)
    if (!std::isfinite(*it))
      throw Error("OpenVDB level set: a voxel's value is not finite");
  const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
  const auto corner = [&](const openvdb::Coord& c) {
    return Vec3(origin_ + voxel_ * Vec3(Real(c.x()), Real(c.y()), Real(c.z())));
  };
  bounds_ = {corner(box.min()), corner(box.max())};
  bytes_ = std::size_t(grid.memUsage());
}

VdbLevelSet::~VdbLevelSet() = default;

std::shared_ptr<const VdbLevelSet> VdbLevelSet::load(const std::filesystem::path& file,
                                                     const std::string& name) {
  initialise_openvdb();
  const std::string where = "OpenVDB file " + file.string() + ": ";
  openvdb::GridBase::Ptr chosen;
  try {
    openvdb::io::File f(file.string());
    f.open(false);  // read everything now: the file may change or go after loading
    std::string names;
    for (auto it = f.beginName(); it != f.endName(); ++it) {
      const std::string n = it.gridName();
      names += (names.empty() ? "" : ", ") + n;
      if (!name.empty() && n != name)
        continue;
      openvdb::GridBase::Ptr g = f.readGrid(n);
      const bool scalar = g->isType<openvdb::FloatGrid>() || g->isType<openvdb::DoubleGrid>();
      if (!name.empty() && (!scalar || g->getGridClass() != openvdb::GRID_LEVEL_SET)) {
        f.close();
        throw Error(where + "grid '" + name + "' is not a level set of floats or doubles");
      }
      if (scalar && g->getGridClass() == openvdb::GRID_LEVEL_SET) {
        chosen = g;
        break;
      }
    }
    f.close();
    if (!chosen)
      throw Error(where +
                  (name.empty() ? "no level set of floats or doubles in it"
                                : "no grid named '" + name + "'") +
                  (names.empty() ? " (it has no grids)" : " (its grids: " + names + ")"));
  } catch (const openvdb::Exception& e) {
    throw Error(where + e.what());
  }
  try {
    return std::shared_ptr<const VdbLevelSet>(
        new VdbLevelSet(std::make_unique<Impl>(Impl{as_double_grid(chosen)})));
  } catch (const Error& e) {
    throw Error(where + e.what());
  }
}

std::shared_ptr<const VdbLevelSet> VdbLevelSet::from_mesh(
    std::span<const Vec3> vertices, std::span<const std::array<std::int32_t, 3>> triangles,
    Real voxel, Real band_voxels, BuildReport* report) {
  const auto start_time = std::chrono::steady_clock::now();
  initialise_openvdb();
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
  // OpenVDB takes the vertices in single precision (about 1e-7 of the mesh's size).
  std::vector<openvdb::Vec3s> points;
  points.reserve(vertices.size());
  for (const Vec3& v : vertices)
    points.emplace_back(float(v.x()), float(v.y()), float(v.z()));
  std::vector<openvdb::Vec3I> faces;
  faces.reserve(triangles.size());
  for (const auto& t : triangles)
    faces.emplace_back(openvdb::Index32(t[0]), openvdb::Index32(t[1]), openvdb::Index32(t[2]));
  openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(voxel);
  openvdb::DoubleGrid::Ptr grid;
  try {
    grid =
        openvdb::tools::meshToLevelSet<openvdb::DoubleGrid>(*xf, points, faces, float(band_voxels));
  } catch (const openvdb::Exception& e) {
    throw Error(std::string("OpenVDB level set: ") + e.what());
  }
  grid->setName("surface");
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  auto result =
      std::shared_ptr<const VdbLevelSet>(new VdbLevelSet(std::make_unique<Impl>(Impl{grid})));
  if (report != nullptr) {
    report->active_voxels = result->active_voxels();
    report->bytes = result->bytes();
    report->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  }
  return result;
}

void VdbLevelSet::save(const std::filesystem::path& file, bool single_precision) const {
  initialise_openvdb();
  openvdb::GridBase::ConstPtr grid = impl_->grid;
  if (single_precision) {
    auto floats =
        openvdb::FloatGrid::create(std::make_shared<openvdb::FloatTree>(impl_->grid->tree()));
    floats->setTransform(impl_->grid->transform().copy());
    floats->setGridClass(openvdb::GRID_LEVEL_SET);
    floats->setName(impl_->grid->getName());
    grid = floats;
  }
  const std::filesystem::path temporary =
      file.string() + ".tmp." + std::to_string(static_cast<long>(::getpid()));
  try {
    openvdb::io::File f(temporary.string());
    f.write(openvdb::GridCPtrVec{grid});
    f.close();
  } catch (const openvdb::Exception& e) {
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
  openvdb::DoubleGrid::ConstUnsafeAccessor values = impl_->grid->getConstUnsafeAccessor();
  return sdf::interpolate(cell, t, voxel_, how, [&](int i, int j, int k) {
    return Real(values.getValue(openvdb::Coord(i, j, k)));
  });
}

}  // namespace tumble
