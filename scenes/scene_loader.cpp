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
#include <new>
#include <optional>
#include <sstream>
#include <system_error>

#include "scenes/yaml_reader.hpp"
#include "tumble/model.hpp"

namespace tumble {
namespace scene_yaml {
namespace {

constexpr std::array<std::string_view, 5> kTopKeys{"world", "materials", "bodies", "camera",
                                                   "randomize"};

std::vector<std::string> split_path(const std::string& field) {
  std::vector<std::string> keys;
  std::size_t begin = 0;
  for (;;) {
    const std::size_t dot = field.find('.', begin);
    keys.push_back(field.substr(begin, dot - begin));
    if (dot == std::string::npos) {
      return keys;
    }
    begin = dot + 1;
  }
}

std::string joined(std::span<const std::string> keys, std::size_t count) {
  std::string path;
  for (std::size_t i = 0; i < count && i < keys.size(); ++i) {
    if (i > 0) {
      path += '.';
    }
    path += keys[i];
  }
  return path;
}

// The item of a list that a path component names: its index, or the item whose `name` it is.
std::optional<std::size_t> list_item(const Node& list, const std::string& key) {
  if (!key.empty() && key.find_first_not_of("0123456789") == std::string::npos && key.size() < 10) {
    const std::size_t i = std::stoul(key);
    if (i < list.items.size()) {
      return i;
    }
    return std::nullopt;
  }
  for (std::size_t i = 0; i < list.items.size(); ++i) {
    const Node& item = *list.items[i];
    if (!item.is_map()) {
      continue;
    }
    for (std::size_t k = 0; k + 1 < item.items.size(); k += 2) {
      if (item.items[k]->scalar == "name" && item.items[k + 1]->is_scalar() &&
          item.items[k + 1]->scalar == key) {
        return i;
      }
    }
  }
  return std::nullopt;
}

}  // namespace

// Copies the nodes on the path (never the ones beside it), so that a node reached through an
// alias from elsewhere keeps its value there.
const Node* Loader::with_field(const Node* node, std::span<const std::string> keys,
                               std::size_t depth, const Node* value, DocumentBuilder& doc) const {
  if (depth == keys.size()) {
    return value;
  }
  const std::string& key = keys[depth];
  const std::string here = joined(keys, depth);
  const std::string field = joined(keys, keys.size());
  if (key.empty()) {
    throw SceneError(source_, 0, 0, field, "a field path has an empty part");
  }
  Node& copy = doc.nodes.emplace_back();
  copy.mark.line = -1;  // not in the file: errors about it carry no position
  if (node == nullptr || node->is_null()) {
    copy.kind = Node::Kind::map;
  } else if (node->is_map() || node->is_sequence()) {
    copy = *node;
  } else {
    throw SceneError(source_, 0, 0, field,
                     "cannot set '" + key + "' inside '" + here + "', which is a value (" +
                         describe(*node) + "), not a map or a list");
  }
  if (copy.is_sequence()) {
    const std::optional<std::size_t> i = list_item(copy, key);
    if (!i) {
      throw SceneError(source_, 0, 0, field,
                       "the list '" + here + "' has no item '" + key + "' (it has " +
                           std::to_string(copy.items.size()) +
                           " items, counted from 0, or name one by its 'name')");
    }
    copy.items[*i] = with_field(copy.items[*i], keys, depth + 1, value, doc);
    return &copy;
  }
  for (std::size_t k = 0; k + 1 < copy.items.size(); k += 2) {
    if (copy.items[k]->is_scalar() && copy.items[k]->scalar == key) {
      copy.items[k + 1] = with_field(copy.items[k + 1], keys, depth + 1, value, doc);
      return &copy;
    }
  }
  Node& new_key = doc.nodes.emplace_back();
  new_key.kind = Node::Kind::scalar;
  new_key.mark.line = -1;
  new_key.scalar = key;
  copy.items.push_back(&new_key);
  copy.items.push_back(with_field(nullptr, keys, depth + 1, value, doc));
  return &copy;
}

Scene Loader::load(std::string_view text, std::span<const FieldOverride> overrides) {
  // The shape cache is keyed by the nodes of one document.
  loaded_shapes_.clear();
  DocumentBuilder doc;
  const Node* root_node = &parse(text, doc, "bodies");
  // Each value is a YAML document of its own; its nodes live as long as the scene's.
  std::deque<DocumentBuilder> values;
  for (const FieldOverride& o : overrides) {
    DocumentBuilder& v = values.emplace_back();
    try {
      std::istringstream in(o.value);
      YAML::Parser parser(in);
      parser.HandleNextDocument(v);
    } catch (const YAML::Exception& e) {
      throw SceneError(source_, 0, 0, o.field,
                       "the value '" + printable(o.value) + "' is not YAML (" + e.msg + ")");
    }
    if (v.roots.empty()) {
      throw SceneError(source_, 0, 0, o.field, "an empty value");
    }
    for (Node& n : v.nodes) {
      n.mark.line = -1;
    }
    root_node = with_field(root_node, split_path(o.field), 0, v.roots[0], doc);
  }
  const Node& root = *root_node;
  const YAML::Mark start = text_start();
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

Shape Loader::load_lone_shape(std::string_view text, Vec3* centre_of_mass) {
  loaded_shapes_.clear();
  DocumentBuilder doc;
  const Node& root = parse(text, doc, "type");
  const YAML::Mark start = text_start();
  const Entry whole{"shape", start, root};
  return load_shape(whole, "shape", centre_of_mass);
}

}  // namespace scene_yaml

using scene_yaml::Loader;

Shape load_shape_text(std::string_view yaml, std::string_view source_name, Vec3* centre_of_mass,
                      const SceneLoadOptions& options) {
  const std::string source(source_name);
  return scene_yaml::with_yaml_errors(
      source, [&] { return Loader(source, options).load_lone_shape(yaml, centre_of_mass); });
}
using scene_yaml::read_file;
using scene_yaml::yaml_syntax_error;

Scene load_scene_string(std::string_view yaml, std::string_view source_name) {
  return load_scene_string(yaml, source_name, {});
}

Scene load_scene_string(std::string_view yaml, std::string_view source_name,
                        std::span<const FieldOverride> overrides, const SceneLoadOptions& options) {
  const std::string source(source_name);
  try {
    return Loader(source, options).load(yaml, overrides);
  } catch (const SceneError&) {
    throw;
  } catch (const std::bad_alloc&) {
    // Running out of memory is not a fault of the file: callers report it as such (the command
    // line with its own exit code, Python as MemoryError).
    throw;
  } catch (const YAML::Exception& e) {
    // Parser errors carry yaml-cpp's own position and message; keep both.
    throw yaml_syntax_error(e, source);
  } catch (const std::exception& e) {
    // Anything else a library throws while loading is reported as a scene error.
    throw SceneError(source, 0, 0, "", std::string("cannot load scene: ") + e.what());
  } catch (...) {
    throw SceneError(source, 0, 0, "", "cannot load scene: unknown error");
  }
}

Scene load_scene_file(const std::filesystem::path& path) {
  return load_scene_file(path, {});
}

Scene load_scene_file(const std::filesystem::path& path, std::span<const FieldOverride> overrides,
                      const SceneLoadOptions& options) {
  // An empty name is said to be one, not left as a message that starts with ": ".
  const std::string source = path.empty() ? "(an empty file name)" : path.string();
  std::string text;
  try {
    text = read_file(path, source);
  } catch (const SceneError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw SceneError(source, 0, 0, "", std::string("cannot open scene file (") + e.what() + ")");
  }
  return load_scene_string(text, source, overrides, options);
}

}  // namespace tumble
