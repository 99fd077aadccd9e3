// tumble::FrameRenderer, the public renderer: frames of the right size that show the bodies,
// PNGs written whole, bad sizes refused, bodies added later drawn.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "renders/image.hpp"
#include "tumble/render.hpp"
#include "tumble/tumble.hpp"

namespace tumble {
namespace {

std::shared_ptr<Scene> small_scene() {
  auto scene = std::make_shared<Scene>();
  scene->bodies.push_back(static_body("ground", Shape::box(Vec3(3, 3, 0.5))));
  BodyDesc box = dynamic_body("box", Shape::box(Vec3(0.5, 0.5, 0.5)));
  box.position = Vec3(0, 0, 1);
  scene->bodies.push_back(box);
  scene->camera = Camera{Vec3(5, -5, 4), Vec3(0, 0, 0.5), 45};
  return scene;
}

int distinct_colours(const std::vector<std::uint8_t>& rgb) {
  std::set<std::uint32_t> colours;
  for (std::size_t i = 0; i + 2 < rgb.size(); i += 3)
    colours.insert(std::uint32_t(rgb[i]) << 16 | std::uint32_t(rgb[i + 1]) << 8 | rgb[i + 2]);
  return static_cast<int>(colours.size());
}

TEST(FrameRenderer, DrawsAFrameOfTheAskedSize) {
  World world(small_scene());
  RenderOptions options;
  options.width = 160;
  options.height = 120;
  options.supersample = 1;
  FrameRenderer renderer(world, options);
  const std::vector<std::uint8_t> frame = renderer.render(world);
  ASSERT_EQ(frame.size(), std::size_t(160 * 120 * 3));
  EXPECT_GT(distinct_colours(frame), 10) << "the frame shows nothing but a background";
  world.add_body([] {
    BodyDesc b = dynamic_body("ball", Shape::sphere(0.4));
    b.position = Vec3(1, 1, 1.5);
    return b;
  }());
  const std::vector<std::uint8_t> with_ball = renderer.render(world);
  EXPECT_NE(frame, with_ball) << "the added body is not drawn";
}

TEST(FrameRenderer, WritesAPng) {
  World world(small_scene());
  RenderOptions options;
  options.width = 64;
  options.height = 48;
  FrameRenderer renderer(world, options);
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "tumble_frame_renderer_test.png";
  renderer.write_png(world, path);
  const render::Image image = render::read_png(path);
  EXPECT_EQ(image.width, 64);
  EXPECT_EQ(image.height, 48);
  std::filesystem::remove(path);
  EXPECT_THROW(renderer.write_png(world, "/nonexistent-folder/x.png"), Error);
}

TEST(FrameRenderer, RefusesBadSizes) {
  World world(small_scene());
  RenderOptions options;
  options.width = 4;
  EXPECT_THROW(FrameRenderer(world, options), Error);
  options.width = 64;
  options.supersample = 9;
  EXPECT_THROW(FrameRenderer(world, options), Error);
}

}  // namespace
}  // namespace tumble
