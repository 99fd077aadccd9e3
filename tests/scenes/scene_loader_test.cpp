// Valid scenes load into the Scene values they describe: every field arrives, defaults are the
// documented ones, mass and inertia follow from density by closed forms computed here
// independently of collision/shapes/shape.cpp, orientations come out exactly unit, and materials
// keep file order behind `default`.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "collision/shapes/convex_hull.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble {
namespace {

constexpr Real kPi = std::numbers::pi_v<Real>;
const std::filesystem::path kSourceDir = TUMBLE_SOURCE_DIR;

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Relative comparison for derived quantities (mass, inertia) that go through a few roundings.
void expect_close(Real actual, Real expected, const char* what) {
  EXPECT_NEAR(actual, expected, 1e-12 * std::abs(expected)) << what;
}

void expect_vec(const Vec3& v, Real x, Real y, Real z) {
  EXPECT_DOUBLE_EQ(v.x(), x);
  EXPECT_DOUBLE_EQ(v.y(), y);
  EXPECT_DOUBLE_EQ(v.z(), z);
}

void expect_diagonal(const Mat3& m, Real xx, Real yy, Real zz) {
  expect_close(m(0, 0), xx, "Ixx");
  expect_close(m(1, 1), yy, "Iyy");
  expect_close(m(2, 2), zz, "Izz");
  EXPECT_EQ(m(0, 1), 0);
  EXPECT_EQ(m(0, 2), 0);
  EXPECT_EQ(m(1, 2), 0);
  EXPECT_EQ(m(1, 0), 0);
  EXPECT_EQ(m(2, 0), 0);
  EXPECT_EQ(m(2, 1), 0);
}

Scene load(const std::string& yaml) {
  return load_scene_string(yaml, "test.yaml");
}

TEST(SceneLoader, EveryFieldArrives) {
  const Scene s = load_scene_file(kSourceDir / "tests/data/scenes/every_field.yaml");
  EXPECT_EQ(s.source, (kSourceDir / "tests/data/scenes/every_field.yaml").string());

  const WorldSettings& w = s.world;
  expect_vec(w.gravity, 0.5, -1, -9.5);
  EXPECT_DOUBLE_EQ(w.dt, 0.005);
  ASSERT_TRUE(w.steps.has_value());
  EXPECT_EQ(*w.steps, 240);
  EXPECT_DOUBLE_EQ(w.duration, 240 * 0.005);  // reported as steps * dt
  EXPECT_EQ(w.substeps, 8);
  EXPECT_EQ(w.solver, SolverType::impulse);
  EXPECT_EQ(w.iterations, 25);
  EXPECT_EQ(w.relax_iterations, 3);
  EXPECT_EQ(w.broadphase, BroadPhaseType::brute);
  EXPECT_EQ(w.ccd, CcdMode::on);
  EXPECT_FALSE(w.contact_recycling);
  EXPECT_DOUBLE_EQ(w.contact_margin, 0.01);
  EXPECT_DOUBLE_EQ(w.penetration_slop, 0.001);
  ASSERT_TRUE(w.contact_hertz.has_value());
  EXPECT_DOUBLE_EQ(*w.contact_hertz, 60);
  EXPECT_EQ(w.max_substeps, 16);
  EXPECT_DOUBLE_EQ(w.sag_tolerance, 0.01);
  EXPECT_DOUBLE_EQ(w.contact_damping_ratio, 2);
  EXPECT_DOUBLE_EQ(w.max_push_velocity, 1.5);
  EXPECT_DOUBLE_EQ(w.restitution_threshold, 0.75);

  // `default` is overridden in place at index 0; the others keep file order.
  ASSERT_EQ(s.materials.size(), 3u);
  EXPECT_EQ(s.materials[0].name, "default");
  EXPECT_DOUBLE_EQ(s.materials[0].friction, 0.7);
  EXPECT_DOUBLE_EQ(s.materials[0].restitution, 0.25);
  EXPECT_EQ(s.materials[1].name, "ice");
  EXPECT_DOUBLE_EQ(s.materials[1].friction, 0.05);
  EXPECT_DOUBLE_EQ(s.materials[1].restitution, 0.1);
  EXPECT_EQ(s.materials[2].name, "rubber");
  EXPECT_DOUBLE_EQ(s.materials[2].friction, 1.2);
  EXPECT_DOUBLE_EQ(s.materials[2].restitution, 0.9);

  ASSERT_EQ(s.bodies.size(), 5u);
  const BodyDesc& ball = s.bodies[0];
  EXPECT_EQ(ball.name, "ball");
  EXPECT_EQ(ball.shape.type, ShapeType::sphere);
  EXPECT_DOUBLE_EQ(ball.shape.radius, 0.5);
  expect_vec(ball.position, 1, 2, 3);
  EXPECT_DOUBLE_EQ(ball.orientation.w(), 0.5);
  EXPECT_DOUBLE_EQ(ball.orientation.x(), 0.5);
  EXPECT_DOUBLE_EQ(ball.orientation.y(), 0.5);
  EXPECT_DOUBLE_EQ(ball.orientation.z(), 0.5);
  expect_vec(ball.velocity, 0.1, -0.2, 0.3);
  expect_vec(ball.angular_velocity, -1, 2, -3);
  EXPECT_DOUBLE_EQ(ball.mass, 2.5);
  // Solid sphere: 2/5 m r^2 about every axis.
  const Real i_ball = 0.4 * 2.5 * 0.25;
  expect_diagonal(ball.inertia, i_ball, i_ball, i_ball);
  EXPECT_EQ(ball.material, 2);
  EXPECT_FALSE(ball.is_static);
  EXPECT_TRUE(ball.fast);

  // Box of full size 1 x 2 x 3 m at 200 kg/m^3: m = 1200 kg, I_xx = m (b^2 + c^2) / 12.
  const BodyDesc& crate = s.bodies[1];
  EXPECT_EQ(crate.shape.type, ShapeType::box);
  expect_vec(crate.shape.half_extents, 0.5, 1, 1.5);
  expect_close(crate.mass, 1200, "crate mass");
  expect_diagonal(crate.inertia, 1200.0 * (4 + 9) / 12, 1200.0 * (1 + 9) / 12,
                  1200.0 * (1 + 4) / 12);
  EXPECT_EQ(crate.material, 1);
  EXPECT_FALSE(crate.fast);
  EXPECT_TRUE(crate.orientation.coeffs().isApprox(Quat::Identity().coeffs()));

  // Capsule at the default density: a cylinder of height h = 2a plus two hemispheres. Each
  // hemisphere (mass m_h) has 2/5 m_h r^2 about the axis and, moved by the parallel-axis theorem
  // from its centroid 3r/8 beyond the cylinder's end, m_h (2r^2/5 + h^2/4 + 3hr/8) across it.
  const BodyDesc& pill = s.bodies[2];
  EXPECT_EQ(pill.name, "pill");
  EXPECT_EQ(pill.shape.type, ShapeType::capsule);
  const Real r = 0.25;
  const Real h = 1.5;
  const Real m_cyl = 1000 * kPi * r * r * h;
  const Real m_hemi = 1000 * 2.0 / 3.0 * kPi * r * r * r;
  expect_close(pill.mass, m_cyl + 2 * m_hemi, "capsule mass");
  const Real axial = m_cyl * r * r / 2 + 2 * m_hemi * 0.4 * r * r;
  const Real transverse =
      m_cyl * (r * r / 4 + h * h / 12) + 2 * m_hemi * (0.4 * r * r + h * h / 4 + 3 * h * r / 8);
  expect_diagonal(pill.inertia, transverse, transverse, axial);
  // Typed with 7 digits (norm 1 + 2e-8): accepted, then normalised exactly.
  EXPECT_NEAR(pill.orientation.norm(), 1, 1e-15);
  EXPECT_NEAR(pill.orientation.w(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(pill.orientation.y(), std::sqrt(0.5), 1e-15);
  EXPECT_EQ(pill.orientation.x(), 0);
  EXPECT_EQ(pill.orientation.z(), 0);
  EXPECT_EQ(pill.material, 0);

  // Explicit principal moments replace the shape's inertia; the mass stays as given.
  const BodyDesc& odd = s.bodies[3];
  EXPECT_DOUBLE_EQ(odd.mass, 3);
  expect_diagonal(odd.inertia, 1, 2, 2.5);
  EXPECT_EQ(odd.material, 0);

  const BodyDesc& floor = s.bodies[4];
  EXPECT_EQ(floor.name, "body4");  // default name body<i>
  EXPECT_EQ(floor.shape.type, ShapeType::plane);
  EXPECT_TRUE(floor.is_static);
  EXPECT_EQ(floor.mass, 0);
  EXPECT_TRUE(floor.inertia.isZero(0));

  ASSERT_TRUE(s.camera.has_value());
  expect_vec(s.camera->position, 10, -10, 5);
  expect_vec(s.camera->target, 0, 0, 2);
  EXPECT_DOUBLE_EQ(s.camera->fov, 60);
}

TEST(SceneLoader, MinimalSceneGetsTheDocumentedDefaults) {
  const Scene s = load("bodies:\n  - shape: {type: sphere, radius: 0.5}\n");
  EXPECT_EQ(s.source, "test.yaml");
  // The literals are the defaults docs/scene-format.md states; a change to WorldSettings must
  // change the documentation too.
  const WorldSettings& w = s.world;
  expect_vec(w.gravity, 0, 0, -9.81);
  EXPECT_DOUBLE_EQ(w.dt, 1.0 / 60);
  EXPECT_DOUBLE_EQ(w.duration, 5);
  EXPECT_FALSE(w.steps.has_value());
  EXPECT_EQ(w.substeps, 4);
  EXPECT_EQ(w.solver, SolverType::impulse);
  EXPECT_EQ(w.iterations, 1);
  EXPECT_EQ(w.relax_iterations, 1);
  EXPECT_EQ(w.broadphase, BroadPhaseType::automatic);
  EXPECT_EQ(w.ccd, CcdMode::automatic);
  EXPECT_TRUE(w.contact_recycling);
  EXPECT_DOUBLE_EQ(w.contact_margin, 0.005);
  EXPECT_DOUBLE_EQ(w.penetration_slop, 0.0001);
  EXPECT_FALSE(w.contact_hertz.has_value()) << "auto: set from the substep rate";
  EXPECT_EQ(w.max_substeps, 64);
  EXPECT_DOUBLE_EQ(w.sag_tolerance, 0.002);
  EXPECT_DOUBLE_EQ(w.contact_damping_ratio, 10);
  EXPECT_DOUBLE_EQ(w.max_push_velocity, 3);
  EXPECT_DOUBLE_EQ(w.restitution_threshold, 0.2);
  EXPECT_FALSE(w.sleeping);
  EXPECT_DOUBLE_EQ(w.sleep_speed, 0.05);
  EXPECT_DOUBLE_EQ(w.sleep_time, 0.5);
  EXPECT_EQ(w.threads, 0) << "auto: the machine's cores";

  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].name, "default");
  EXPECT_DOUBLE_EQ(s.materials[0].friction, 0.5);
  EXPECT_DOUBLE_EQ(s.materials[0].restitution, 0);
  EXPECT_DOUBLE_EQ(s.materials[0].stiffness, 1e6);
  EXPECT_DOUBLE_EQ(s.materials[0].damping, 1e3);

  ASSERT_EQ(s.bodies.size(), 1u);
  const BodyDesc& b = s.bodies[0];
  EXPECT_EQ(b.name, "body0");
  expect_vec(b.position, 0, 0, 0);
  EXPECT_EQ(b.orientation.w(), 1);
  EXPECT_TRUE(b.orientation.vec().isZero(0));
  EXPECT_TRUE(b.velocity.isZero(0));
  EXPECT_TRUE(b.angular_velocity.isZero(0));
  EXPECT_FALSE(b.is_static);
  EXPECT_FALSE(b.fast);
  EXPECT_EQ(b.material, 0);
  // Default density 1000 kg/m^3.
  const Real m = 1000 * 4.0 / 3.0 * kPi * 0.125;
  expect_close(b.mass, m, "sphere mass");
  expect_diagonal(b.inertia, 0.4 * m * 0.25, 0.4 * m * 0.25, 0.4 * m * 0.25);

  EXPECT_FALSE(s.camera.has_value());
}

TEST(SceneLoader, EmptySectionsMeanDefaults) {
  const Scene s = load(
      "world:\nmaterials:\ncamera:\nbodies:\n  - shape: {type: box, half_extents: [1, 1, 1]}\n");
  EXPECT_DOUBLE_EQ(s.world.dt, 1.0 / 60);
  ASSERT_EQ(s.materials.size(), 1u);
  ASSERT_TRUE(s.camera.has_value());
  expect_vec(s.camera->position, 6, -6, 4);
  expect_vec(s.camera->target, 0, 0, 1);
  EXPECT_DOUBLE_EQ(s.camera->fov, 45);
  // A 2 m cube of water.
  expect_close(s.bodies[0].mass, 8000, "cube mass");
  expect_diagonal(s.bodies[0].inertia, 8000 * 8.0 / 12, 8000 * 8.0 / 12, 8000 * 8.0 / 12);
}

TEST(SceneLoader, DensityGivesMassAndInertiaByClosedForm) {
  const Scene s = load(R"(
bodies:
  - shape: {type: sphere, radius: 0.3}
    density: 7800
  - shape: {type: box, half_extents: [0.1, 0.2, 0.4]}
    density: 2.5
  - shape: {type: capsule, radius: 0.1, half_length: 0}
    density: 10
)");
  const Real m_sphere = 7800 * 4.0 / 3.0 * kPi * 0.027;
  expect_close(s.bodies[0].mass, m_sphere, "steel ball");
  const Real i_sphere = 0.4 * m_sphere * 0.09;
  expect_diagonal(s.bodies[0].inertia, i_sphere, i_sphere, i_sphere);

  const Real m_box = 2.5 * 0.2 * 0.4 * 0.8;
  expect_close(s.bodies[1].mass, m_box, "box");
  expect_diagonal(s.bodies[1].inertia, m_box * (0.16 + 0.64) / 12, m_box * (0.04 + 0.64) / 12,
                  m_box * (0.04 + 0.16) / 12);

  // A capsule with no core is a sphere.
  const Real m_capsule = 10 * 4.0 / 3.0 * kPi * 0.001;
  expect_close(s.bodies[2].mass, m_capsule, "core-less capsule");
  const Real i_capsule = 0.4 * m_capsule * 0.01;
  expect_diagonal(s.bodies[2].inertia, i_capsule, i_capsule, i_capsule);
}

TEST(SceneLoader, CylinderAndHullGetMassAndInertiaByClosedForm) {
  // A hull given as the corners of a box [0, 2] x [0, 1] x [0, 1]: the box's mass properties,
  // and the body moved to the box's centre (the hull is re-centred on its centre of mass).
  const Scene s = load(R"(
bodies:
  - shape: {type: cylinder, radius: 0.2, half_length: 0.5}
    density: 100
  - shape:
      type: hull
      points: [[0, 0, 0], [2, 0, 0], [0, 1, 0], [2, 1, 0], [0, 0, 1], [2, 0, 1], [0, 1, 1], [2, 1, 1]]
    position: [10, 0, 0]
    orientation: [0.7071067811865476, 0, 0, 0.7071067811865476]
    density: 3
)");
  const Real m_cylinder = 100 * kPi * 0.04 * 1.0;
  expect_close(s.bodies[0].mass, m_cylinder, "cylinder");
  expect_diagonal(s.bodies[0].inertia, m_cylinder * (3 * 0.04 + 1.0) / 12,
                  m_cylinder * (3 * 0.04 + 1.0) / 12, m_cylinder * 0.04 / 2);
  const Real m_hull = 3 * 2.0;
  expect_close(s.bodies[1].mass, m_hull, "hull");
  // Computed by the divergence theorem from tetrahedra: off-diagonal terms cancel to rounding.
  const Mat3 expected =
      Vec3(m_hull * (1 + 1) / 12, m_hull * (4 + 1) / 12, m_hull * (4 + 1) / 12).asDiagonal();
  EXPECT_LT((s.bodies[1].inertia - expected).norm(), 1e-12);
  // The centre (1, 0.5, 0.5) in the body frame, turned 90 degrees about z: (-0.5, 1, 0.5).
  EXPECT_NEAR((s.bodies[1].position - Vec3(9.5, 1, 0.5)).norm(), 0, 1e-12);
}

TEST(SceneLoader, HullFromAnObjFileNextToTheScene) {
  const Scene s = load_scene_file(kSourceDir / "tests/data/scenes/hull_from_obj.yaml");
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(s.bodies[0].shape.type, ShapeType::hull);
  EXPECT_EQ(s.bodies[0].shape.hull->vertices().size(), 8u);
  expect_close(s.bodies[0].mass, 2000, "OBJ hull");
  EXPECT_NEAR((s.bodies[0].position - Vec3(1, 0.5, 1.5)).norm(), 0, 1e-12);
}

TEST(SceneLoader, OrientationIsNormalisedExactlyWithinTolerance) {
  // Off by 9e-7: inside the 1e-6 tolerance.
  const Scene s = load(R"(
bodies:
  - shape: {type: sphere, radius: 1}
    orientation: [1.0000009, 0, 0, 0]
  - shape: {type: sphere, radius: 1}
    orientation: [0.5, 0.5, 0.5, 0.5000001]
)");
  EXPECT_EQ(s.bodies[0].orientation.w(), 1);
  EXPECT_NEAR(s.bodies[1].orientation.norm(), 1, 1e-15);
  EXPECT_LT(s.bodies[1].orientation.w(), 0.5);  // scaled down, not left as typed
  // Off by 1.1e-6: outside.
  EXPECT_THROW(load("bodies:\n  - shape: {type: sphere, radius: 1}\n"
                    "    orientation: [1.0000011, 0, 0, 0]\n"),
               SceneError);
  EXPECT_THROW(load("bodies:\n  - shape: {type: sphere, radius: 1}\n"
                    "    orientation: [0, 0, 0, 0]\n"),
               SceneError);
}

TEST(SceneLoader, MaterialsKeepFileOrderBehindDefault) {
  const Scene s = load(R"(
materials:
  zinc: {friction: 0.1}
  alpha: {restitution: 0.5}
  mid: {}
bodies:
  - {name: a, shape: {type: sphere, radius: 1}, material: mid}
  - {name: b, shape: {type: sphere, radius: 1}, material: zinc}
  - {name: c, shape: {type: sphere, radius: 1}, material: alpha}
  - {name: d, shape: {type: sphere, radius: 1}, material: default}
)");
  ASSERT_EQ(s.materials.size(), 4u);
  EXPECT_EQ(s.materials[0].name, "default");
  EXPECT_EQ(s.materials[1].name, "zinc");
  EXPECT_EQ(s.materials[2].name, "alpha");
  EXPECT_EQ(s.materials[3].name, "mid");
  // Unset fields take the built-in defaults, not those of `default`.
  EXPECT_DOUBLE_EQ(s.materials[1].restitution, 0);
  EXPECT_DOUBLE_EQ(s.materials[2].friction, 0.5);
  EXPECT_DOUBLE_EQ(s.materials[3].friction, 0.5);
  EXPECT_EQ(s.bodies[0].material, 3);
  EXPECT_EQ(s.bodies[1].material, 1);
  EXPECT_EQ(s.bodies[2].material, 2);
  EXPECT_EQ(s.bodies[3].material, 0);
  EXPECT_EQ(s.find_material("alpha"), 2);
  EXPECT_EQ(s.find_body("c"), 2);
}

TEST(SceneLoader, DurationWithoutStepsLeavesStepsUnset) {
  const Scene s = load(
      "world: {dt: 0.01, duration: 2.5}\nbodies: [{shape: {type: plane}, "
      "static: true}]\n");
  EXPECT_DOUBLE_EQ(s.world.duration, 2.5);
  EXPECT_FALSE(s.world.steps.has_value());
}

TEST(SceneLoader, IntegersMayBeWrittenInExponentForm) {
  const Scene s = load(
      "world: {steps: 1e6, iterations: 2.0e1, substeps: +3}\n"
      "bodies: [{shape: {type: sphere, radius: 1}}]\n");
  EXPECT_EQ(*s.world.steps, 1000000);
  EXPECT_EQ(s.world.iterations, 20);
  EXPECT_EQ(s.world.substeps, 3);
}

TEST(SceneLoader, AcceptsEveryDecimalSpelling) {
  const char* spellings[] = {"2",     "+2",    "2.",   "2.0",      "2.000",
                             "20e-1", "0.2E1", ".2e1", "!!float 2"};
  for (const char* text : spellings) {
    const std::string yaml =
        std::string("bodies: [{shape: {type: sphere, radius: ") + text + "}}]\n";
    try {
      EXPECT_DOUBLE_EQ(load(yaml).bodies[0].shape.radius, 2) << text;
    } catch (const SceneError& e) {
      ADD_FAILURE() << text << ": " << e.what();
    }
  }
}

TEST(SceneLoader, BooleansAndModes) {
  const Scene s = load(R"(
world: {ccd: off, broadphase: auto}
bodies:
  - {shape: {type: sphere, radius: 1}, fast: True}
  - {shape: {type: sphere, radius: 1}, fast: FALSE, static: false}
  - {shape: {type: plane}, static: TRUE, velocity: [0, 0, 0], angular_velocity: [0, -0, 0]}
)");
  EXPECT_EQ(s.world.ccd, CcdMode::off);
  EXPECT_EQ(s.world.broadphase, BroadPhaseType::automatic);
  EXPECT_TRUE(s.bodies[0].fast);
  EXPECT_FALSE(s.bodies[1].fast);
  EXPECT_TRUE(s.bodies[2].is_static);
}

TEST(SceneLoader, AnchorsAndAliasesWork) {
  const Scene s = load(R"(
bodies:
  - name: a
    shape: &unit {type: box, half_extents: [0.5, 0.5, 0.5]}
    position: &up [0, 0, 1]
  - name: b
    shape: *unit
    position: *up
)");
  ASSERT_EQ(s.bodies.size(), 2u);
  EXPECT_EQ(s.bodies[1].shape.type, ShapeType::box);
  expect_vec(s.bodies[1].position, 0, 0, 1);
}

TEST(SceneLoader, ManyBodiesGetUniqueDefaultNames) {
  std::string yaml = "bodies:\n";
  for (int i = 0; i < 5000; ++i) {
    yaml +=
        "  - {shape: {type: sphere, radius: 0.5}, position: [" + std::to_string(i) + ", 0, 1]}\n";
  }
  const Scene s = load(yaml);
  ASSERT_EQ(s.bodies.size(), 5000u);
  EXPECT_EQ(s.bodies[4999].name, "body4999");
  EXPECT_DOUBLE_EQ(s.bodies[4999].position.x(), 4999);
}

TEST(SceneLoader, FileAndStringGiveTheSameScene) {
  const auto path = kSourceDir / "tests/data/scenes/every_field.yaml";
  const Scene a = load_scene_file(path);
  const Scene b = load_scene_string(read_text(path), path.string());
  ASSERT_EQ(a.bodies.size(), b.bodies.size());
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    EXPECT_EQ(a.bodies[i].name, b.bodies[i].name);
    EXPECT_EQ(a.bodies[i].mass, b.bodies[i].mass);
    EXPECT_EQ(a.bodies[i].inertia, b.bodies[i].inertia);
    EXPECT_EQ(a.bodies[i].orientation.coeffs(), b.bodies[i].orientation.coeffs());
  }
  EXPECT_EQ(a.source, b.source);
}

// The complete example in docs/scene-format.md is the first ```yaml block after its heading; it
// must load, so the documentation cannot drift from the loader.
TEST(SceneFormatDoc, CompleteExampleLoads) {
  const std::string doc = read_text(kSourceDir / "docs/scene-format.md");
  const auto heading = doc.find("## Complete example");
  ASSERT_NE(heading, std::string::npos) << "docs/scene-format.md lost its complete example";
  const auto start = doc.find("```yaml\n", heading);
  ASSERT_NE(start, std::string::npos);
  const auto body = start + 8;
  const auto end = doc.find("```", body);
  ASSERT_NE(end, std::string::npos);
  try {
    const Scene s = load_scene_string(doc.substr(body, end - body), "scene-format.md example");
    EXPECT_GE(s.bodies.size(), 4u);
    EXPECT_TRUE(s.camera.has_value());
  } catch (const SceneError& e) {
    FAIL() << e.what();
  }
}

// Every field the loader accepts is documented (as `name`), so the reference stays complete.
TEST(SceneFormatDoc, DocumentsEveryField) {
  const std::string doc = read_text(kSourceDir / "docs/scene-format.md");
  const char* fields[] = {"world",
                          "materials",
                          "bodies",
                          "camera",
                          "gravity",
                          "dt",
                          "duration",
                          "steps",
                          "substeps",
                          "max_substeps",
                          "solver",
                          "iterations",
                          "relax_iterations",
                          "broadphase",
                          "ccd",
                          "contact_recycling",
                          "contact_margin",
                          "penetration_slop",
                          "contact_hertz",
                          "sag_tolerance",
                          "contact_damping_ratio",
                          "max_push_velocity",
                          "restitution_threshold",
                          "sleeping",
                          "sleep_speed",
                          "sleep_time",
                          "threads",
                          "friction",
                          "restitution",
                          "stiffness",
                          "damping",
                          "name",
                          "shape",
                          "position",
                          "orientation",
                          "velocity",
                          "angular_velocity",
                          "mass",
                          "density",
                          "inertia",
                          "material",
                          "static",
                          "fast",
                          "type",
                          "radius",
                          "half_extents",
                          "half_length",
                          "sphere",
                          "box",
                          "capsule",
                          "plane",
                          "target",
                          "fov",
                          "impulse",
                          "auto",
                          "brute",
                          "on",
                          "off"};
  for (const char* f : fields) {
    EXPECT_NE(doc.find(std::string("`") + f + "`"), std::string::npos) << f;
  }
}

// The scene library under scenes/ is read by the CLI, the renderer and the physics tests; every
// file in it must pass the validator.
TEST(SceneLibrary, EverySceneLoads) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kSourceDir / "scenes")) {
    if (entry.path().extension() != ".yaml")
      continue;
    ++count;
    try {
      load_scene_file(entry.path());
    } catch (const SceneError& e) {
      ADD_FAILURE() << e.what();
    }
  }
  EXPECT_GT(count, 0);
}

}  // namespace
}  // namespace tumble
