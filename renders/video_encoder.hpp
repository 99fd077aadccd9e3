// Streams frames to an ffmpeg child process (rawvideo rgb24 on its stdin, H.264 in MP4 out), so
// a video of any length needs one frame of memory. The MP4 is written to a temporary name beside
// the target and renamed when ffmpeg has finished it: an interrupted or failed render leaves no
// partial file under the final name.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include "renders/image.hpp"

namespace tumble::render {

// ffmpeg is missing, cannot start, or failed: the message says which and what to do.
struct VideoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The executable `name` as the shell would find it on PATH, or nothing.
std::optional<std::filesystem::path> find_on_path(const std::string& name);

class VideoEncoder {
 public:
  // Starts ffmpeg. Width and height must be even (yuv420p). Uses libx264 when ffmpeg has it,
  // else mpeg4 with a note on stderr. Throws VideoError.
  VideoEncoder(const std::filesystem::path& output, int width, int height, double fps);
  // Without finish(): stops ffmpeg and removes the temporary file.
  ~VideoEncoder();
  VideoEncoder(const VideoEncoder&) = delete;
  VideoEncoder& operator=(const VideoEncoder&) = delete;

  // Throws VideoError when ffmpeg has gone away.
  void write_frame(const Image& frame);
  // Closes ffmpeg's input, waits for it and renames the finished file onto the target.
  void finish();

  const std::string& codec() const { return codec_; }

 private:
  void stop_child();

  std::filesystem::path output_;
  std::filesystem::path temporary_;
  int width_ = 0;
  int height_ = 0;
  std::string codec_;
  pid_t child_ = -1;
  int pipe_ = -1;
  bool finished_ = false;
  void (*previous_sigpipe_)(int) = nullptr;
};

}  // namespace tumble::render
