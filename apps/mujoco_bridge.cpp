// The MuJoCo peer (apps/mujoco_bridge.hpp). The MJCF goes to a temporary file because MuJoCo
// 2.2.2 loads XML from a path (or a virtual file system that needs the same).
#include "apps/mujoco_bridge.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#ifdef TUMBLE_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#include <unistd.h>
#endif

namespace tumble::app {
namespace {

std::string numbers(std::initializer_list<Real> values) {
  std::ostringstream out;
  out.precision(17);
  bool first = true;
  for (const Real v : values) {
    out << (first ? "" : " ") << v;
    first = false;
  }
  return out.str();
}

std::string geom_of(const BodyDesc& b, const std::string& where, Real friction) {
  std::ostringstream g;
  const Shape& s = b.shape;
  switch (s.type) {
    case ShapeType::box:
      g << "<geom type=\"box\" size=\""
        << numbers({s.half_extents.x(), s.half_extents.y(), s.half_extents.z()}) << "\"";
      break;
    case ShapeType::sphere:
      g << "<geom type=\"sphere\" size=\"" << numbers({s.radius}) << "\"";
      break;
    case ShapeType::capsule:
      g << "<geom type=\"capsule\" size=\"" << numbers({s.radius, s.half_length}) << "\"";
      break;
    case ShapeType::plane:
      if (!b.is_static)
        throw std::invalid_argument(where + ": a plane must be static");
      g << "<geom type=\"plane\" size=\"0 0 1\"";
      break;
    default:
      throw std::invalid_argument(where + ": the MuJoCo peer has no " +
                                  std::string(shape_type_name(s.type)));
  }
  // MuJoCo's friction: sliding, torsional, rolling; only sliding is tumble's.
  g << " friction=\"" << numbers({friction, 0.005, 0.0001}) << "\"";
  if (b.is_static) {
    g << " pos=\"" << numbers({b.position.x(), b.position.y(), b.position.z()}) << "\" quat=\""
      << numbers({b.orientation.w(), b.orientation.x(), b.orientation.y(), b.orientation.z()})
      << "\"";
  }
  g << "/>";
  return g.str();
}

}  // namespace

std::string mjcf_of(const Scene& scene) {
  std::vector<Material> materials = scene.materials;
  if (materials.empty())
    materials.push_back(Material{"default"});
  const MixingRule& mix = scene.friction_mixing;
  std::ostringstream x;
  const Vec3 g = scene.world.gravity;
  x << "<mujoco model=\"tumble\">\n"
    << "  <option timestep=\"" << numbers({scene.world.dt}) << "\" gravity=\""
    << numbers({g.x(), g.y(), g.z()})
    << "\"/>\n"
    // MuJoCo 2.2 sizes its arrays up front: room for 8 contacts a body (a box on a plane makes
    // 4) and the 4 rows of each (a pyramidal friction cone); its stack follows from these.
    << "  <size nconmax=\"" << 8 * scene.bodies.size() + 20 << "\" njmax=\""
    << 4 * (8 * scene.bodies.size() + 20) << "\"/>\n"
    << "  <worldbody>\n";
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDesc& b = scene.bodies[i];
    const std::string where = "bodies[" + std::to_string(i) + "] '" + b.name + "'";
    if (b.kinematic)
      throw std::invalid_argument(where + ": the MuJoCo peer has no kinematic bodies");
    const Material& m = materials[std::size_t(b.material)];
    const Real friction = mix ? mix(m, m) : default_friction_mixing(m, m);
    if (b.is_static) {
      x << "    " << geom_of(b, where, friction) << "\n";
      continue;
    }
    x << "    <body pos=\"" << numbers({b.position.x(), b.position.y(), b.position.z()})
      << "\" quat=\""
      << numbers({b.orientation.w(), b.orientation.x(), b.orientation.y(), b.orientation.z()})
      << "\">\n"
      << "      <freejoint/>\n"
      << "      <inertial pos=\"0 0 0\" mass=\"" << numbers({b.mass}) << "\" diaginertia=\""
      << numbers({b.inertia(0, 0), b.inertia(1, 1), b.inertia(2, 2)}) << "\"/>\n"
      << "      " << geom_of(b, where, friction) << "\n"
      << "    </body>\n";
  }
  x << "  </worldbody>\n</mujoco>\n";
  return x.str();
}

#ifdef TUMBLE_HAVE_MUJOCO

bool mujoco_available() {
  return true;
}

std::string mujoco_version() {
  return mj_versionString();
}

struct MujocoBatch::Impl {
  mjModel* model = nullptr;
  std::vector<mjData*> data;
  std::vector<int> free_address;  // qpos address of each dynamic body's free joint

  ~Impl() {
    for (mjData* d : data)
      mj_deleteData(d);
    if (model != nullptr)
      mj_deleteModel(model);
  }
};

MujocoBatch::MujocoBatch(const Scene& scene, int worlds) : impl_(std::make_unique<Impl>()) {
  const std::string xml = mjcf_of(scene);
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("tumble_mjcf_" + std::to_string(::getpid()) + "_" +
       std::to_string(reinterpret_cast<std::uintptr_t>(this)) + ".xml");
  {
    std::ofstream out(path);
    out << xml;
  }
  char error[1000] = "";
  impl_->model = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  std::filesystem::remove(path);
  if (impl_->model == nullptr)
    throw std::runtime_error(std::string("MuJoCo refused the scene's MJCF: ") + error);
  for (int j = 0; j < impl_->model->njnt; ++j)
    impl_->free_address.push_back(impl_->model->jnt_qposadr[j]);
  for (int w = 0; w < worlds; ++w)
    impl_->data.push_back(mj_makeData(impl_->model));
}

MujocoBatch::~MujocoBatch() = default;

int MujocoBatch::size() const {
  return static_cast<int>(impl_->data.size());
}

void MujocoBatch::step(int w) {
  mj_step(impl_->model, impl_->data[std::size_t(w)]);
}

void MujocoBatch::reset(int w) {
  mj_resetData(impl_->model, impl_->data[std::size_t(w)]);
}

int MujocoBatch::contacts(int w) const {
  return impl_->data[std::size_t(w)]->ncon;
}

Real MujocoBatch::height(int w, int dynamic_body) const {
  return impl_->data[std::size_t(w)]->qpos[impl_->free_address[std::size_t(dynamic_body)] + 2];
}

std::size_t MujocoBatch::bytes_per_world() const {
  const mjData* d = impl_->data.front();
  return std::size_t(d->nbuffer) + std::size_t(d->nstack) * sizeof(mjtNum);
}

#else

bool mujoco_available() {
  return false;
}

std::string mujoco_version() {
  return "absent";
}

struct MujocoBatch::Impl {};

MujocoBatch::MujocoBatch(const Scene&, int) {
  throw std::runtime_error("this build of tumble has no MuJoCo (install libmujoco-dev)");
}
MujocoBatch::~MujocoBatch() = default;
int MujocoBatch::size() const {
  return 0;
}
void MujocoBatch::step(int) {}
void MujocoBatch::reset(int) {}
int MujocoBatch::contacts(int) const {
  return 0;
}
Real MujocoBatch::height(int, int) const {
  return 0;
}
std::size_t MujocoBatch::bytes_per_world() const {
  return 0;
}

#endif

}  // namespace tumble::app
