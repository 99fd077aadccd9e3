#include "renders/renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "collision/shapes/surface_mesh.hpp"
#include "renders/camera_framing.hpp"
#include "renders/osmesa_library.hpp"

#if defined(__SANITIZE_ADDRESS__)
// Mesa's OSMesa keeps framebuffer records it never frees (a list that lives until exit); they
// are not tumble's leaks. LeakSanitizer calls this hook, defined by any linked object, for the
// suppressions it starts with.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libOSMesa.so\n";
}
#endif

namespace tumble::render {
namespace {

using Colour = std::array<float, 3>;
using Matrix = std::array<double, 16>;  // column-major, as OpenGL takes it

constexpr std::array<std::string_view, kOverlayCount> kOverlayNames = {"aabb", "pairs", "contacts",
                                                                       "stage", "rest"};

// Distinct, not too saturated hues for dynamic bodies, by body index.
constexpr std::array<Colour, 8> kPalette = {{{0.86f, 0.42f, 0.26f},
                                             {0.27f, 0.56f, 0.82f},
                                             {0.93f, 0.75f, 0.27f},
                                             {0.42f, 0.72f, 0.42f},
                                             {0.66f, 0.44f, 0.78f},
                                             {0.30f, 0.73f, 0.72f},
                                             {0.88f, 0.50f, 0.64f},
                                             {0.60f, 0.60f, 0.36f}}};
constexpr Colour kStaticColour = {0.62f, 0.58f, 0.54f};
constexpr Colour kBackground = {0.84f, 0.88f, 0.93f};
constexpr Colour kFloorLight = {0.80f, 0.80f, 0.78f};
constexpr Colour kFloorDark = {0.58f, 0.60f, 0.63f};
constexpr Colour kStageNone = {0.55f, 0.60f, 0.68f};
constexpr Colour kStageCandidate = {0.95f, 0.82f, 0.22f};
constexpr Colour kStageTouching = {0.90f, 0.28f, 0.20f};
constexpr Colour kResting = {0.30f, 0.45f, 0.95f};
constexpr Colour kMoving = {0.95f, 0.60f, 0.22f};

Matrix pose_matrix(const Vec3& t, const Quat& q) {
  const Mat3 r = q.toRotationMatrix();
  Matrix m{};
  for (int c = 0; c < 3; ++c) {
    for (int row = 0; row < 3; ++row)
      m[c * 4 + row] = r(row, c);
  }
  m[12] = t.x();
  m[13] = t.y();
  m[14] = t.z();
  m[15] = 1;
  return m;
}

Matrix look_at(const Vec3& eye, const Vec3& target) {
  const Vec3 f = (target - eye).normalized();
  Vec3 up = Vec3::UnitZ();
  if (std::abs(f.dot(up)) > 0.999)
    up = Vec3::UnitY();
  const Vec3 s = f.cross(up).normalized();
  const Vec3 u = s.cross(f);
  Matrix m{};
  for (int i = 0; i < 3; ++i) {
    m[i * 4 + 0] = s[i];
    m[i * 4 + 1] = u[i];
    m[i * 4 + 2] = -f[i];
  }
  m[12] = -s.dot(eye);
  m[13] = -u.dot(eye);
  m[14] = f.dot(eye);
  m[15] = 1;
  return m;
}

Matrix perspective(double fov_degrees, double aspect, double near, double far) {
  const double f = 1 / std::tan(fov_degrees * std::numbers::pi / 360);
  Matrix m{};
  m[0] = f / aspect;
  m[5] = f;
  m[10] = (far + near) / (near - far);
  m[11] = -1;
  m[14] = 2 * far * near / (near - far);
  return m;
}

// Projects onto the plane n.x + d = 0 along the direction `l` towards a light at infinity
// (Blinn, "Me and my (fake) shadow", IEEE CG&A 8(1), 1988).
Matrix planar_shadow(const Vec3& n, Real d, const Vec3& l) {
  const std::array<double, 4> plane = {n.x(), n.y(), n.z(), d};
  const std::array<double, 4> light = {l.x(), l.y(), l.z(), 0};
  const double dot = n.dot(l);
  Matrix m{};
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r)
      m[c * 4 + r] = (r == c ? dot : 0) - light[r] * plane[c];
  }
  return m;
}

struct DrawMesh {
  std::vector<float> positions;
  std::vector<float> normals;
  std::vector<GLuint> indices;
};

DrawMesh to_draw_mesh(const SurfaceMesh& mesh) {
  DrawMesh d;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      d.positions.push_back(static_cast<float>(mesh.positions[i][k]));
      d.normals.push_back(static_cast<float>(mesh.normals[i][k]));
    }
  }
  d.indices.assign(mesh.indices.begin(), mesh.indices.end());
  return d;
}

// A checkered quad grid on one plane body, in world coordinates, with its plane equation.
struct Floor {
  std::vector<float> positions;
  std::vector<float> colours;
  Vec3 normal = Vec3::UnitZ();
  Real offset = 0;  // normal.x + offset = 0
};

// A round tile size near `span` / 30: 1, 2 or 5 times a power of ten.
Real nice_tile(Real span) {
  const Real raw = std::max(span / 30, Real(1e-3));
  const Real decade = std::pow(Real(10), std::floor(std::log10(raw)));
  for (const Real step : {Real(1), Real(2), Real(5), Real(10)}) {
    if (decade * step >= raw)
      return decade * step;
  }
  return decade * 10;
}

Floor make_floor(const BodyDesc& plane, const Aabb& bounds, const Vec3& target) {
  const Transform pose{plane.position, plane.orientation};
  Floor floor;
  floor.normal = pose.rotate(Vec3::UnitZ());
  floor.offset = -floor.normal.dot(plane.position);
  // Extent: the bodies' box and the camera target, seen in the plane's frame, with a margin.
  Real lo_x = target.x(), hi_x = lo_x, lo_y = target.y(), hi_y = lo_y;
  {
    const Vec3 local = pose.apply_inverse(target);
    lo_x = hi_x = local.x();
    lo_y = hi_y = local.y();
  }
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p((corner & 1) ? bounds.max.x() : bounds.min.x(),
                 (corner & 2) ? bounds.max.y() : bounds.min.y(),
                 (corner & 4) ? bounds.max.z() : bounds.min.z());
    const Vec3 local = pose.apply_inverse(p);
    lo_x = std::min(lo_x, local.x());
    hi_x = std::max(hi_x, local.x());
    lo_y = std::min(lo_y, local.y());
    hi_y = std::max(hi_y, local.y());
  }
  const Real size = std::max({hi_x - lo_x, hi_y - lo_y, Real(1)});
  const Real margin = std::max(Real(4), 2 * size);
  const Real tile = nice_tile(size + 2 * margin);
  const auto first_x = static_cast<long>(std::floor((lo_x - margin) / tile));
  const auto last_x = static_cast<long>(std::ceil((hi_x + margin) / tile));
  const auto first_y = static_cast<long>(std::floor((lo_y - margin) / tile));
  const auto last_y = static_cast<long>(std::ceil((hi_y + margin) / tile));
  for (long i = first_x; i < last_x; ++i) {
    for (long j = first_y; j < last_y; ++j) {
      const Colour& c = ((i + j) % 2 == 0) ? kFloorLight : kFloorDark;
      const Real x0 = i * tile, x1 = (i + 1) * tile, y0 = j * tile, y1 = (j + 1) * tile;
      const std::array<Vec3, 6> corners = {Vec3(x0, y0, 0), Vec3(x1, y0, 0), Vec3(x1, y1, 0),
                                           Vec3(x0, y0, 0), Vec3(x1, y1, 0), Vec3(x0, y1, 0)};
      for (const Vec3& local : corners) {
        const Vec3 p = pose.apply(local);
        for (int k = 0; k < 3; ++k) {
          floor.positions.push_back(static_cast<float>(p[k]));
          floor.colours.push_back(c[k]);
        }
      }
    }
  }
  return floor;
}

}  // namespace

std::string_view overlay_name(Overlay overlay) {
  return kOverlayNames[static_cast<std::size_t>(overlay)];
}

std::optional<Overlay> parse_overlay(std::string_view name) {
  for (int i = 0; i < kOverlayCount; ++i) {
    if (kOverlayNames[i] == name)
      return static_cast<Overlay>(i);
  }
  return std::nullopt;
}

std::string overlay_names() {
  std::string names;
  for (const std::string_view name : kOverlayNames) {
    if (!names.empty())
      names += ", ";
    names += name;
  }
  return names;
}

struct Renderer::Impl {
  // Loaded when the first renderer is made (throws with the reason when libOSMesa is missing).
  const OsMesaLibrary& gl = osmesa_library();
  const Scene& scene;
  RenderSettings settings;
  Camera camera;
  int buffer_width = 0;
  int buffer_height = 0;
  std::vector<std::uint8_t> buffer;  // RGBA, bottom row first
  OSMesaContext context = nullptr;
  std::vector<DrawMesh> meshes;  // per body; empty for planes
  std::vector<Floor> floors;
  Vec3 light = Vec3::UnitZ();  // towards the light
  double near = 0.05, far = 100;
  Real arrow_length = Real(0.2);
  std::vector<int> stage;  // per body, for the stage overlay

  Impl(const Scene& s, const RenderSettings& r) : scene(s), settings(r) {}

  Colour body_colour(std::size_t i, const State& state) const {
    const BodyDesc& d = scene.bodies[i];
    if (settings.has(Overlay::stage))
      return stage[i] == 2 ? kStageTouching : stage[i] == 1 ? kStageCandidate : kStageNone;
    if (settings.has(Overlay::rest) && !d.is_static) {
      // With sleeping on, the engine's own verdict; without it, which bodies would be candidates.
      const BodyState& b = state.bodies[i];
      const bool resting = scene.world.sleeping
                               ? state.asleep[i] != 0
                               : b.velocity.norm() < 0.05 && b.angular_velocity.norm() < 0.05;
      return resting ? kResting : kMoving;
    }
    return d.is_static ? kStaticColour : kPalette[i % kPalette.size()];
  }

  void set_colour(const Colour& c, float alpha = 1) const { gl.glColor4f(c[0], c[1], c[2], alpha); }

  void vertex(const Vec3& p) const { gl.glVertex3d(p.x(), p.y(), p.z()); }

  void draw_mesh(const DrawMesh& m) const {
    gl.glVertexPointer(3, GL_FLOAT, 0, m.positions.data());
    gl.glNormalPointer(GL_FLOAT, 0, m.normals.data());
    gl.glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m.indices.size()), GL_UNSIGNED_INT,
                      m.indices.data());
  }

  void draw_floors() const {
    gl.glEnableClientState(GL_COLOR_ARRAY);
    gl.glDisableClientState(GL_NORMAL_ARRAY);
    gl.glEnable(GL_STENCIL_TEST);
    gl.glStencilFunc(GL_ALWAYS, 1, 0xff);
    gl.glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    gl.glDisable(GL_CULL_FACE);
    for (const Floor& f : floors) {
      gl.glNormal3d(f.normal.x(), f.normal.y(), f.normal.z());
      gl.glVertexPointer(3, GL_FLOAT, 0, f.positions.data());
      gl.glColorPointer(3, GL_FLOAT, 0, f.colours.data());
      gl.glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(f.positions.size() / 3));
    }
    gl.glDisableClientState(GL_COLOR_ARRAY);
    gl.glEnableClientState(GL_NORMAL_ARRAY);
    gl.glDisable(GL_STENCIL_TEST);
  }

  void draw_shadows(const State& state) const {
    gl.glDisable(GL_LIGHTING);
    gl.glEnable(GL_BLEND);
    gl.glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    gl.glDepthMask(GL_FALSE);
    gl.glEnable(GL_POLYGON_OFFSET_FILL);
    gl.glPolygonOffset(-2, -2);
    // Each floor pixel darkens once however many shadows overlap it.
    gl.glEnable(GL_STENCIL_TEST);
    gl.glStencilFunc(GL_EQUAL, 1, 0xff);
    gl.glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
    gl.glColor4f(0.05f, 0.06f, 0.1f, 0.38f);
    for (const Floor& f : floors) {
      if (f.normal.dot(light) <= 0.05)
        continue;  // light grazing or from below: no sensible shadow
      const Matrix shadow = planar_shadow(f.normal, f.offset, light);
      for (std::size_t i = 0; i < meshes.size(); ++i) {
        const BodyState& b = state.bodies[i];
        if (meshes[i].indices.empty() || f.normal.dot(b.position) + f.offset <= 0)
          continue;
        gl.glPushMatrix();
        gl.glMultMatrixd(shadow.data());
        gl.glMultMatrixd(pose_matrix(b.position, b.orientation).data());
        draw_mesh(meshes[i]);
        gl.glPopMatrix();
      }
    }
    gl.glDisable(GL_STENCIL_TEST);
    gl.glDisable(GL_POLYGON_OFFSET_FILL);
    gl.glDepthMask(GL_TRUE);
    gl.glDisable(GL_BLEND);
    gl.glEnable(GL_LIGHTING);
  }

  void draw_bodies(const State& state) const {
    gl.glEnable(GL_CULL_FACE);
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      if (meshes[i].indices.empty())
        continue;
      const BodyState& b = state.bodies[i];
      set_colour(body_colour(i, state));
      gl.glPushMatrix();
      gl.glMultMatrixd(pose_matrix(b.position, b.orientation).data());
      draw_mesh(meshes[i]);
      gl.glPopMatrix();
    }
    gl.glDisable(GL_CULL_FACE);
  }

  void draw_overlays(const Simulation& world) const {
    const State& state = world.state();
    const float s = static_cast<float>(settings.supersample);
    gl.glDisable(GL_LIGHTING);
    gl.glLineWidth(1.5f * s);
    if (settings.has(Overlay::aabb)) {
      set_colour({1.0f, 0.85f, 0.1f});
      gl.glBegin(GL_LINES);
      for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
        if (!scene.bodies[i].shape.is_bounded())
          continue;
        const BodyState& b = state.bodies[i];
        const Aabb box = world_aabb(scene.bodies[i].shape, Transform{b.position, b.orientation});
        const auto corner = [&](int k) {
          return Vec3((k & 1) ? box.max.x() : box.min.x(), (k & 2) ? box.max.y() : box.min.y(),
                      (k & 4) ? box.max.z() : box.min.z());
        };
        for (int k = 0; k < 8; ++k) {
          for (const int bit : {1, 2, 4}) {
            if ((k & bit) == 0) {
              vertex(corner(k));
              vertex(corner(k | bit));
            }
          }
        }
      }
      gl.glEnd();
    }
    // Pairs and contacts show through bodies: they sit where surfaces meet.
    gl.glDisable(GL_DEPTH_TEST);
    if (settings.has(Overlay::pairs)) {
      set_colour({0.1f, 0.85f, 0.95f});
      gl.glBegin(GL_LINES);
      for (const ProxyPair& pair : world.candidate_pairs()) {
        Vec3 ends[2];
        const std::int32_t ids[2] = {pair.a, pair.b};
        for (int e = 0; e < 2; ++e)
          ends[e] = state.bodies[ids[e]].position;
        // A plane's end is the foot of the other body's centre on it.
        for (int e = 0; e < 2; ++e) {
          const BodyDesc& d = scene.bodies[ids[e]];
          if (!d.shape.is_bounded()) {
            const Vec3 n = state.bodies[ids[e]].orientation * Vec3::UnitZ();
            const Vec3& other = ends[1 - e];
            ends[e] = other - n * n.dot(other - state.bodies[ids[e]].position);
          }
        }
        vertex(ends[0]);
        vertex(ends[1]);
      }
      gl.glEnd();
    }
    if (settings.has(Overlay::contacts)) {
      set_colour({0.15f, 0.85f, 0.2f});
      gl.glBegin(GL_LINES);
      for (const PairContact& pc : world.contacts()) {
        for (int k = 0; k < pc.manifold.count; ++k) {
          const Vec3& p = pc.manifold.points[k].position;
          vertex(p);
          vertex(p - arrow_length * pc.manifold.normal);
        }
      }
      gl.glEnd();
      gl.glPointSize(5 * s);
      set_colour({0.9f, 0.1f, 0.1f});
      gl.glBegin(GL_POINTS);
      for (const PairContact& pc : world.contacts()) {
        for (int k = 0; k < pc.manifold.count; ++k)
          vertex(pc.manifold.points[k].position);
      }
      gl.glEnd();
    }
    gl.glEnable(GL_DEPTH_TEST);
    gl.glEnable(GL_LIGHTING);
  }

  void update_stages(const Simulation& world) {
    std::fill(stage.begin(), stage.end(), 0);
    for (const ProxyPair& p : world.candidate_pairs()) {
      stage[p.a] = std::max(stage[p.a], 1);
      stage[p.b] = std::max(stage[p.b], 1);
    }
    for (const PairContact& c : world.contacts()) {
      stage[c.body_a] = 2;
      stage[c.body_b] = 2;
    }
  }
};

std::string render_buffer_problem(const RenderSettings& settings) {
  const long long width = static_cast<long long>(settings.width) * settings.supersample;
  const long long height = static_cast<long long>(settings.height) * settings.supersample;
  if (width > kMaxBufferSide || height > kMaxBufferSide)
    return "the supersampled image, " + std::to_string(width) + "x" + std::to_string(height) +
           ", exceeds OSMesa's 16384 pixels a side: lower --size or --supersample";
  return "";
}

namespace {

// The settings, once they are in range: checked before libOSMesa is loaded, so that a bad size
// gets its own error on any machine.
const RenderSettings& checked(const RenderSettings& settings) {
  if (settings.width < 16 || settings.width > 8192 || settings.height < 16 ||
      settings.height > 8192) {
    throw std::invalid_argument("image size " + std::to_string(settings.width) + "x" +
                                std::to_string(settings.height) + " is outside 16..8192");
  }
  if (settings.supersample < 1 || settings.supersample > 4)
    throw std::invalid_argument("supersample must be 1..4");
  const std::string too_large = render_buffer_problem(settings);
  if (!too_large.empty())
    throw std::invalid_argument(too_large);
  return settings;
}

}  // namespace

Renderer::Renderer(const Scene& scene, const RenderSettings& settings,
                   std::span<const std::uint8_t> hidden)
    : impl_(std::make_unique<Impl>(scene, checked(settings))) {
  Impl& m = *impl_;
  const OsMesaLibrary& gl = m.gl;
  m.buffer_width = settings.width * settings.supersample;
  m.buffer_height = settings.height * settings.supersample;
  m.buffer.resize(static_cast<std::size_t>(m.buffer_width) * m.buffer_height * 4);
  m.stage.resize(scene.bodies.size());

  const State initial = initial_state(scene);
  const double aspect = double(settings.width) / settings.height;
  m.camera = settings.camera ? *settings.camera : choose_camera(scene, initial, aspect);
  const Aabb bounds = bounds_of_bodies(scene, initial);

  TessellationDetail detail;
  std::vector<Real> radii;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDesc& body = scene.bodies[i];
    if (i < hidden.size() && hidden[i] != 0) {
      m.meshes.emplace_back();  // empty: never drawn
      continue;
    }
    if (!body.shape.is_bounded()) {
      m.meshes.emplace_back();
      m.floors.push_back(make_floor(body, bounds, m.camera.target));
      continue;
    }
    m.meshes.push_back(to_draw_mesh(settings.generic_meshes
                                        ? tessellate_convex_support(body.shape, detail)
                                        : tessellate(body.shape, detail)));
    radii.push_back(bounding_radius(body.shape));
  }
  if (!radii.empty()) {
    std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
    m.arrow_length = Real(0.6) * radii[radii.size() / 2];
  }

  // Light from above, over the camera's left shoulder: faces the camera sees differ in brightness
  // (form), and shadows fall to the right and back where the camera sees them.
  const Vec3 forward = (m.camera.target - m.camera.position).normalized();
  Vec3 right = forward.cross(Vec3::UnitZ());
  right = right.norm() > 1e-6 ? right.normalized() : Vec3::UnitX();
  Vec3 towards_camera(-forward.x(), -forward.y(), 0);
  towards_camera = towards_camera.norm() > 1e-6 ? towards_camera.normalized() : Vec3::Zero();
  m.light =
      (Real(1.3) * Vec3::UnitZ() - Real(0.6) * right + Real(0.8) * towards_camera).normalized();

  const Real distance = (m.camera.target - m.camera.position).norm();
  const Real extent = (bounds.max - bounds.min).norm() + 20;
  m.near = std::clamp(distance * 0.01, 0.002, 1.0);
  m.far = distance + 4 * extent;

  m.context = gl.OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
  if (m.context == nullptr)
    throw std::runtime_error("OSMesa could not create an off-screen OpenGL context");
  if (!gl.OSMesaMakeCurrent(m.context, m.buffer.data(), GL_UNSIGNED_BYTE, m.buffer_width,
                            m.buffer_height)) {
    gl.OSMesaDestroyContext(m.context);
    m.context = nullptr;
    throw std::runtime_error("OSMesa could not bind a " + std::to_string(m.buffer_width) + "x" +
                             std::to_string(m.buffer_height) + " buffer");
  }
}

Renderer::~Renderer() {
  if (impl_ && impl_->context != nullptr)
    impl_->gl.OSMesaDestroyContext(impl_->context);
}

const Camera& Renderer::camera() const {
  return impl_->camera;
}

void Renderer::render(const Simulation& world, Image& image) {
  Impl& m = *impl_;
  const OsMesaLibrary& gl = m.gl;
  if (!gl.OSMesaMakeCurrent(m.context, m.buffer.data(), GL_UNSIGNED_BYTE, m.buffer_width,
                            m.buffer_height)) {
    throw std::runtime_error("OSMesa could not make its context current");
  }
  const State& state = world.state();
  if (m.settings.has(Overlay::stage))
    m.update_stages(world);

  gl.glViewport(0, 0, m.buffer_width, m.buffer_height);
  gl.glClearColor(kBackground[0], kBackground[1], kBackground[2], 1);
  gl.glClearStencil(0);
  gl.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  gl.glEnable(GL_DEPTH_TEST);
  gl.glDepthFunc(GL_LEQUAL);
  gl.glFrontFace(GL_CCW);
  gl.glCullFace(GL_BACK);

  gl.glMatrixMode(GL_PROJECTION);
  gl.glLoadMatrixd(
      perspective(m.camera.fov, double(m.settings.width) / m.settings.height, m.near, m.far)
          .data());
  gl.glMatrixMode(GL_MODELVIEW);
  gl.glLoadMatrixd(look_at(m.camera.position, m.camera.target).data());

  // One directional light with ambient; set after the view so its direction is in world space.
  const GLfloat light_direction[4] = {float(m.light.x()), float(m.light.y()), float(m.light.z()),
                                      0};
  const GLfloat ambient[4] = {0.42f, 0.42f, 0.44f, 1};
  const GLfloat diffuse[4] = {0.72f, 0.72f, 0.70f, 1};
  const GLfloat specular[4] = {0.25f, 0.25f, 0.25f, 1};
  const GLfloat no_global_ambient[4] = {0, 0, 0, 1};
  gl.glLightModelfv(GL_LIGHT_MODEL_AMBIENT, no_global_ambient);
  gl.glLightfv(GL_LIGHT0, GL_POSITION, light_direction);
  gl.glLightfv(GL_LIGHT0, GL_AMBIENT, ambient);
  gl.glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
  gl.glLightfv(GL_LIGHT0, GL_SPECULAR, specular);
  gl.glEnable(GL_LIGHT0);
  gl.glEnable(GL_LIGHTING);
  gl.glEnable(GL_NORMALIZE);
  gl.glShadeModel(GL_SMOOTH);
  gl.glEnable(GL_COLOR_MATERIAL);
  gl.glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
  const GLfloat material_specular[4] = {0.3f, 0.3f, 0.3f, 1};
  gl.glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, material_specular);
  gl.glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, 24);

  // The floor's far edge fades into the background.
  const Real distance = (m.camera.target - m.camera.position).norm();
  const GLfloat fog_colour[4] = {kBackground[0], kBackground[1], kBackground[2], 1};
  gl.glFogi(GL_FOG_MODE, GL_LINEAR);
  gl.glFogfv(GL_FOG_COLOR, fog_colour);
  gl.glFogf(GL_FOG_START, static_cast<float>(distance * 1.2));
  gl.glFogf(GL_FOG_END, static_cast<float>(distance * 3));
  gl.glEnable(GL_FOG);

  gl.glEnableClientState(GL_VERTEX_ARRAY);
  gl.glEnableClientState(GL_NORMAL_ARRAY);
  m.draw_floors();
  if (m.settings.shadows)
    m.draw_shadows(state);
  m.draw_bodies(state);
  gl.glDisable(GL_FOG);
  if (m.settings.overlays != 0)
    m.draw_overlays(world);
  gl.glDisableClientState(GL_NORMAL_ARRAY);
  gl.glDisableClientState(GL_VERTEX_ARRAY);
  gl.glFinish();

  // Box filter down to the output size; OSMesa's rows run bottom-up.
  const int s = m.settings.supersample;
  image.width = m.settings.width;
  image.height = m.settings.height;
  image.rgb.resize(static_cast<std::size_t>(image.width) * image.height * 3);
  const int samples = s * s;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      int sum[3] = {0, 0, 0};
      for (int j = 0; j < s; ++j) {
        const int row = m.buffer_height - 1 - (y * s + j);
        const std::uint8_t* p =
            m.buffer.data() + (static_cast<std::size_t>(row) * m.buffer_width + x * s) * 4;
        for (int i = 0; i < s; ++i) {
          for (int c = 0; c < 3; ++c)
            sum[c] += p[i * 4 + c];
        }
      }
      std::uint8_t* out = image.rgb.data() + (static_cast<std::size_t>(y) * image.width + x) * 3;
      for (int c = 0; c < 3; ++c)
        out[c] = static_cast<std::uint8_t>((sum[c] + samples / 2) / samples);
    }
  }
}

}  // namespace tumble::render
