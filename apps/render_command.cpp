#include "apps/render_command.hpp"

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string_view>

#include <unistd.h>

#include "apps/scene_access.hpp"
#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"

#if TUMBLE_HAS_RENDERER
#include "renders/renderer.hpp"
#include "renders/video_encoder.hpp"
#endif

namespace tumble::app {

#if !TUMBLE_HAS_RENDERER

int render_command(const RenderOptions&) {
  std::cerr << "tumble render: this build has no renderer (configured without OSMesa: "
               "TUMBLE_WITH_RENDER=OFF); install libosmesa6-dev and libpng-dev (or run "
               "scripts/setup-debian.sh) and reconfigure with -DTUMBLE_WITH_RENDER=ON\n";
  return 1;
}

#else

namespace {

volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_render_interrupt(int) {
  g_interrupted = 1;
}

// One line on stderr, redrawn in place at most ten times a second on a terminal; into a log
// file or pipe, one line per tenth of the frames instead.
class ProgressBar {
 public:
  ProgressBar(std::int64_t total, bool enabled)
      : total_(total),
        enabled_(enabled),
        terminal_(::isatty(STDERR_FILENO) != 0),
        start_(std::chrono::steady_clock::now()) {}

  void update(std::int64_t done) {
    if (!enabled_)
      return;
    const auto now = std::chrono::steady_clock::now();
    if (terminal_) {
      if (done < total_ && now - last_ < std::chrono::milliseconds(100))
        return;
    } else if (done < total_ && (10 * done) / total_ == (10 * (done - 1)) / total_) {
      return;
    }
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double rate = elapsed > 0 ? done / elapsed : 0;
    const double left = rate > 0 ? (total_ - done) / rate : 0;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * done / std::max<std::int64_t>(total_, 1));
    std::fprintf(stderr, "%s[%s%s] %lld/%lld frames  %5.1f fps  %5.1f s left %s",
                 terminal_ ? "\r" : "", std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, '.').c_str(), static_cast<long long>(done),
                 static_cast<long long>(total_), rate, left, terminal_ ? "" : "\n");
    std::fflush(stderr);
  }
  void finish() {
    if (enabled_ && terminal_)
      std::fprintf(stderr, "\n");
  }

 private:
  std::int64_t total_;
  bool enabled_;
  bool terminal_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_{};
};

// "WIDTHxHEIGHT", each 1 to 5 digits. (Not std::regex: g++ 12 warns inside it under -O2 with
// the sanitizers.)
bool parse_size(const std::string& text, int& width, int& height) {
  const std::size_t x = text.find('x');
  if (x == std::string::npos)
    return false;
  const auto digits = [](std::string_view part, int& value) {
    if (part.empty() || part.size() > 5)
      return false;
    value = 0;
    for (const char c : part) {
      if (c < '0' || c > '9')
        return false;
      value = value * 10 + (c - '0');
    }
    return true;
  };
  const std::string_view view(text);
  return digits(view.substr(0, x), width) && digits(view.substr(x + 1), height);
}

}  // namespace

int render_command(const RenderOptions& options) {
  using render::Overlay;
  render::RenderSettings settings;
  if (!parse_size(options.size, settings.width, settings.height) || settings.width < 16 ||
      settings.height < 16 || settings.width > 8192 || settings.height > 8192) {
    std::cerr << "tumble render: --size: expected WIDTHxHEIGHT with each in 16..8192, got '"
              << options.size << "'\n";
    return 1;
  }
  for (const std::string& name : options.overlays) {
    const auto overlay = render::parse_overlay(name);
    if (!overlay) {
      std::cerr << "tumble render: --overlay: unknown overlay '" << name
                << "'; known: " << render::overlay_names() << "\n";
      return 1;
    }
    settings.enable(*overlay);
  }
  settings.supersample = options.supersample;
  settings.shadows = options.shadows;
  if (const std::string problem = render::render_buffer_problem(settings); !problem.empty()) {
    std::cerr << "tumble render: --size " << options.size << " --supersample "
              << options.supersample << ": " << problem << "\n";
    return 1;
  }

  auto scene = std::make_shared<Scene>(load_scene_file(options.scene, {}, scene_load_options()));
  if (options.threads)
    scene->world.threads = *options.threads;
  const double duration = options.duration ? *options.duration
                          : scene->world.steps
                              ? static_cast<double>(*scene->world.steps) * scene->world.dt
                              : scene->world.duration;
  const auto frames = std::max<std::int64_t>(1, std::llround(duration * options.fps));

  std::filesystem::path video = options.output;
  if (video.empty() && options.frames_dir.empty())
    video = std::filesystem::path("out") / options.scene.stem() /
            (options.scene.stem().string() + ".mp4");
  for (const std::filesystem::path& dir :
       {video.empty() ? std::filesystem::path() : video.parent_path(), options.frames_dir}) {
    if (dir.empty())
      continue;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) {
      std::cerr << "tumble render: " << dir.string() << ": cannot create directory ("
                << ec.message() << ")\n";
      return 1;
    }
  }

  // The encoder first: a missing ffmpeg is reported before any work is done.
  std::unique_ptr<render::VideoEncoder> encoder;
  try {
    if (!video.empty()) {
      encoder = std::make_unique<render::VideoEncoder>(video, settings.width, settings.height,
                                                       options.fps);
    }
  } catch (const render::VideoError& e) {
    std::cerr << "tumble render: " << e.what() << "\n";
    return 1;
  }

  g_interrupted = 0;
  auto previous_int = std::signal(SIGINT, on_render_interrupt);
  auto previous_term = std::signal(SIGTERM, on_render_interrupt);
  auto previous_hup = std::signal(SIGHUP, on_render_interrupt);  // the terminal closed
  struct RestoreSignals {
    void (*previous_int)(int);
    void (*previous_term)(int);
    void (*previous_hup)(int);
    ~RestoreSignals() {
      std::signal(SIGINT, previous_int);
      std::signal(SIGTERM, previous_term);
      std::signal(SIGHUP, previous_hup);
    }
  } restore{previous_int, previous_term, previous_hup};

  Simulation world(scene);
  std::unique_ptr<render::Renderer> renderer;
  try {
    renderer = std::make_unique<render::Renderer>(*scene, settings);
  } catch (const std::invalid_argument& e) {
    std::cerr << "tumble render: " << options.scene.string() << ": cannot render: " << e.what()
              << "\n";
    return 1;
  }
  render::Image image;
  ProgressBar progress(frames, !options.quiet);
  const Real dt = scene->world.dt;
  const auto start = std::chrono::steady_clock::now();
  double render_seconds = 0;
  for (std::int64_t k = 0; k < frames && !g_interrupted; ++k) {
    // The frame shows the first state at or after its time k / fps.
    const Real frame_time = static_cast<Real>(k) / options.fps;
    while (world.state().time + Real(1e-6) * dt < frame_time && !g_interrupted)
      world.step();
    if (g_interrupted)
      break;
    const auto render_start = std::chrono::steady_clock::now();
    renderer->render(world, image);
    render_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - render_start).count();
    if (!options.frames_dir.empty()) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%06lld.png", static_cast<long long>(k));
      render::write_png(options.frames_dir / name, image);
    }
    if (encoder) {
      try {
        encoder->write_frame(image);
      } catch (const render::VideoError& e) {
        progress.finish();
        std::cerr << "tumble render: " << e.what() << "\n";
        return 1;
      }
    }
    progress.update(k + 1);
  }
  progress.finish();
  if (g_interrupted) {
    // The encoder's destructor stops ffmpeg and removes its temporary file.
    std::cerr << "tumble render: interrupted; no video written\n";
    return 130;
  }
  if (encoder) {
    try {
      encoder->finish();
    } catch (const render::VideoError& e) {
      std::cerr << "tumble render: " << e.what() << "\n";
      return 1;
    }
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!options.quiet) {
    std::cout << "tumble render: " << frames << " frames " << settings.width << "x"
              << settings.height << " at " << options.fps << " fps (" << duration
              << " s simulated) in " << wall << " s, " << 1000 * render_seconds / frames
              << " ms per frame rendering\n";
    if (encoder)
      std::cout << "  video:  " << video.string() << " (" << encoder->codec() << ")\n";
    if (!options.frames_dir.empty())
      std::cout << "  frames: " << options.frames_dir.string() << "/frame_NNNNNN.png\n";
  }
  return 0;
}

#endif

}  // namespace tumble::app
