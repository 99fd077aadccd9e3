// Off-screen pictures of a world (OSMesa: no display, no GPU), from the optional renderer library
// (CMake target tumble::render). docs/rendering.md describes what it draws.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "tumble/scene.hpp"
#include "tumble/world.hpp"

namespace tumble {

struct RenderOptions {
  int width = 1280;  // pixels, 16 to 8192
  int height = 720;
  int supersample = 2;  // 1 to 4: renders this many times larger and filters down
  bool shadows = true;
  // Empty: the scene's camera, else one framed around the bodies.
  std::optional<Camera> camera;
};

// The version libtumble_render.so was built as.
const char* render_library_version();

class FrameRenderer {
 public:
  // Throws tumble::Error for sizes out of range, when libOSMesa cannot be loaded (it is loaded
  // with the first renderer) or when OSMesa cannot make a context.
  explicit FrameRenderer(const World& world, const RenderOptions& options = {});
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  int width() const;
  int height() const;
  // The world as it is now: width * height * 3 bytes of 8-bit RGB, rows from the top. Bodies
  // added or removed since the last frame are drawn as they are now.
  std::vector<std::uint8_t> render(const World& world);
  // The same frame as a PNG, written to a temporary file and renamed onto `path`.
  void write_png(const World& world, const std::filesystem::path& path);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tumble
