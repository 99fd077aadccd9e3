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
  // The model the renderer's meshes were built for: held, so that a world that adds or removes a
  // body (and so makes a new model) is always noticed.
  std::shared_ptr<const Model> model;
  std::unique_ptr<render::Renderer> renderer;
  render::Image image;

  void follow(const World& world) {
    const Model& now = world.simulation().model();
    if (renderer && model.get() == &now)
      return;
    std::vector<std::uint8_t> hidden(now.body_count(), 0);
    for (std::size_t i = 0; i < hidden.size(); ++i)
      hidden[i] = now.is_removed(i) ? 1 : 0;
    try {
      renderer = std::make_unique<render::Renderer>(now.scene(), settings, hidden);
    } catch (const std::exception& e) {
      throw Error(std::string("tumble::FrameRenderer: ") + e.what());
    }
    model = world.simulation().model_pointer();
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
