// `tumble render` run as a user runs it: the video's frame count, size and duration measured by
// ffprobe, PNG frames, clear errors (no ffmpeg, bad size, unknown overlay) and no partial video
// after Ctrl-C.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "renders/image.hpp"

extern char** environ;

namespace tumble::test {
namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code = -1;
  std::string output;
};

Result shell(const std::string& command) {
  Result r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr)
    return r;
  std::array<char, 4096> buffer;
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    r.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

Result tumble(const std::string& arguments) {
  // Appended, not `std::string(TUMBLE_CLI) + " " + arguments`: GCC 12 at -O3 warns falsely
  // (-Warray-bounds) on that temporary once the test binary's precompiled header is in use.
  std::string command = TUMBLE_CLI;
  command += ' ';
  command += arguments;
  return shell(command);
}

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("tumble_render_cli_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A ball dropping onto a box: small and quick to render.
fs::path write_scene(const fs::path& dir) {
  const fs::path scene = dir / "drop.yaml";
  std::ofstream(scene) << R"(
world: {dt: 0.005, duration: 1.0}
bodies:
  - {name: floor, shape: {type: plane}, static: true}
  - {name: crate, shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [0, 0, 0.5]}
  - {name: ball, shape: {type: sphere, radius: 0.3}, position: [0.1, 0, 2.0]}
)";
  return scene;
}

bool no_temporaries(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().filename().string().find(".tmp-") != std::string::npos)
      return false;
  }
  return true;
}

TEST(RenderCommand, VideoHasTheFrameCountSizeAndDurationAsked) {
  const fs::path dir = scratch("video");
  const fs::path video = dir / "drop.mp4";
  const Result r = tumble("render " + write_scene(dir).string() +
                          " -q --fps 24 --size 160x120 -o " + video.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(video));
  EXPECT_TRUE(no_temporaries(dir));
  const Result probe = shell(
      "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
      "stream=codec_name,width,height,nb_read_frames,pix_fmt:format=duration -of json '" +
      video.string() + "'");
  ASSERT_EQ(probe.exit_code, 0) << probe.output;
  const auto j = nlohmann::json::parse(probe.output);
  const auto& stream = j.at("streams").at(0);
  EXPECT_EQ(stream.at("codec_name"), "h264");
  EXPECT_EQ(stream.at("pix_fmt"), "yuv420p");
  EXPECT_EQ(stream.at("width"), 160);
  EXPECT_EQ(stream.at("height"), 120);
  EXPECT_EQ(std::stoi(stream.at("nb_read_frames").get<std::string>()), 24);  // 1 s at 24 fps
  EXPECT_NEAR(std::stod(j.at("format").at("duration").get<std::string>()), 1.0, 0.05);
}

TEST(RenderCommand, FramesAreWrittenAsPngs) {
  const fs::path dir = scratch("frames");
  const Result r = tumble("render " + write_scene(dir).string() +
                          " -q --fps 10 --duration 0.5 --size 96x64 --overlay contacts,aabb "
                          "--frames " +
                          (dir / "png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  int count = 0;
  for (const auto& e : fs::directory_iterator(dir / "png")) {
    const render::Image image = render::read_png(e.path());
    EXPECT_EQ(image.width, 96);
    EXPECT_EQ(image.height, 64);
    ++count;
  }
  EXPECT_EQ(count, 5);
  EXPECT_TRUE(fs::exists(dir / "png" / "frame_000004.png"));
  // --frames alone writes no video.
  EXPECT_FALSE(fs::exists(dir / "drop.mp4"));
}

TEST(RenderCommand, MissingFfmpegIsAClearError) {
  const fs::path dir = scratch("no_ffmpeg");
  const fs::path empty = dir / "empty_path";
  fs::create_directories(empty);
  const Result r =
      shell("PATH='" + empty.string() + "' " + TUMBLE_CLI + " render " + write_scene(dir).string() +
            " -q --size 64x48 -o " + (dir / "x.mp4").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("ffmpeg not found"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "x.mp4"));
}

// libOSMesa is loaded when a renderer is made (renders/osmesa_library.hpp): a machine without it
// gets the library's name, its package and the loader's reason, and no video.
TEST(RenderCommand, MissingOsMesaIsAClearError) {
  const fs::path dir = scratch("no_osmesa");
  const Result r = shell("TUMBLE_OSMESA_LIBRARY='" + (dir / "libOSMesa.so.8").string() + "' " +
                         TUMBLE_CLI + " render " + write_scene(dir).string() +
                         " -q --size 64x48 -o " + (dir / "x.mp4").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("libOSMesa.so.8 (Debian package libosmesa6"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find((dir / "libOSMesa.so.8").string()), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "x.mp4"));
}

// The command line does not link libOSMesa (nor the libLLVM it brings): its start-up costs every
// command that never draws 0.1 to 0.25 s of symbol resolution (docs/reliability.md, "CI time").
TEST(RenderCommand, TheCommandLineLoadsOsMesaOnlyToRender) {
  const Result r = shell(std::string("ldd ") + TUMBLE_CLI);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("libstdc++"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("libOSMesa"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("libLLVM"), std::string::npos) << r.output;
}

TEST(RenderCommand, BadOptionsAreUserErrors) {
  const fs::path dir = scratch("bad");
  const std::string scene = write_scene(dir).string();
  const fs::path out = dir / "x.mp4";
  Result r = tumble("render " + scene + " --size 65x48 -o " + out.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("even"), std::string::npos) << r.output;
  r = tumble("render " + scene + " --size big -o " + out.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--size"), std::string::npos) << r.output;
  r = tumble("render " + scene + " --overlay contacts,normals -o " + out.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("unknown overlay 'normals'"), std::string::npos) << r.output;
  r = tumble("render " + (dir / "missing.yaml").string() + " -o " + out.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("missing.yaml"), std::string::npos) << r.output;
  // Each value in range, the supersampled buffer (24576 a side) not: refused before OSMesa,
  // which crashed on it.
  r = tumble("render " + scene + " --size 8192x8192 --supersample 3 -o " + out.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("exceeds OSMesa's 16384 pixels a side"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

// Ctrl-C mid-video: exit 130, no file under the final name, no temporary left behind.
TEST(RenderCommand, InterruptedRenderLeavesNoPartialVideo) {
  const fs::path dir = scratch("interrupt");
  const std::string cli = TUMBLE_CLI;
  std::vector<std::string> args = {
      cli,     "render", write_scene(dir).string(),  "-q", "--duration", "1000", "--size",
      "64x48", "-o",     (dir / "long.mp4").string()};
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  ASSERT_EQ(::posix_spawn(&pid, cli.c_str(), nullptr, nullptr, argv.data(), environ), 0);
  // Wait for ffmpeg's temporary file, so that the interrupt lands mid-video.
  for (int i = 0; i < 300 && no_temporaries(dir); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_FALSE(no_temporaries(dir));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_FALSE(fs::exists(dir / "long.mp4"));
  EXPECT_TRUE(no_temporaries(dir));
}

}  // namespace
}  // namespace tumble::test
