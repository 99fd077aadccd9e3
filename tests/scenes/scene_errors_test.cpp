// Every malformed scene under tests/data/malformed is rejected with one SceneError that names
// the file, the line, the full field path and what was expected. The table below is the
// specification: one row per file, and a test that fails when a file has no row (or a row no
// file), so that no fixture goes unchecked.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <ostream>
#include <set>
#include <string>
#include <string_view>

#include "scenes/scene_loader.hpp"
#include "tumble/error.hpp"
#include "tumble/model.hpp"

namespace tumble {
namespace {

const std::filesystem::path kMalformedDir =
    std::filesystem::path(TUMBLE_SOURCE_DIR) / "tests/data/malformed";

struct Malformed {
  const char* file;
  int line;            // 1-based; 0 for errors with no position (a file that cannot be opened)
  const char* field;   // exact SceneError::field; "" for errors that are not about one field
  const char* phrase;  // a key phrase the message must contain
};

// "does_not_exist.yaml" is deliberately absent from the directory.
constexpr Malformed kCases[] = {
    {"does_not_exist.yaml", 0, "", "cannot open scene file (No such file or directory)"},
    {"syntax_unclosed_list.yaml", 6, "", "YAML syntax error: end of sequence flow not found"},
    {"syntax_bad_indentation.yaml", 4, "", "YAML syntax error"},
    {"root_is_list.yaml", 2, "", "expected a map with the fields world, materials, bodies"},
    {"empty_file.yaml", 1, "bodies", "missing required field 'bodies'"},
    {"two_documents.yaml", 4, "", "more than one YAML document"},
    {"syntax_stray_comma.yaml", 2, "", "YAML syntax error: unexpected ','"},
    {"missing_bodies.yaml", 2, "bodies", "missing required field 'bodies'"},
    {"empty_bodies.yaml", 4, "bodies", "expected a non-empty list of bodies, got an empty list"},
    {"bodies_is_map.yaml", 3, "bodies", "expected a non-empty list of bodies, got a map"},
    {"unknown_top_level_field.yaml", 4, "cameras",
     "unknown field 'cameras' at the top level; expected one of: world, materials, bodies, "
     "camera, randomize (did you mean 'camera'?)"},
    {"compound_alias_of_itself.yaml", 4, "bodies[0].shape.parts[0].shape",
     "a compound part must be a sphere, box, capsule, cylinder or hull, got compound"},
    {"nested_too_deep.yaml", 3, "", "YAML nested deeper than"},
    {"randomize_low_above_high.yaml", 5, "randomize.friction",
     "expected [low, high] with low <= high, got [0.9, 0.1]"},
    {"randomize_unknown_field.yaml", 6, "randomize.frction",
     "unknown field 'frction' in randomize"},
    {"randomize_gravity_without_high.yaml", 6, "randomize.gravity", "missing field 'high'"},
    {"randomize_size_noise_too_large.yaml", 5, "randomize.size_noise",
     "expected a relative standard deviation (0 to 0.2), got 0.5"},
    {"unknown_world_field.yaml", 4, "world.gravty", "unknown field 'gravty' in world"},
    {"unknown_material_field.yaml", 3, "materials.rubber.bounciness",
     "unknown field 'bounciness' in materials.rubber; expected one of: friction, restitution"},
    {"unknown_body_field.yaml", 7, "bodies[1].colour", "unknown field 'colour' in bodies[1]"},
    {"unknown_shape_field.yaml", 6, "bodies[0].shape.radiuss",
     "unknown field 'radiuss' in bodies[0].shape; expected one of: type, radius"},
    {"unknown_camera_field.yaml", 6, "camera.zoom",
     "unknown field 'zoom' in camera; expected one of: position, target, fov"},
    {"negative_mass.yaml", 5, "bodies[0].mass", "expected a positive mass in kilograms"},
    {"zero_size_box.yaml", 4, "bodies[0].shape.half_extents[1]",
     "expected a positive number in metres (1e-9 to 1e9), got 0"},
    {"negative_radius.yaml", 8, "bodies[1].shape.radius",
     "expected a positive number in metres (1e-9 to 1e9), got -1"},
    {"huge_radius.yaml", 3, "bodies[0].shape.radius", "(1e-9 to 1e9), got 1e10"},
    {"nan_position.yaml", 5, "bodies[0].position[1]", "got .nan, which is not a finite number"},
    {"inf_gravity.yaml", 3, "world.gravity[2]", "got -.inf, which is not a finite number"},
    {"overflowing_number.yaml", 3, "world.duration", "too large or too small for a double"},
    {"missing_shape.yaml", 5, "bodies[1].shape", "missing required field 'shape'"},
    {"shape_without_type.yaml", 3, "bodies[0].shape.type", "missing required field 'type'"},
    {"sphere_without_radius.yaml", 5, "bodies[0].shape.radius", "missing required field 'radius'"},
    {"unknown_shape_type.yaml", 3, "bodies[0].shape.type",
     "expected one of: sphere, box, capsule, plane, cylinder, hull, mesh, compound, sdf, got cube"},
    {"mesh_dynamic.yaml", 4, "bodies[0].static", "a triangle mesh is a surface"},
    {"mesh_index_out_of_range.yaml", 10, "bodies[0].shape.triangles[1][2]",
     "vertex index 9 is out of range: the mesh has 4 vertices"},
    {"mesh_degenerate_triangle.yaml", 8, "bodies[0].shape.triangles", "triangle 1 has zero area"},
    {"mesh_nan_vertex.yaml", 7, "bodies[0].shape.vertices[2][0]", "which is not a finite number"},
    {"mesh_missing_obj.yaml", 5, "bodies[0].shape.file", "cannot open OBJ file"},
    {"compound_mesh_part.yaml", 8, "bodies[0].shape.parts[1].shape",
     "a compound part must be a sphere, box, capsule, cylinder or hull, got plane"},
    {"compound_empty_parts.yaml", 4, "bodies[0].shape.parts", "expected a list of 1 to 256 parts"},
    {"sdf_without_field.yaml", 4, "bodies[0].shape.sdf", "missing required field 'sdf'"},
    {"sdf_unbounded.yaml", 5, "bodies[0].shape.sdf", "an SDF shape must be a bounded solid"},
    {"sdf_without_mass.yaml", 5, "bodies[0].shape", "needs 'mass' or 'density'"},
    {"hull_flat.yaml", 4, "bodies[0].shape.points",
     "hull points are coplanar (a flat hull with no volume)"},
    {"hull_bad_point.yaml", 6, "bodies[0].shape.points[2]", "expected a list of 3 numbers"},
    {"hull_missing_obj.yaml", 4, "bodies[0].shape.file", "cannot open OBJ file"},
    {"cylinder_zero_height.yaml", 4, "bodies[0].shape.half_length", "a positive number"},
    {"non_unit_quaternion.yaml", 5, "bodies[0].orientation",
     "expected a unit quaternion [w, x, y, z] (norm within 1e-6 of 1), got norm 1.00498756"},
    {"steps_absurd.yaml", 4, "world.steps", "(1 to 1e9), got 1e12"},
    {"steps_not_integer.yaml", 3, "world.steps", "got 2.5, which is not an integer"},
    {"substeps_absurd.yaml", 3, "world.substeps", "(1 to 1000), got 100000"},
    {"zero_iterations.yaml", 3, "world.iterations", "(1 to 10000), got 0"},
    {"zero_contact_hertz.yaml", 3, "world.contact_hertz",
     "expected a frequency in Hz or auto (greater than 0, at most 1e6), got 0"},
    {"duration_and_steps.yaml", 4, "world.steps", "either duration or steps, not both"},
    {"too_many_implied_steps.yaml", 4, "world.duration", "at most 1e9 are allowed"},
    {"dt_too_large.yaml", 3, "world.dt", "(1e-9 to 1), got 2"},
    {"duplicate_body_names.yaml", 7, "bodies[2].name",
     "duplicate body name 'box', already used by bodies[0]"},
    {"default_name_taken.yaml", 5, "bodies[1].name",
     "the default name 'body1' is already used by bodies[0]"},
    {"body_name_with_comma.yaml", 3, "bodies[0].name", "without commas"},
    {"duplicate_key.yaml", 7, "bodies[0].shape.radius",
     "duplicate field 'radius' (first given on line 6)"},
    {"undefined_material.yaml", 7, "bodies[0].material",
     "undefined material 'rubber'; defined: default, ice"},
    {"restitution_above_one.yaml", 3, "materials.bouncy.restitution", "(0 to 1), got 1.5"},
    {"negative_friction.yaml", 3, "materials.default.friction", "got -0.1"},
    {"material_not_map.yaml", 3, "materials.rubber", "expected a map {friction, restitution}"},
    {"zero_stiffness.yaml", 3, "materials.soft.stiffness",
     "expected a contact stiffness in N/m (greater than 0, at most 1e12), got 0"},
    {"negative_damping.yaml", 3, "materials.soft.damping",
     "expected a contact damping in N s/m (0 to 1e12), got -10"},
    {"stiffness_absurd.yaml", 3, "materials.steel.stiffness",
     "(greater than 0, at most 1e12), got 1e15"},
    {"mass_and_density.yaml", 6, "bodies[0].density", "give either mass or density, not both"},
    {"plane_not_static.yaml", 4, "bodies[0].static", "a plane is infinite"},
    {"static_with_mass.yaml", 6, "bodies[0].mass", "static bodies have no mass"},
    {"static_with_velocity.yaml", 6, "bodies[0].velocity", "a static body never moves"},
    {"inertia_triangle.yaml", 6, "bodies[0].inertia", "triangle inequality"},
    {"inertia_implausible.yaml", 7, "bodies[0].inertia", "less than a hundredth"},
    {"inertia_impossible.yaml", 6, "bodies[0].inertia.override", "more than any mass of 1 kg"},
    {"bool_yes.yaml", 5, "bodies[0].static", "expected true or false, got yes"},
    {"sleeping_not_bool.yaml", 3, "world.sleeping", "expected true or false, got 1"},
    {"zero_sleep_speed.yaml", 4, "world.sleep_speed",
     "expected a speed in m/s (greater than 0, at most 1e6), got 0"},
    {"negative_sleep_time.yaml", 4, "world.sleep_time",
     "expected a duration in seconds (greater than 0, at most 1e9), got -1"},
    {"zero_threads.yaml", 3, "world.threads",
     "expected a whole number of threads, or auto (1 to 1024), got 0"},
    {"threads_word.yaml", 3, "world.threads", "expected a whole number of threads, or auto"},
    {"unknown_solver.yaml", 3, "world.solver", "expected one of: impulse, penalty, got pgs"},
    {"unknown_broadphase.yaml", 3, "world.broadphase",
     "expected one of: auto, brute, sap, hash, bvh, lbvh, octree, kdtree, grid, hgrid, got "
     "quadtree"},
    {"unknown_ccd_mode.yaml", 3, "world.ccd", "expected one of: auto, on, off"},
    {"string_for_number.yaml", 3, "world.dt", "expected a time step in seconds"},
    {"quoted_number.yaml", 5, "bodies[0].mass", "got the quoted string \"2.0\""},
    {"number_with_junk.yaml", 3, "bodies[0].shape.radius", "got 1.0abc"},
    {"list_wrong_length.yaml", 5, "bodies[0].position",
     "expected a list of 3 numbers [x, y, z] in metres, got a list of 2 items"},
    {"map_for_list.yaml", 5, "bodies[0].velocity", "expected a list of 3 numbers"},
    {"position_out_of_range.yaml", 5, "bodies[0].position[2]", "(-1e9 to 1e9), got -2e9"},
    {"capsule_negative_half_length.yaml", 4, "bodies[0].shape.half_length",
     "expected a non-negative number in metres"},
    {"fov_out_of_range.yaml", 4, "camera.fov", "(1 to 179), got 180"},
    {"camera_target_at_position.yaml", 6, "camera.target", "no view direction"},
};

// Names the row by its file in test output instead of a byte dump.
void PrintTo(const Malformed& c, std::ostream* os) {
  *os << c.file;
}

class MalformedScene : public testing::TestWithParam<Malformed> {};

TEST_P(MalformedScene, IsRejectedWithFileLineFieldAndReason) {
  const Malformed& c = GetParam();
  const std::filesystem::path path = kMalformedDir / c.file;
  const std::string source = path.string();
  try {
    load_scene_file(path);
    FAIL() << c.file << " loaded, but it should have been rejected";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    SCOPED_TRACE(what);
    EXPECT_EQ(e.file, source);
    EXPECT_EQ(e.line, c.line);
    EXPECT_EQ(e.field, c.field);
    EXPECT_NE(what.find(c.phrase), std::string::npos) << "missing phrase: " << c.phrase;
    EXPECT_NE(e.reason.find(c.phrase), std::string::npos);
    // FILE:LINE:COLUMN: field 'PATH': REASON, all on one line.
    std::string prefix = source;
    if (c.line > 0) {
      EXPECT_GT(e.column, 0);
      prefix += ":" + std::to_string(e.line) + ":" + std::to_string(e.column);
    } else {
      EXPECT_EQ(e.column, 0);
    }
    prefix += ": ";
    if (*c.field != '\0')
      prefix += "field '" + std::string(c.field) + "': ";
    EXPECT_EQ(what, prefix + e.reason);
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
}

std::string case_name(const testing::TestParamInfo<Malformed>& info) {
  std::string name = info.param.file;
  name = name.substr(0, name.find('.'));
  return name;
}

INSTANTIATE_TEST_SUITE_P(Files, MalformedScene, testing::ValuesIn(kCases), case_name);

TEST(MalformedScenes, EveryFileHasARowAndEveryRowAFile) {
  std::set<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(kMalformedDir)) {
    files.insert(entry.path().filename().string());
  }
  std::set<std::string> rows;
  for (const Malformed& c : kCases) {
    EXPECT_TRUE(rows.insert(c.file).second) << "two rows for " << c.file;
  }
  for (const std::string& f : files) {
    EXPECT_TRUE(rows.count(f)) << f << " has no row in kCases";
  }
  for (const std::string& r : rows) {
    if (r == "does_not_exist.yaml") {
      EXPECT_FALSE(files.count(r)) << "does_not_exist.yaml must not exist";
      continue;
    }
    EXPECT_TRUE(files.count(r)) << r << " is in kCases but not in " << kMalformedDir;
  }
  EXPECT_GE(files.size(), 25u);
}

SceneError error_of(const std::string& yaml) {
  try {
    load_scene_string(yaml, "inline.yaml");
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "loaded, but should have been rejected:\n" << yaml;
  return SceneError("", 0, 0, "", "");
}

TEST(SceneErrors, MessageFormatForAStringSource) {
  const SceneError e = error_of("bodies:\n  - shape: {type: sphere, radius: -1}\n");
  EXPECT_STREQ(e.what(),
               "inline.yaml:2:35: field 'bodies[0].shape.radius': expected a positive number in "
               "metres (1e-9 to 1e9), got -1");
  EXPECT_EQ(e.file, "inline.yaml");
  EXPECT_EQ(e.line, 2);
  EXPECT_EQ(e.column, 35);
}

// A camera target a hair from its position has no view direction: refused with the line, and by
// check_scene for a scene built in code.
TEST(SceneErrors, CameraTargetTooCloseToItsPosition) {
  const SceneError e = error_of(
      "camera:\n  position: [1, 2, 3]\n  target: [1, 2, 3.0000000000001]\nbodies:\n"
      "  - shape: {type: sphere, radius: 1}\n");
  EXPECT_EQ(e.field, "camera.target");
  EXPECT_EQ(e.line, 3);
  EXPECT_NE(e.reason.find("within 1e-6 m"), std::string::npos) << e.what();
  Scene scene = load_scene_string("bodies:\n  - shape: {type: sphere, radius: 1}\n", "code");
  scene.camera = Camera{};
  scene.camera->position = Vec3(0, 0, 0);
  scene.camera->target = Vec3(1e-300, 0, 0);
  try {
    check_scene(scene);
    FAIL() << "a camera 1e-300 m from its target was accepted";
  } catch (const SceneError& err) {
    EXPECT_EQ(err.field, "camera.target");
  }
}

TEST(SceneErrors, DirectoryCannotBeOpened) {
  try {
    load_scene_file(kMalformedDir);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), kMalformedDir.string() + ": cannot open scene file (" +
                                         std::make_error_code(std::errc::is_a_directory).message() +
                                         ")");
  }
}

// A FIFO would block the read for ever and /dev/zero never ends: neither is read at all.
TEST(SceneErrors, OnlyRegularFilesAreRead) {
  const std::filesystem::path fifo =
      std::filesystem::temp_directory_path() / ("tumble_scene_fifo_" + std::to_string(::getpid()));
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::filesystem::path& path : {fifo, std::filesystem::path("/dev/zero")}) {
    try {
      load_scene_file(path);
      ADD_FAILURE() << path << " was read";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
  }
  std::filesystem::remove(fifo);
}

// Every spelling here must be refused as a radius; all are things yaml-cpp's own as<double>
// accepts, or typos that a loose parser would read as a different number.
TEST(SceneErrors, NumbersAreParsedStrictly) {
  const char* bad[] = {"1.0abc", "1;5",   "0x10", "1_000",   "1e",    "e5",     ".",        "+-1",
                       "--1",    "nan",   ".NaN", ".inf",    "+.Inf", "-.INF",  "inf",      "1e999",
                       "1e-999", "\"1\"", "'1'",  "!!str 1", "[1]",   "{a: 1}", "",         "~",
                       "null",   "true",  "1 2",  "0b1",     "1e5.5", "0.5.",   "Infinity", "1/2"};
  for (const char* text : bad) {
    SCOPED_TRACE(text);
    const SceneError e =
        error_of(std::string("bodies:\n  - shape: {type: sphere, radius: ") + text + "}\n");
    EXPECT_EQ(e.field, "bodies[0].shape.radius");
    EXPECT_NE(e.reason.find("expected a positive number in metres"), std::string::npos);
  }
}

TEST(SceneErrors, OnlyCoreSchemaBooleans) {
  for (const char* text : {"yes", "no", "on", "off", "y", "n", "1", "0", "\"true\"", "[]"}) {
    SCOPED_TRACE(text);
    const SceneError e = error_of(
        std::string("bodies:\n  - shape: {type: sphere, radius: 1}\n    fast: ") + text + "\n");
    EXPECT_EQ(e.field, "bodies[0].fast");
    EXPECT_NE(e.reason.find("expected true or false"), std::string::npos);
  }
}

TEST(SceneErrors, MergeKeysAreExplained) {
  const SceneError e = error_of(R"(
bodies:
  - &ball {name: a, shape: {type: sphere, radius: 1}}
  - <<: *ball
    name: b
)");
  EXPECT_EQ(e.field, "bodies[1].<<");
  EXPECT_NE(e.reason.find("merge keys"), std::string::npos);
}

TEST(SceneErrors, ComputedMassOutOfRange) {
  // Each input is in range, but 1e6 kg/m^3 times a (2e6 m)^3 box is far beyond 1e15 kg.
  const SceneError e = error_of(
      "bodies:\n  - shape: {type: box, half_extents: [1e6, 1e6, 1e6]}\n    density: 1e6\n");
  EXPECT_EQ(e.field, "bodies[0].density");
  EXPECT_NE(e.reason.find("gives a mass of"), std::string::npos);
}

TEST(SceneErrors, LaterNameCollidingWithADefaultName) {
  const SceneError e = error_of(R"(
bodies:
  - shape: {type: sphere, radius: 1}
  - name: body0
    shape: {type: sphere, radius: 1}
)");
  EXPECT_EQ(e.field, "bodies[1].name");
  EXPECT_NE(e.reason.find("already used by bodies[0] (its default name)"), std::string::npos);
}

TEST(SceneErrors, ControlCharactersAreEscapedInMessages) {
  const SceneError e = error_of("bodies:\n  - shape: {type: sphere, radius: \"\\x01\\t\"}\n");
  EXPECT_EQ(std::string(e.what()).find('\t'), std::string::npos);
  EXPECT_NE(std::string(e.what()).find("\\x01\\x09"), std::string::npos);
}

// A lone ',' sends yaml-cpp 0.7's LoadAll into an endless, allocating loop (jbeder/yaml-cpp#1040);
// the loader must answer with a syntax error instead. The test would hang without the guard.
TEST(SceneErrors, StrayCommaIsASyntaxErrorNotAHang) {
  for (const char* text : {",", ",\n", "\n\n  ,", ", bodies: []"}) {
    SCOPED_TRACE(text);
    const SceneError e = error_of(text);
    EXPECT_NE(e.reason.find("YAML syntax error"), std::string::npos) << e.what();
  }
}

// An alias inside its own anchored node makes a cycle; the loader must not follow it forever.
TEST(SceneErrors, SelfReferenceAndUndefinedAliases) {
  const SceneError cycle = error_of("bodies: &b [*b]\n");
  EXPECT_EQ(cycle.field, "bodies[0]");
  EXPECT_NE(cycle.reason.find("expected a map describing a body, got a list of 1 item"),
            std::string::npos);
  const SceneError undefined = error_of("bodies: [*nothing]\n");
  EXPECT_EQ(undefined.line, 1);
  EXPECT_NE(undefined.reason.find("YAML syntax error"), std::string::npos);
}

// Keys come from the file and end up in the field path; they must not break the one-line message.
TEST(SceneErrors, KeysAreEscapedInFieldPaths) {
  const SceneError e =
      error_of("\"odd\\nkey\": 1\nbodies: [{shape: {type: plane}, static: true}]\n");
  EXPECT_EQ(e.field, "odd\\x0akey");
  EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
}

TEST(SceneErrors, NonScalarKeysAreRejected) {
  const SceneError e = error_of("? [a, b]\n: 1\nbodies: [{shape: {type: plane}, static: true}]\n");
  EXPECT_EQ(e.line, 1);
  EXPECT_NE(e.reason.find("expected a field name"), std::string::npos);
}

}  // namespace
}  // namespace tumble

namespace tumble {
namespace {

// inertia: {override: [...]} takes moments the shape of uniform density would not have (here
// the mass near the centre), and the C++ path refuses what no mass within the shape can have.
TEST(InertiaChecks, OverrideIsTakenAndTheImpossibleRefusedOnEveryPath) {
  const auto scene = load_scene_string(
      "bodies:\n"
      "  - name: pebble_in_a_box\n"
      "    shape: {type: box, half_extents: [0.5, 0.5, 0.5]}\n"
      "    mass: 1\n"
      "    inertia: {override: [1.0e-5, 1.0e-5, 1.0e-5]}\n",
      "override.yaml");
  EXPECT_EQ(scene.bodies[0].inertia, Mat3(Vec3::Constant(1e-5).asDiagonal()));
  Scene api = scene;
  api.bodies[0].inertia = Mat3(Vec3::Constant(0.8).asDiagonal());  // above m R^2 = 0.75
  EXPECT_THROW(check_scene(api), Error);
  api.bodies[0].inertia = Mat3(Vec3::Constant(0.74).asDiagonal());
  EXPECT_NO_THROW(check_scene(api));
}

}  // namespace
}  // namespace tumble
