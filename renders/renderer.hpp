// Off-screen rendering of a world through OSMesa (Mesa's software rasteriser: no display, no
// GPU), with legacy fixed-function OpenGL: one directional light with ambient, planar shadows on
// the floors, supersampling for anti-aliasing, and optional debug overlays of what the
// collision pipeline saw. docs/rendering.md describes it and what it costs.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "engine/simulation.hpp"
#include "renders/image.hpp"

namespace tumble::render {

// Debug overlays (docs/rendering.md, "Debug overlays"), each drawn only when asked for.
enum class Overlay : std::uint8_t {
  aabb,      // each bounded body's world AABB, yellow
  pairs,     // a line between the centres of each broad-phase candidate pair, cyan
  contacts,  // contact points (red) and the push on the second body, -normal (green)
  stage,     // body colour by the furthest stage it reached: none, candidate pair, touching
  rest,      // body colour by rest: blue when slower than 5 cm/s and 0.05 rad/s
};
inline constexpr int kOverlayCount = 5;

std::string_view overlay_name(Overlay overlay);
std::optional<Overlay> parse_overlay(std::string_view name);
// "aabb, pairs, contacts, stage, rest", for help texts and messages.
std::string overlay_names();

struct RenderSettings {
  int width = 1280;  // output pixels
  int height = 720;
  int supersample = 2;  // renders at supersample x size and box-filters down (anti-aliasing)
  bool shadows = true;
  // Draw every bounded shape through the generic support-map mesh, even those with a dedicated
  // one (to check that path against the dedicated meshes).
  bool generic_meshes = false;
  std::uint32_t overlays = 0;  // bit (1 << Overlay)
  // The camera; empty: the scene's, else framed around the bodies of the initial state.
  std::optional<Camera> camera;

  bool has(Overlay o) const { return (overlays >> static_cast<int>(o)) & 1u; }
  void enable(Overlay o) { overlays |= 1u << static_cast<int>(o); }
};

// The largest drawing buffer side OSMesa's software rasteriser takes (MAX_WIDTH and MAX_HEIGHT of
// Mesa's src/mesa/main/config.h); beyond it OSMesa crashes instead of failing. At 4 bytes a pixel
// the largest buffer is then 1 GiB.
inline constexpr int kMaxBufferSide = 16384;
// Empty when the settings' supersampled buffer fits, else why not (for messages).
std::string render_buffer_problem(const RenderSettings& settings);

class Renderer {
 public:
  // Builds the meshes of every body and an OSMesa context; `scene` must outlive the renderer.
  // Throws std::invalid_argument for sizes outside 16..8192, a supersample outside 1..4 or a
  // shape it cannot draw, and std::runtime_error when OSMesa cannot create the context.
  // Bodies whose flag in `hidden` is 1 (empty slots of a world that removed them) are not drawn.
  Renderer(const Scene& scene, const RenderSettings& settings,
           std::span<const std::uint8_t> hidden = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Draws the world's current state (and, for overlays, its last step's pairs and contacts)
  // into `image`, resized to the output size.
  void render(const Simulation& world, Image& image);

  const Camera& camera() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tumble::render
