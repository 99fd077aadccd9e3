// libtumble_openvdb.so: tumble's OpenVDB code (reading, building from a mesh, writing and sampling
// level sets), loaded by VdbLevelSet when a scene first needs it (collision/sdf/openvdb_module.hpp
// says why it is a module). OpenVDB: Museth, "VDB: High-resolution sparse volumes with dynamic
// topology", ACM Transactions on Graphics 32(3), 2013.
#include "collision/sdf/openvdb_module.hpp"

#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include "tumble/error.hpp"

namespace tumble::openvdb_module {
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

class OpenVdbGrid final : public Grid {
 public:
  OpenVdbGrid(openvdb::DoubleGrid::Ptr grid, std::int64_t max_active_voxels)
      : grid_(std::move(grid)) {
    const openvdb::math::Transform& xf = grid_->transform();
    const openvdb::Vec3d o = xf.indexToWorld(openvdb::Vec3d(0, 0, 0));
    voxel = xf.voxelSize()[0];
    // Voxels must be axis-aligned cubes: the sampler maps world to index by a scale and a shift.
    bool cubic = xf.isLinear() && voxel > 0 && std::isfinite(voxel);
    for (int axis = 0; cubic && axis < 3; ++axis) {
      openvdb::Vec3d unit(0, 0, 0);
      unit[axis] = 1;
      const openvdb::Vec3d step = xf.indexToWorld(unit) - o;
      for (int k = 0; k < 3; ++k)
        cubic = cubic && std::abs(step[k] - (k == axis ? voxel : 0)) <= 1e-12 * voxel;
    }
    if (!cubic)
      throw Error("OpenVDB level set: its voxels must be cubes aligned with the axes");
    origin = Vec3(o[0], o[1], o[2]);
    band = grid_->background();
    if (!(band > 0) || !std::isfinite(band))
      throw Error("OpenVDB level set: its background (the band's half width) must be positive");
    active_voxels = std::int64_t(grid_->activeVoxelCount());
    if (active_voxels == 0)
      throw Error("OpenVDB level set: the grid has no active voxels (no surface)");
    if (active_voxels > max_active_voxels)
      throw Error("OpenVDB level set: more than " + std::to_string(max_active_voxels) +
                  " active voxels");
    for (auto it = grid_->cbeginValueOn(); it; ++it)
      if (!std::isfinite(*it))
        throw Error("OpenVDB level set: a voxel's value is not finite");
    const openvdb::CoordBBox box = grid_->evalActiveVoxelBoundingBox();
    lowest = {box.min().x(), box.min().y(), box.min().z()};
    highest = {box.max().x(), box.max().y(), box.max().z()};
    bytes = std::size_t(grid_->memUsage());
  }

  sdf::Sample sample_cell(const int cell[3], const Real t[3],
                          GridInterpolation how) const override {
    openvdb::DoubleGrid::ConstUnsafeAccessor values = grid_->getConstUnsafeAccessor();
    return sdf::interpolate(cell, t, voxel, how, [&](int i, int j, int k) {
      return Real(values.getValue(openvdb::Coord(i, j, k)));
    });
  }

  void write(const std::filesystem::path& file, bool single_precision) const override {
    initialise_openvdb();
    openvdb::GridBase::ConstPtr grid = grid_;
    if (single_precision) {
      auto floats = openvdb::FloatGrid::create(std::make_shared<openvdb::FloatTree>(grid_->tree()));
      floats->setTransform(grid_->transform().copy());
      floats->setGridClass(openvdb::GRID_LEVEL_SET);
      floats->setName(grid_->getName());
      grid = floats;
    }
    try {
      openvdb::io::File f(file.string());
      f.write(openvdb::GridCPtrVec{grid});
      f.close();
    } catch (const openvdb::Exception& e) {
      throw Error(e.what());
    }
  }

 private:
  openvdb::DoubleGrid::Ptr grid_;
};

std::unique_ptr<Grid> load(const std::filesystem::path& file, const std::string& name,
                           std::int64_t max_active_voxels) {
  initialise_openvdb();
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
        throw Error("grid '" + name + "' is not a level set of floats or doubles");
      }
      if (scalar && g->getGridClass() == openvdb::GRID_LEVEL_SET) {
        chosen = g;
        break;
      }
    }
    f.close();
    if (!chosen)
      throw Error((name.empty() ? "no level set of floats or doubles in it"
                                : "no grid named '" + name + "'") +
                  (names.empty() ? " (it has no grids)" : " (its grids: " + names + ")"));
  } catch (const openvdb::Exception& e) {
    throw Error(e.what());
  }
  return std::make_unique<OpenVdbGrid>(as_double_grid(chosen), max_active_voxels);
}

std::unique_ptr<Grid> from_mesh(std::span<const Vec3> vertices,
                                std::span<const std::array<std::int32_t, 3>> triangles, Real voxel,
                                Real band_voxels, std::int64_t max_active_voxels) {
  initialise_openvdb();
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
  return std::make_unique<OpenVdbGrid>(grid, max_active_voxels);
}

const Functions kFunctions{kInterface, &load, &from_mesh};

}  // namespace
}  // namespace tumble::openvdb_module

extern "C" __attribute__((visibility("default"))) const tumble::openvdb_module::Functions*
tumble_openvdb_functions() {
  return &tumble::openvdb_module::kFunctions;
}
