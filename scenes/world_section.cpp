// The `world` and `camera` sections of a scene file (docs/scene-format.md).
#include <algorithm>
#include <cmath>
#include <string>

#include "collision/broad_phase/broad_phase_factory.hpp"
#include "scenes/yaml_reader.hpp"

namespace tumble::scene_yaml {
namespace {

// clang-format off
constexpr std::array<std::string_view, 24> kWorldKeys{
    "gravity", "dt", "duration", "steps", "substeps", "max_substeps", "solver", "iterations",
    "relax_iterations", "broadphase", "ccd", "contact_recycling", "contact_margin",
    "penetration_slop", "contact_hertz", "sag_tolerance", "contact_damping_ratio",
    "max_push_velocity", "restitution_threshold", "sleeping", "sleep_speed", "sleep_time",
    "threads", "geometry"};
// clang-format on
constexpr std::array<std::string_view, 3> kCameraKeys{"position", "target", "fov"};

}  // namespace

void Loader::load_world(const Entry* e, WorldSettings& w) const {
  if (e == nullptr) {
    return;
  }
  const Fields f = read_map(e->value, e->mark(), "world", "a map of world settings", true);
  check_known(f, kWorldKeys);
  const auto path = [](std::string_view key) { return child("world", key); };

  if (const Entry* x = f.find("gravity")) {
    w.gravity = read_vector<3>(*x, path("gravity"), "[x, y, z]", "m/s^2", kAcceleration);
  }
  if (const Entry* x = f.find("dt")) {
    w.dt = read_real(*x, path("dt"), kTimeStep);
  }
  const Entry* duration = f.find("duration");
  const Entry* steps = f.find("steps");
  if (duration != nullptr && steps != nullptr) {
    fail(steps->key_mark, path("steps"),
         "give either duration or steps, not both (duration is on line " +
             std::to_string(duration->key_mark.line + 1) + ")");
  }
  if (duration != nullptr) {
    w.duration = read_real(*duration, path("duration"), kDuration);
  }
  if (steps != nullptr) {
    w.steps = read_int(*steps, path("steps"), kSteps);
    // Keep duration consistent with the steps actually run, for summaries that print it.
    w.duration = static_cast<Real>(*w.steps) * w.dt;
  } else {
    // The run length is ceil(duration / dt): bound it like an explicit step count.
    const Real n = std::ceil(w.duration / w.dt);
    if (!(n <= static_cast<Real>(kMaxSteps))) {
      const Entry* culprit = duration != nullptr ? duration : f.find("dt");
      const YAML::Mark where = culprit != nullptr ? culprit->mark() : f.mark;
      fail(where, path(culprit != nullptr ? culprit->key : "dt"),
           "duration / dt gives " + fmt(n) +
               " steps; at most 1e9 are allowed (raise dt or shorten duration)");
    }
  }
  if (const Entry* x = f.find("substeps")) {
    w.substeps = static_cast<int>(read_int(*x, path("substeps"), kSubsteps));
  }
  if (const Entry* x = f.find("max_substeps")) {
    w.max_substeps = static_cast<int>(read_int(*x, path("max_substeps"), kSubsteps));
  }
  if (const Entry* x = f.find("solver")) {
    const std::string s = read_word(*x, path("solver"), "a solver name (impulse, penalty)");
    if (s == "impulse") {
      w.solver = SolverType::impulse;
    } else if (s == "penalty") {
      w.solver = SolverType::penalty;
    } else {
      fail(x->mark(), path("solver"),
           "expected one of: impulse, penalty, got " + describe(x->value));
    }
  }
  if (const Entry* x = f.find("iterations")) {
    w.iterations = static_cast<int>(read_int(*x, path("iterations"), kIterations));
  }
  if (const Entry* x = f.find("relax_iterations")) {
    w.relax_iterations = static_cast<int>(read_int(*x, path("relax_iterations"), kRelaxIterations));
  }
  if (const Entry* x = f.find("broadphase")) {
    const std::string s = read_word(*x, path("broadphase"), "a broad phase name");
    if (const auto type = parse_broad_phase(s)) {
      w.broadphase = *type;
    } else {
      fail(x->mark(), path("broadphase"),
           "expected one of: auto, brute, sap, hash, bvh, lbvh, octree, kdtree, grid, hgrid, "
           "got " +
               describe(x->value));
    }
  }

  if (const Entry* x = f.find("ccd")) {
    // Read as a word: YAML 1.1 would turn the bare on/off into booleans, but the text is kept.
    const std::string s = read_word(*x, path("ccd"), "one of: auto, on, off");
    if (s == "auto") {
      w.ccd = CcdMode::automatic;
    } else if (s == "on") {
      w.ccd = CcdMode::on;
    } else if (s == "off") {
      w.ccd = CcdMode::off;
    } else {
      fail(x->mark(), path("ccd"), "expected one of: auto, on, off, got " + describe(x->value));
    }
  }
  if (const Entry* x = f.find("contact_recycling")) {
    w.contact_recycling = read_bool(*x, path("contact_recycling"));
  }
  if (const Entry* x = f.find("contact_margin")) {
    w.contact_margin = read_real(*x, path("contact_margin"), kDistance);
  }
  if (const Entry* x = f.find("penetration_slop")) {
    w.penetration_slop = read_real(*x, path("penetration_slop"), kDistance);
  }
  if (const Entry* x = f.find("contact_hertz")) {
    if (x->value.kind == Node::Kind::scalar && x->value.scalar == "auto")
      w.contact_hertz.reset();
    else
      w.contact_hertz = read_real(*x, path("contact_hertz"), kFrequency);
  }
  if (const Entry* x = f.find("geometry")) {
    const std::string g = read_word(*x, path("geometry"), "a geometry (deploy, train)");
    if (g == "deploy") {
      w.geometry = Geometry::deploy;
    } else if (g == "train") {
      w.geometry = Geometry::train;
    } else {
      fail(x->mark(), path("geometry"),
           "expected one of: deploy, train, got " + describe(x->value));
    }
  }
  if (const Entry* x = f.find("threads")) {
    if (x->value.kind == Node::Kind::scalar && x->value.scalar == "auto")
      w.threads = 0;
    else
      w.threads = static_cast<int>(read_int(*x, path("threads"), kThreads));
  }
  if (const Entry* x = f.find("sag_tolerance")) {
    w.sag_tolerance = read_real(*x, path("sag_tolerance"), kSagTolerance);
  }
  if (const Entry* x = f.find("contact_damping_ratio")) {
    w.contact_damping_ratio = read_real(*x, path("contact_damping_ratio"), kDampingRatio);
  }
  if (const Entry* x = f.find("max_push_velocity")) {
    w.max_push_velocity = read_real(*x, path("max_push_velocity"), kPushSpeed);
  }
  if (const Entry* x = f.find("restitution_threshold")) {
    w.restitution_threshold = read_real(*x, path("restitution_threshold"), kSpeedThreshold);
  }
  if (const Entry* x = f.find("sleeping")) {
    w.sleeping = read_bool(*x, path("sleeping"));
  }
  if (const Entry* x = f.find("sleep_speed")) {
    w.sleep_speed = read_real(*x, path("sleep_speed"), kPushSpeed);
  }
  if (const Entry* x = f.find("sleep_time")) {
    w.sleep_time = read_real(*x, path("sleep_time"), kDuration);
  }
}

Camera Loader::load_camera(const Entry& e) const {
  const Fields f = read_map(e.value, e.mark(), "camera", "a map {position, target, fov}", true);
  check_known(f, kCameraKeys);
  Camera c;
  if (const Entry* x = f.find("position")) {
    c.position = read_vector<3>(*x, "camera.position", "[x, y, z]", "metres", kCoordinate);
  }
  if (const Entry* x = f.find("target")) {
    c.target = read_vector<3>(*x, "camera.target", "[x, y, z]", "metres", kCoordinate);
  }
  if (const Entry* x = f.find("fov")) {
    c.fov = read_real(*x, "camera.fov", kFov);
  }
  // Closer than kMinCameraDistance the difference has no direction worth the name (1e-300 m
  // apart gave blank frames); the same rule as check_scene's, here with the line.
  if (!((c.target - c.position).norm() >= kMinCameraDistance)) {
    const Entry* x = f.find("target") != nullptr ? f.find("target") : f.find("position");
    const YAML::Mark where = x != nullptr ? x->mark() : f.mark;
    fail(where, "camera.target",
         "the camera's target is within 1e-6 m of its position, so it has no view direction");
  }
  return c;
}

}  // namespace tumble::scene_yaml
