// A short simulated scene: up to six bodies of any shape, in any pose and motion, with world
// settings drawn across and beyond their documented ranges, through the C++ API (compile, World).
// A scene outside the ranges is refused with tumble::Error naming the field; one inside runs up to
// 20 steps, after each of which every body's state is finite, or the world stops with tumble::Error
// (a NonFiniteStateError names the body). A crash, another exception, a sanitizer report or a hang
// is a finding.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "tests/fuzz/fuzz_input.hpp"
#include "tumble/model.hpp"
#include "tumble/world.hpp"

namespace {

using namespace tumble;

// A setting: a usual value, an edge of its range, or (rarely) a value outside it.
Real setting(FuzzedDataProvider& in, Real usual, Real low, Real high) {
  switch (in.ConsumeIntegralInRange<int>(0, 7)) {
    case 0:
      return low;
    case 1:
      return high;
    case 2:
      return in.ConsumeFloatingPointInRange<Real>(low, high);
    case 3:
      return in.ConsumeFloatingPoint<Real>();  // anything, NaN and infinities included
    default:
      return usual;
  }
}

BodyDesc body(FuzzedDataProvider& in, int index) {
  const bool fixed = in.ConsumeIntegralInRange<int>(0, 3) == 0;
  std::optional<Shape> shape = fuzz::shape(in, !fixed);
  if (!shape)
    shape = Shape::sphere(Real(0.5));
  BodyDesc b = fixed ? static_body("b" + std::to_string(index), *shape)
                     : dynamic_body("b" + std::to_string(index), *shape,
                                    setting(in, 1000, Real(1e-3), Real(1e5)));
  b.kinematic =
      !fixed && shape->type != ShapeType::mesh && in.ConsumeIntegralInRange<int>(0, 5) == 0;
  if (b.kinematic) {
    b.mass = 0;
    b.inertia.setZero();
  }
  const Transform pose = fuzz::pose(in, 2);
  b.position = pose.translation;
  b.orientation = pose.rotation;
  if (!fixed) {
    b.velocity = fuzz::point(in, in.ConsumeBool() ? Real(1) : Real(1000));
    b.angular_velocity = fuzz::point(in, in.ConsumeBool() ? Real(1) : Real(100));
  }
  b.fast = in.ConsumeBool();
  return b;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  auto scene = std::make_shared<Scene>();
  scene->source = "fuzz";
  WorldSettings& w = scene->world;
  w.dt = setting(in, Real(1) / 60, Real(1e-4), Real(0.1));
  w.gravity = Vec3(0, 0, -setting(in, Real(9.81), 0, 100));
  w.substeps = in.ConsumeIntegralInRange<int>(1, 8);
  w.max_substeps = in.ConsumeBool() ? 64 : in.ConsumeIntegralInRange<int>(w.substeps, 128);
  w.solver = in.ConsumeIntegralInRange<int>(0, 3) == 0 ? SolverType::penalty : SolverType::impulse;
  w.iterations = in.ConsumeIntegralInRange<int>(1, 4);
  w.relax_iterations = in.ConsumeIntegralInRange<int>(0, 4);
  w.broadphase = static_cast<BroadPhaseType>(in.ConsumeIntegralInRange<int>(0, 9));
  w.ccd = static_cast<CcdMode>(in.ConsumeIntegralInRange<int>(0, 2));
  w.contact_recycling = in.ConsumeBool();
  w.contact_margin = setting(in, Real(0.005), 0, 1);
  w.penetration_slop = setting(in, Real(1e-4), 0, Real(0.1));
  if (in.ConsumeBool())
    w.contact_hertz = setting(in, 30, Real(0.1), 1000);
  w.contact_damping_ratio = setting(in, 10, 0, 100);
  w.restitution_threshold = setting(in, Real(0.2), 0, 10);
  w.sleeping = in.ConsumeBool();
  w.threads = 1;
  Material m;
  m.friction = setting(in, Real(0.5), 0, 2);
  m.restitution = setting(in, 0, 0, 1);
  m.stiffness = setting(in, 1e6, 1, 1e9);
  m.damping = setting(in, 1e3, 0, 1e6);
  scene->materials.push_back(m);
  std::unique_ptr<World> world;
  try {
    const int bodies = in.ConsumeIntegralInRange<int>(1, 6);
    for (int i = 0; i < bodies; ++i)
      scene->bodies.push_back(body(in, i));
    world = std::make_unique<World>(compile(scene));
  } catch (const Error&) {
    return 0;  // refused, naming the body or field (dynamic_body, check_scene)
  }
  const int steps = in.ConsumeIntegralInRange<int>(1, 20);
  try {
    for (int s = 0; s < steps; ++s) {
      world->step();
      for (const BodyId id : world->bodies()) {
        const BodyState state = world->body_state(id);
        if (!state.position.allFinite() || !state.velocity.allFinite() ||
            !state.angular_velocity.allFinite() || !state.orientation.coeffs().allFinite()) {
          std::fprintf(stderr, "short scene: body %s not finite after step %d\n",
                       world->name(id).c_str(), s);
          std::abort();
        }
      }
    }
  } catch (const Error&) {
    // a clean stop with a message (NonFiniteStateError names the body and the step)
  }
  return 0;
}
