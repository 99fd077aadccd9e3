// The files a scene names (meshes, hulls, grids) must lie in its folder or below it, symbolic
// links followed, unless SceneLoadOptions::allow_outside_files; a hull's file is read like a
// mesh's (regular files only, bad lines named by number, never echoed at length).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "scenes/scene_loader.hpp"

namespace tumble {
namespace {

namespace fs = std::filesystem;

constexpr const char* kTetrahedron =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n"
    "f 1 4 3\nf 2 3 4\n";

void write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// A scene folder `scene/` with a tetrahedron beside it and one inside it.
struct Folders {
  fs::path root;
  fs::path scene_dir;
  Folders() {
    root = fs::temp_directory_path() / ("tumble_scene_files_" + std::to_string(::getpid()));
    fs::remove_all(root);
    scene_dir = root / "scene";
    write(root / "outside.obj", kTetrahedron);
    write(scene_dir / "meshes" / "inside.obj", kTetrahedron);
  }
  ~Folders() { fs::remove_all(root); }
  // A scene whose one static body is the shape `shape` (YAML flow map), written as scene.yaml.
  fs::path scene_with(const std::string& shape) const {
    const fs::path path = scene_dir / "scene.yaml";
    write(path,
          "world: {dt: 0.01, duration: 0.1}\nbodies:\n  - {name: thing, static: true,\n"
          "     shape: " +
              shape + "}\n");
    return path;
  }
};

std::string refusal(const fs::path& scene, const SceneLoadOptions& options = {}) {
  try {
    (void)load_scene_file(scene, {}, options);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneFiles, AFileOutsideTheScenesFolderIsRefusedUnlessAllowed) {
  const Folders f;
  const SceneLoadOptions anywhere{.allow_outside_files = true};
  for (const std::string& name : {std::string("../outside.obj"), (f.root / "outside.obj").string(),
                                  std::string("meshes/../../outside.obj")}) {
    for (const std::string type : {"mesh", "hull"}) {
      const fs::path scene = f.scene_with("{type: " + type + ", file: '" + name + "'}");
      const std::string why = refusal(scene);
      EXPECT_NE(why.find("scene.yaml:4:"), std::string::npos) << why;
      EXPECT_NE(why.find("bodies[0].shape.file"), std::string::npos) << why;
      EXPECT_NE(why.find("lies outside the scene's folder"), std::string::npos) << why;
      EXPECT_NE(why.find("--allow-outside-files"), std::string::npos) << why;
      EXPECT_EQ(refusal(scene, anywhere), "") << type << " " << name;
    }
  }
  // In the folder or below it: read as always.
  EXPECT_EQ(refusal(f.scene_with("{type: mesh, file: meshes/inside.obj}")), "");
  EXPECT_EQ(refusal(f.scene_with("{type: hull, file: meshes/../meshes/inside.obj}")), "");
  // A grid field's mesh follows the same rule.
  const fs::path grid = f.scene_with("{type: sdf, sdf: {grid: {file: ../outside.obj, cell: 0.2}}}");
  EXPECT_NE(refusal(grid).find("sdf.grid.file"), std::string::npos);
}

TEST(SceneFiles, ALinkInTheFolderToAFileOutsideItIsRefused) {
  const Folders f;
  fs::create_symlink(f.root / "outside.obj", f.scene_dir / "link.obj");
  const fs::path scene = f.scene_with("{type: mesh, file: link.obj}");
  EXPECT_NE(refusal(scene).find("'link.obj' lies outside"), std::string::npos) << refusal(scene);
  EXPECT_EQ(refusal(scene, {.allow_outside_files = true}), "");
  // A link to a folder outside leads out as well.
  fs::create_directory_symlink(f.root, f.scene_dir / "up");
  EXPECT_NE(refusal(f.scene_with("{type: hull, file: up/outside.obj}")).find("lies outside"),
            std::string::npos);
}

TEST(SceneFiles, ATextScenesFolderIsTheCurrentOne) {
  const Folders f;
  const fs::path previous = fs::current_path();
  fs::current_path(f.scene_dir);
  const std::string yaml = "bodies:\n  - {name: m, static: true, shape: {type: mesh, file: X}}\n";
  const auto refused = [&](const std::string& name, const SceneLoadOptions& options) {
    std::string text = yaml;
    text.replace(text.find('X'), 1, name);
    try {
      (void)load_scene_string(text, "<text>", {}, options);
    } catch (const SceneError& e) {
      return std::string(e.what()).find("lies outside") != std::string::npos;
    }
    return false;
  };
  EXPECT_FALSE(refused("meshes/inside.obj", {}));
  EXPECT_TRUE(refused("../outside.obj", {}));
  EXPECT_FALSE(refused("../outside.obj", {.allow_outside_files = true}));
  fs::current_path(previous);
}

TEST(SceneFiles, AHullFileIsReadLikeAMeshFile) {
  const Folders f;
  // Not a regular file: refused at once (a FIFO would block the read for ever).
  const fs::path fifo = f.scene_dir / "pipe.obj";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(refusal(f.scene_with("{type: hull, file: pipe.obj}")).find("not a regular file"),
            std::string::npos);
  // A bad vertex is named by its line, and the line is not echoed.
  write(f.scene_dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 secret-text-of-the-file\nv 0 0 1\n");
  const std::string why = refusal(f.scene_with("{type: hull, file: bad.obj}"));
  EXPECT_NE(why.find("line 3: vertex coordinate 3"), std::string::npos) << why;
  EXPECT_EQ(why.find("secret"), std::string::npos) << why;
  // Points with no faces are a hull's usual file.
  write(f.scene_dir / "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n");
  EXPECT_EQ(refusal(f.scene_with("{type: hull, file: points.obj}")), "");
}

// The system reads a file name up to its first NUL byte, so a name holding one would open another
// file ("inside.obj\0.txt" is inside.obj): refused, whether the scene's own name (as the C++ and
// Python APIs can pass it) or one the scene names (YAML's "\0" escape). Messages show control
// bytes of a name as \xNN, so that a message is never cut at a NUL. Found by the Python argument
// fuzz (python/tests/test_argument_fuzz.py): World("a\0b") raised an error whose message was "a".
TEST(SceneFiles, ANameHoldingANulByteIsRefusedAndShownEscaped) {
  const Folders f;
  const std::string scene = (f.scene_dir / "scene.yaml").string();
  (void)f.scene_with("{type: mesh, file: meshes/inside.obj}");
  ASSERT_EQ(refusal(scene), "");
  const std::string why = refusal(scene + std::string(1, '\0') + ".txt");
  EXPECT_NE(
      why.find("scene.yaml\\x00.txt: cannot open scene file (the file name holds a NUL byte)"),
      std::string::npos)
      << why;
  for (const std::string shape :
       {R"({type: mesh, file: "meshes/inside.obj\0.txt"})",
        R"({type: hull, file: "meshes/inside.obj\0.txt"})",
        R"({type: sdf, sdf: {grid: {file: "meshes/inside.obj\0.txt", cell: 0.2}}})",
        R"({type: sdf, sdf: {neural: {file: "meshes/inside.obj\0.txt"}}})"}) {
    const std::string named = refusal(f.scene_with(shape));
    EXPECT_NE(named.find("scene.yaml:4:"), std::string::npos) << named;
    EXPECT_NE(named.find(".file'"), std::string::npos) << named;
    EXPECT_EQ(named.find(std::string(1, '\0')), std::string::npos) << named;
  }
  EXPECT_NE(refusal("").find("(an empty file name): cannot open scene file"), std::string::npos);
}

// A file past the size limit (1 GiB) is refused before it is read, whether the scene itself, a
// mesh, a hull's points or an OpenVDB volume; a sparse file stands in for a large one.
TEST(SceneFiles, AFileLargerThanTheLimitIsRefusedBeforeItIsRead) {
  const Folders folders;
  const fs::path big = folders.scene_dir / "big.obj";
  write(big, kTetrahedron);
  fs::resize_file(big, (std::uintmax_t(1) << 30) + 1);
  for (const std::string shape : {"{type: mesh, file: big.obj}", "{type: hull, file: big.obj}"}) {
    const std::string message = refusal(folders.scene_with(shape));
    EXPECT_NE(message.find("larger than the limit of 1 GiB"), std::string::npos) << message;
    EXPECT_NE(message.find("1073741825 bytes"), std::string::npos) << message;
  }
  const fs::path vdb = folders.scene_dir / "big.vdb";
  write(vdb, "");
  fs::resize_file(vdb, (std::uintmax_t(1) << 30) + 1);
  const std::string vdb_message =
      refusal(folders.scene_with("{type: sdf, sdf: {grid: {file: big.vdb}}}, density: 1000"));
  // Without OpenVDB the build refuses .vdb files for that reason first.
  EXPECT_TRUE(vdb_message.find("larger than the limit of 1 GiB") != std::string::npos ||
              vdb_message.find("needs a build with OpenVDB") != std::string::npos)
      << vdb_message;
  const fs::path scene = folders.scene_dir / "huge.yaml";
  write(scene, "world: {dt: 0.01}\n");
  fs::resize_file(scene, (std::uintmax_t(1) << 30) + 1);
  const std::string scene_message = refusal(scene);
  EXPECT_NE(scene_message.find("larger than the limit of 1 GiB"), std::string::npos)
      << scene_message;
}

}  // namespace
}  // namespace tumble
