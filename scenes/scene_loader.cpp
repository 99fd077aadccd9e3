// The YAML scene loader. yaml-cpp's parser turns the text into events and a small tree is built
// from them; everything after that is ours: every field is read through a handful of strict readers
// (number, integer, boolean, name, list of numbers, map of known fields) that know the field's
// path, unit and allowed range, so that each mistake becomes one SceneError with file, line, column
// and a message that says what was expected. The reference for every field is docs/scene-format.md;
// keep the two in step.
#include "scenes/scene_loader.hpp"

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "scenes/yaml_reader.hpp"
#include "tumble/model.hpp"

namespace tumble {
namespace scene_yaml {
namespace {

constexpr std::array<std::string_view, 5> kTopKeys{"world", "materials", "bodies", "camera",
                                                   "randomize"};

}  // namespace

Scene Loader::load(std::string_view text) {
  // The shape cache is keyed by the nodes of one document.
  loaded_shapes_.clear();
  DocumentBuilder doc;
  const Node& root = parse(text, doc, "bodies");
  YAML::Mark start;  // line 0, column 0: the start of the text
  start.line = 0;
  start.column = 0;
  const Fields top =
      read_map(root, mark_or(root, start), "",
               "a map with the fields world, materials, bodies, camera and randomize", false);
  check_known(top, kTopKeys);

  Scene scene;
  scene.source = source_;
  load_world(top.find("world"), scene.world);
  load_materials(top.find("materials"), scene.materials);
  load_bodies(top, scene);
  load_randomize(top.find("randomize"), scene.randomize);
  if (const Entry* x = top.find("camera")) {
    scene.camera = load_camera(*x);
  }
  // The check every scene passes, from a file or from code (tumble/model.hpp): the fields above
  // were read against the same table, so this finds only what no single field shows.
  check_scene(scene);
  return scene;
}

}  // namespace scene_yaml

using scene_yaml::Loader;
using scene_yaml::read_file;
using scene_yaml::yaml_syntax_error;

Scene load_scene_string(std::string_view yaml, std::string_view source_name) {
  const std::string source(source_name);
  try {
    return Loader(source).load(yaml);
  } catch (const SceneError&) {
    throw;
  } catch (const YAML::Exception& e) {
    // Parser errors carry yaml-cpp's own position and message; keep both.
    throw yaml_syntax_error(e, source);
  } catch (const std::exception& e) {
    // The contract is that callers only ever see SceneError (an allocation failure on a huge
    // file included).
    throw SceneError(source, 0, 0, "", std::string("cannot load scene: ") + e.what());
  } catch (...) {
    throw SceneError(source, 0, 0, "", "cannot load scene: unknown error");
  }
}

Scene load_scene_file(const std::filesystem::path& path) {
  const std::string source = path.string();
  std::string text;
  try {
    text = read_file(path, source);
  } catch (const SceneError&) {
    throw;
  } catch (const std::exception& e) {
    throw SceneError(source, 0, 0, "", std::string("cannot open scene file (") + e.what() + ")");
  }
  return load_scene_string(text, source);
}

}  // namespace tumble
