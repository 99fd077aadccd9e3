#include "renders/video_encoder.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

extern char** environ;

namespace tumble::render {
namespace {

// Whether this ffmpeg build lists the libx264 encoder (Debian's does).
bool has_libx264(const std::filesystem::path& ffmpeg) {
  const std::string command = "'" + ffmpeg.string() + "' -hide_banner -encoders 2>/dev/null";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr)
    return false;
  std::string listing;
  std::array<char, 4096> buffer;
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    listing.append(buffer.data(), n);
  ::pclose(pipe);
  return listing.find(" libx264 ") != std::string::npos;
}

std::string number(double value) {
  std::ostringstream s;
  s.precision(17);
  s << value;
  return s.str();
}

}  // namespace

std::optional<std::filesystem::path> find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (path == nullptr)
    return std::nullopt;
  std::stringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    // An empty entry means the current directory.
    const std::filesystem::path candidate =
        (dir.empty() ? std::filesystem::current_path() : std::filesystem::path(dir)) / name;
    if (::access(candidate.c_str(), X_OK) == 0 && !std::filesystem::is_directory(candidate))
      return candidate;
  }
  return std::nullopt;
}

VideoEncoder::VideoEncoder(const std::filesystem::path& output, int width, int height, double fps)
    : output_(output), width_(width), height_(height) {
  if (width % 2 != 0 || height % 2 != 0) {
    throw VideoError("video size " + std::to_string(width) + "x" + std::to_string(height) +
                     " must have even width and height (H.264 with yuv420p)");
  }
  const auto ffmpeg = find_on_path("ffmpeg");
  if (!ffmpeg) {
    throw VideoError(
        "ffmpeg not found on PATH; install it (Debian: apt-get install ffmpeg, or run "
        "scripts/setup-debian.sh), or write PNG frames with --frames DIR instead");
  }
  codec_ = has_libx264(*ffmpeg) ? "libx264" : "mpeg4";
  if (codec_ != "libx264")
    std::fprintf(stderr, "tumble: note: this ffmpeg has no libx264; encoding MPEG-4 part 2\n");

  const std::filesystem::path dir = output.has_parent_path() ? output.parent_path() : ".";
  temporary_ =
      dir / ("." + output.filename().string() + ".tmp-" + std::to_string(::getpid()) + ".mp4");

  std::vector<std::string> args = {ffmpeg->string(),
                                   "-hide_banner",
                                   "-loglevel",
                                   "error",
                                   "-y",
                                   "-f",
                                   "rawvideo",
                                   "-pix_fmt",
                                   "rgb24",
                                   "-s",
                                   std::to_string(width) + "x" + std::to_string(height),
                                   "-r",
                                   number(fps),
                                   "-i",
                                   "pipe:0",
                                   "-an",
                                   "-c:v",
                                   codec_};
  if (codec_ == "libx264") {
    args.insert(args.end(), {"-preset", "veryfast", "-crf", "20"});
  } else {
    args.insert(args.end(), {"-q:v", "3"});
  }
  args.insert(args.end(),
              {"-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4", temporary_.string()});
  std::vector<char*> argv;
  for (std::string& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);

  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw VideoError(std::string("cannot create a pipe to ffmpeg: ") + std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  // Its own process group: Ctrl-C reaches tumble only, which then stops ffmpeg in order.
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  const int spawned = ::posix_spawn(&child_, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  ::close(fds[0]);
  if (spawned != 0) {
    ::close(fds[1]);
    child_ = -1;
    throw VideoError("cannot start " + ffmpeg->string() + ": " + std::strerror(spawned));
  }
  pipe_ = fds[1];
  // A write to a dead ffmpeg must be an error we report, not a signal that kills us.
  previous_sigpipe_ = std::signal(SIGPIPE, SIG_IGN);
}

VideoEncoder::~VideoEncoder() {
  if (!finished_) {
    stop_child();
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
  }
  std::signal(SIGPIPE, previous_sigpipe_ == SIG_ERR ? SIG_DFL : previous_sigpipe_);
}

void VideoEncoder::stop_child() {
  if (pipe_ >= 0) {
    ::close(pipe_);
    pipe_ = -1;
  }
  if (child_ > 0) {
    ::kill(child_, SIGTERM);
    int status = 0;
    while (::waitpid(child_, &status, 0) < 0 && errno == EINTR) {
    }
    child_ = -1;
  }
}

void VideoEncoder::write_frame(const Image& frame) {
  if (frame.width != width_ || frame.height != height_)
    throw VideoError("frame size does not match the video size");
  if (pipe_ < 0)
    throw VideoError("the video is already finished");
  const std::uint8_t* data = frame.rgb.data();
  std::size_t left = frame.rgb.size();
  while (left > 0) {
    const ssize_t n = ::write(pipe_, data, left);
    if (n < 0) {
      if (errno == EINTR)
        continue;
      throw VideoError(std::string("ffmpeg stopped accepting frames (") + std::strerror(errno) +
                       "); see its message above");
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
}

void VideoEncoder::finish() {
  ::close(pipe_);
  pipe_ = -1;
  int status = 0;
  while (::waitpid(child_, &status, 0) < 0) {
    if (errno != EINTR)
      throw VideoError(std::string("waiting for ffmpeg failed: ") + std::strerror(errno));
  }
  child_ = -1;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw VideoError("ffmpeg failed (" +
                     (WIFEXITED(status) ? "exit code " + std::to_string(WEXITSTATUS(status))
                                        : "signal " + std::to_string(WTERMSIG(status))) +
                     ") writing " + output_.string() + "; see its message above");
  }
  std::error_code ec;
  std::filesystem::rename(temporary_, output_, ec);
  if (ec)
    throw VideoError(output_.string() + ": cannot rename the finished video (" + ec.message() +
                     ")");
  finished_ = true;
}

}  // namespace tumble::render
