// tumble::FrameRenderer (include/tumble/render.hpp): the public face of the OSMesa renderer.
#include "tumble/render.hpp"

#include <string>

#include "engine/simulation.hpp"
#include "renders/image.hpp"
#include "renders/renderer.hpp"
#include "tumble/error.hpp"

namespace tumble {

struct FrameRenderer::Impl {
  render::RenderSettings settings;
  const Scene* scene = nullptr;  // the scene the renderer's meshes were built for
  std::unique_ptr<render::Renderer> renderer;
  render::Image image;

  void follow(const World& world) {
    if (renderer && scene == &world.scene())
      return;
    try {
      renderer = std::make_unique<render::Renderer>(world.scene(), settings);
    } catch (const std::exception& e) {
      throw Error(std::string("tumble::FrameRenderer: ") + e.what());
    }
    scene = &world.scene();
    // Later frames keep the first frame's camera, so a body added later does not move it.
    settings.camera = renderer->camera();
  }
};

FrameRenderer::FrameRenderer(const World& world, const RenderOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->settings.width = options.width;
  impl_->settings.height = options.height;
  impl_->settings.supersample = options.supersample;
  impl_->settings.shadows = options.shadows;
  impl_->settings.camera = options.camera;
  impl_->follow(world);
}

FrameRenderer::~FrameRenderer() = default;

int FrameRenderer::width() const {
  return impl_->settings.width;
}

int FrameRenderer::height() const {
  return impl_->settings.height;
}

std::vector<std::uint8_t> FrameRenderer::render(const World& world) {
  impl_->follow(world);
  impl_->renderer->render(world.simulation(), impl_->image);
  return impl_->image.rgb;
}

void FrameRenderer::write_png(const World& world, const std::filesystem::path& path) {
  impl_->follow(world);
  impl_->renderer->render(world.simulation(), impl_->image);
  try {
    render::write_png(path, impl_->image);
  } catch (const std::exception& e) {
    throw Error(std::string("tumble::FrameRenderer::write_png: ") + e.what());
  }
}

}  // namespace tumble
