// `tumble render`: simulate a scene and render it off-screen in the same run, frame by frame,
// to an H.264 MP4 through ffmpeg and/or to PNG files.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace tumble::app {

struct RenderOptions {
  std::optional<int> threads;  // overrides the scene's world.threads
  std::filesystem::path scene;
  std::filesystem::path output;      // .mp4; empty: out/<scene>/<scene>.mp4 unless frames is set
  std::filesystem::path frames_dir;  // empty: no PNG frames
  double fps = 60;
  std::string size = "1280x720";  // WIDTHxHEIGHT
  std::vector<std::string> overlays;
  std::optional<double> duration;  // s, overrides the scene
  int supersample = 2;
  bool shadows = true;
  bool quiet = false;
};

// Returns the process exit code: 0 done, 1 user error (message on stderr, including "this build
// has no renderer" and "ffmpeg not found"), 130 interrupted.
int render_command(const RenderOptions& options);

}  // namespace tumble::app
