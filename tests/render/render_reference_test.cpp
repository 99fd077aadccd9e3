// Fixed scenes rendered to PNG and compared with committed references (tests/data/render/), so
// that a change that breaks rendering fails; plus checks that do not depend on references
// (bodies appear where the camera model puts them, lit faces differ) and that the comparison
// itself can fail.
//
// Regenerate the references after an intended change of the picture:
//   TUMBLE_UPDATE_RENDER_REFERENCES=1 build-dev/tests/test_render --gtest_filter='RenderReference*'
// then look at every changed PNG before committing it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <memory>

#include "renders/camera_framing.hpp"
#include "renders/renderer.hpp"
#include "scenes/scene_loader.hpp"

namespace tumble::render {
namespace {

namespace fs = std::filesystem;

const fs::path kReferences = fs::path(TUMBLE_SOURCE_DIR) / "tests/data/render";

// Rendering is deterministic on one machine; the tolerance absorbs rounding differences between
// Mesa builds (a pixel's edge coverage, a shade off by a few levels), not moved geometry.
constexpr double kMaxMeanAbsolute = 1.0;  // of 255, over all channels
constexpr int kPixelThreshold = 40;       // a pixel "differs" beyond this in some channel
constexpr double kMaxFractionDifferent = 0.004;

bool matches(const ImageDifference& d) {
  return d.mean_absolute <= kMaxMeanAbsolute && d.fraction_different <= kMaxFractionDifferent;
}

// A floor, a sphere, a tilted box and a lying capsule, seen from a fixed camera.
constexpr const char* kShapes = R"(
world: {dt: 0.01, duration: 1}
bodies:
  - {name: floor, shape: {type: plane}, static: true}
  - {name: ball, shape: {type: sphere, radius: 0.5}, position: [-1.2, 0, 0.5]}
  - name: crate
    shape: {type: box, half_extents: [0.4, 0.3, 0.5]}
    position: [0.3, 0.4, 0.5]
    orientation: [0.9238795325112867, 0, 0, 0.3826834323650898]
  - name: pill
    shape: {type: capsule, radius: 0.25, half_length: 0.5}
    position: [0.6, -1.2, 0.25]
    orientation: [0.7071067811865476, 0, 0.7071067811865476, 0]
camera: {position: [4, -4, 2.5], target: [0, 0, 0.4], fov: 45}
)";

// A box on the floor and a ball resting on the box, after a few steps, so the overlays have
// pairs and contacts to show.
constexpr const char* kContacts = R"(
world: {dt: 0.01, duration: 1}
bodies:
  - {name: floor, shape: {type: plane}, static: true}
  - {name: crate, shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [0, 0, 0.5]}
  - {name: ball, shape: {type: sphere, radius: 0.3}, position: [0.1, 0, 1.3]}
  - {name: far, shape: {type: sphere, radius: 0.2}, position: [1.5, 1.0, 1.5]}
camera: {position: [3, -3.5, 2.2], target: [0, 0, 0.7], fov: 45}
)";

Image render_scene(const char* yaml, int steps, RenderSettings settings) {
  auto scene = std::make_shared<Scene>(load_scene_string(yaml, "test"));
  Simulation world(scene);
  for (int i = 0; i < steps; ++i)
    world.step();
  settings.width = 320;
  settings.height = 240;
  Renderer renderer(*scene, settings);
  Image image;
  renderer.render(world, image);
  return image;
}

// Compares with the named reference, or rewrites it when TUMBLE_UPDATE_RENDER_REFERENCES is set.
// On a mismatch the actual image is kept beside the test's temporary files for inspection.
void expect_matches_reference(const Image& actual, const std::string& name) {
  const fs::path reference = kReferences / (name + ".png");
  if (std::getenv("TUMBLE_UPDATE_RENDER_REFERENCES") != nullptr) {
    fs::create_directories(kReferences);
    write_png(reference, actual);
    GTEST_SKIP() << "rewrote " << reference;
  }
  ASSERT_TRUE(fs::exists(reference)) << reference << " is missing; see this file's header";
  const ImageDifference d = compare_images(actual, read_png(reference), kPixelThreshold);
  if (!matches(d)) {
    const fs::path kept = fs::temp_directory_path() /
                          ("tumble_render_" + name + "_" + std::to_string(::getpid()) + ".png");
    write_png(kept, actual);
    ADD_FAILURE() << name << ": differs from " << reference << ": mean " << d.mean_absolute
                  << ", fraction " << d.fraction_different << ", max " << d.max_absolute
                  << "; actual image kept at " << kept;
  }
}

TEST(RenderReference, ShapesOnAFloor) {
  expect_matches_reference(render_scene(kShapes, 0, {}), "shapes");
}

TEST(RenderReference, ContactsAabbsAndPairs) {
  RenderSettings s;
  s.enable(Overlay::contacts);
  s.enable(Overlay::aabb);
  s.enable(Overlay::pairs);
  expect_matches_reference(render_scene(kContacts, 30, s), "contacts_aabb_pairs");
}

TEST(RenderReference, ColourByStage) {
  RenderSettings s;
  s.enable(Overlay::stage);
  expect_matches_reference(render_scene(kContacts, 30, s), "stage");
}

TEST(RenderReference, AutomaticCameraWithoutShadows) {
  // kShapes without its camera line: framed around the bodies.
  std::string yaml = kShapes;
  yaml = yaml.substr(0, yaml.find("camera:"));
  RenderSettings s;
  s.shadows = false;
  expect_matches_reference(render_scene(yaml.c_str(), 0, s), "auto_camera");
}

// The comparison must be able to fail: a slightly moved camera, a different overlay and a
// missing shadow each fail it against the reference they are not.
TEST(RenderReference, ComparisonRejectsWrongRenders) {
  const fs::path reference = kReferences / "shapes.png";
  ASSERT_TRUE(fs::exists(reference));
  const Image expected = read_png(reference);

  RenderSettings moved;
  moved.camera = Camera{Vec3(4.2, -3.8, 2.5), Vec3(0, 0, 0.4), 45};
  const ImageDifference d_moved =
      compare_images(render_scene(kShapes, 0, moved), expected, kPixelThreshold);
  EXPECT_FALSE(matches(d_moved)) << d_moved.mean_absolute << " " << d_moved.fraction_different;

  RenderSettings no_shadows;
  no_shadows.shadows = false;
  const ImageDifference d_shadow =
      compare_images(render_scene(kShapes, 0, no_shadows), expected, kPixelThreshold);
  EXPECT_FALSE(matches(d_shadow)) << d_shadow.mean_absolute << " " << d_shadow.fraction_different;

  RenderSettings stage;
  stage.enable(Overlay::stage);
  const ImageDifference d_stage =
      compare_images(render_scene(kShapes, 0, stage), expected, kPixelThreshold);
  EXPECT_FALSE(matches(d_stage)) << d_stage.mean_absolute << " " << d_stage.fraction_different;

  // And the same render passes: the comparison is not failing everything.
  EXPECT_TRUE(matches(compare_images(render_scene(kShapes, 0, {}), expected, kPixelThreshold)));
}

// The generic support-map mesh, which new convex shapes render through, draws the same picture
// as the dedicated sphere, box and capsule meshes.
TEST(RenderReference, GenericMeshesDrawTheSamePicture) {
  RenderSettings generic;
  generic.generic_meshes = true;
  const ImageDifference d = compare_images(render_scene(kShapes, 0, generic),
                                           render_scene(kShapes, 0, {}), kPixelThreshold);
  EXPECT_TRUE(matches(d)) << d.mean_absolute << " " << d.fraction_different;
}

// Independent of references: a lone sphere straight ahead of the camera covers the image
// centre in its own colour, the corners show the background, and the lit top is brighter than
// the underside.
TEST(Render, BodyAppearsWhereTheCameraLooks) {
  constexpr const char* kLone = R"(
bodies:
  - {name: ball, shape: {type: sphere, radius: 1}, position: [2, 3, 4]}
camera: {position: [2, -3, 4], target: [2, 3, 4], fov: 40}
)";
  const Image image = render_scene(kLone, 0, {});
  const auto pixel = [&](int x, int y) {
    const std::uint8_t* p = image.rgb.data() + (static_cast<std::size_t>(y) * image.width + x) * 3;
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  const auto centre = pixel(160, 120);
  const auto corner = pixel(2, 2);
  // The first palette colour is a warm orange: red dominates.
  EXPECT_GT(centre[0], centre[2] + 40);
  EXPECT_GT(centre[0], centre[1]);
  // Background: pale blue-grey, blue highest.
  EXPECT_GE(corner[2], corner[0]);
  EXPECT_GT(corner[0] + corner[1] + corner[2], 3 * 180);
  // Sphere of radius 1 at distance 6 with 40 degrees of view: radius on screen
  // 120 * tan(asin(1/6)) / tan(20 deg) = 55 pixels. Inside at 45, outside at 65.
  EXPECT_NE(pixel(160, 120 - 45), corner);
  EXPECT_EQ(pixel(160, 120 - 65), corner);
  EXPECT_EQ(pixel(160 + 65, 120), corner);
  const auto top = pixel(160, 120 - 40);
  const auto bottom = pixel(160, 120 + 40);
  EXPECT_GT(top[0] + top[1] + top[2], bottom[0] + bottom[1] + bottom[2] + 60);
}

TEST(Render, RejectsAbsurdSizes) {
  auto scene = std::make_shared<Scene>(load_scene_string(kShapes, "test"));
  RenderSettings s;
  s.width = 100000;
  EXPECT_THROW(Renderer(*scene, s), std::invalid_argument);
  s.width = 320;
  s.supersample = 9;
  EXPECT_THROW(Renderer(*scene, s), std::invalid_argument);
}

TEST(Render, OverlayNamesRoundTrip) {
  for (int i = 0; i < kOverlayCount; ++i) {
    const auto o = static_cast<Overlay>(i);
    EXPECT_EQ(parse_overlay(overlay_name(o)), o);
  }
  EXPECT_FALSE(parse_overlay("contact"));
}

TEST(Render, AutomaticFramingHoldsTheBounds) {
  const Aabb box{Vec3(-1, -2, 0), Vec3(3, 2, 1)};
  const Camera c = frame_bounds(box, 16.0 / 9.0);
  EXPECT_TRUE(((c.target - Vec3(1, 0, 0.5)).array().abs() < 1e-12).all());
  // Every corner lies inside the view cone.
  const Vec3 axis = (c.target - c.position).normalized();
  for (int k = 0; k < 8; ++k) {
    const Vec3 p((k & 1) ? 3 : -1, (k & 2) ? 2 : -2, (k & 4) ? 1 : 0);
    const Vec3 to = (p - c.position).normalized();
    EXPECT_GT(to.dot(axis), std::cos(22.5 * M_PI / 180)) << k;
  }
}

}  // namespace
}  // namespace tumble::render
