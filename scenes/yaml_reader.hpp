// The YAML scene reader's machinery, shared by the files that read each part of a scene
// (world_section.cpp, body_section.cpp, shape_section.cpp, query_file.cpp) and scene_loader.cpp:
// the document tree, the text helpers, the map of a section's fields, and the Loader whose strict
// readers know each field's path, unit and range (engine/scene_limits.hpp). Private to
// tumble_scenes, like yaml-cpp itself.
#pragma once

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <array>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "collision/sdf/neural_sdf.hpp"
#include "collision/sdf/sdf_tree.hpp"
#include "engine/printable_text.hpp"
#include "engine/scene_limits.hpp"
#include "scenes/query_file.hpp"
#include "scenes/scene_loader.hpp"
#include "scenes/sweep_file.hpp"
#include "tumble/error.hpp"
#include "tumble/scene.hpp"

namespace tumble::scene_yaml {

using Keys = std::span<const std::string_view>;
using namespace scene_limits;

// The document tree. yaml-cpp's parser reports events and the tree is built here instead of with
// YAML::Load/LoadAll, for three reasons: LoadAll can loop forever on malformed input (see
// Loader::parse), yaml-cpp's node graph takes several times the memory of this one (a
// 100,000-body scene needs 1.2 GB as YAML::Node), and its map iterators hand out proxies that
// are easy to leave dangling. Marks are the ones yaml-cpp's own builder would record.

struct Node {
  enum class Kind : std::uint8_t { null, scalar, sequence, map };
  // How a scalar was written. Quoted and !!str scalars are strings even when they look like
  // numbers or booleans.
  enum class Style : std::uint8_t { plain, quoted, string_tag, other_tag };

  Kind kind = Kind::null;
  Style style = Style::plain;
  YAML::Mark mark;
  std::string scalar;
  std::vector<const Node*> items;  // sequence items; map keys and values, alternating

  bool is_null() const { return kind == Kind::null; }
  bool is_scalar() const { return kind == Kind::scalar; }
  bool is_sequence() const { return kind == Kind::sequence; }
  bool is_map() const { return kind == Kind::map; }
  bool is_string() const { return style == Style::quoted || style == Style::string_tag; }
  std::size_t size() const { return kind == Kind::map ? items.size() / 2 : items.size(); }
};

class DocumentBuilder final : public YAML::EventHandler {
 public:
  std::deque<Node> nodes;          // owns every node; a deque never moves its elements
  std::vector<const Node*> roots;  // one per document
  std::vector<YAML::Mark> starts;  // where each document starts

  void OnDocumentStart(const YAML::Mark& mark) override {
    starts.push_back(mark);
    open_.clear();
    anchors_.clear();  // anchors are local to their document
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    add(mark, anchor, Node::Kind::null);
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    // Aliases share the anchored node, as in yaml-cpp: no copies, so alias chains cost nothing.
    if (anchor >= anchors_.size() || anchors_[anchor] == nullptr) {
      throw YAML::ParserException(mark, "alias to an undefined anchor");
    }
    attach(anchors_[anchor]);
  }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                const std::string& value) override {
    Node& n = add(mark, anchor, Node::Kind::scalar);
    n.scalar = value;
    // yaml-cpp tags plain scalars "?" and quoted ones "!"; explicit tags arrive resolved.
    if (tag == "?") {
      n.style = Node::Style::plain;
    } else if (tag == "!") {
      n.style = Node::Style::quoted;
    } else if (tag == "tag:yaml.org,2002:str") {
      n.style = Node::Style::string_tag;
    } else {
      n.style = Node::Style::other_tag;
    }
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    open_.push_back(&add(mark, anchor, Node::Kind::sequence));
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    open_.push_back(&add(mark, anchor, Node::Kind::map));
  }
  void OnMapEnd() override { close(); }

 private:
  Node& add(const YAML::Mark& mark, YAML::anchor_t anchor, Node::Kind kind) {
    Node& n = nodes.emplace_back();
    n.kind = kind;
    n.mark = mark;
    if (anchor != YAML::NullAnchor) {
      if (anchor >= anchors_.size()) {
        anchors_.resize(anchor + 1, nullptr);
      }
      anchors_[anchor] = &n;
    }
    attach(&n);
    return n;
  }
  void attach(const Node* n) {
    if (open_.empty()) {
      roots.push_back(n);
    } else {
      open_.back()->items.push_back(n);
    }
  }
  void close() {
    if (!open_.empty()) {
      open_.pop_back();
    }
  }

  std::vector<Node*> open_;  // collections still being filled, innermost last
  std::vector<const Node*> anchors_;
};

enum class NumberStatus : std::uint8_t { ok, not_a_number, not_finite, out_of_range };

// Text helpers (yaml_reader.cpp).
std::string join(Keys keys);
bool contains(Keys keys, std::string_view key);
std::string index(const std::string& path, std::size_t i);
std::string fmt(Real v);
using tumble::printable;
std::string child(const std::string& path, std::string_view key);
std::string describe(const Node& n);
std::size_t edit_distance(std::string_view a, std::string_view b);
NumberStatus parse_number(const std::string& s, Real& out);

// A map read into entries in file order, with duplicate keys rejected (the parser keeps them, and
// yaml-cpp's own lookup would silently answer the first).

struct Entry {
  std::string key;
  YAML::Mark key_mark;
  const Node& value;

  // Where to point for a problem with the value. An empty value's own mark is the position of
  // the next token, often on a later line, so point at its key instead.
  YAML::Mark mark() const {
    if (value.is_null() || value.mark.line < 0) {
      return key_mark;
    }
    return value.mark;
  }
};

struct Fields {
  std::string path;
  YAML::Mark mark;  // of the map itself, for "missing field" messages
  std::vector<Entry> entries;

  const Entry* find(std::string_view key) const {
    for (const Entry& e : entries) {
      if (e.key == key) {
        return &e;
      }
    }
    return nullptr;
  }
};

// Materials by name, for bodies to look theirs up in constant time.
struct MaterialIndex {
  const std::vector<Material>& list;
  std::unordered_map<std::string, int> index;

  explicit MaterialIndex(const std::vector<Material>& materials) : list(materials) {
    for (std::size_t i = 0; i < materials.size(); ++i) {
      index.emplace(materials[i].name, static_cast<int>(i));
    }
  }
};

YAML::Mark mark_or(const Node& n, const YAML::Mark& fallback);

// yaml-cpp's exception as a SceneError naming `source`, the line and column, and what the parser
// found (nesting beyond its depth limit said as such, not as its "bad file").
SceneError yaml_syntax_error(const YAML::Exception& e, const std::string& source);

// Line 0, column 0: where messages about a whole document point.
inline YAML::Mark text_start() {
  YAML::Mark start;
  start.line = 0;
  start.column = 0;
  return start;
}

// `read()` (a Loader reading one text) with yaml-cpp's own errors turned into SceneError naming
// `source`, its line and column: the one wrapper every file kind's entry point shares.
template <class Read>
auto with_yaml_errors(const std::string& source, Read&& read) -> decltype(read()) {
  try {
    return read();
  } catch (const YAML::Exception& e) {
    throw yaml_syntax_error(e, source);
  }
}

// The whole of a scene or query file, or SceneError naming `source` and why it cannot be read.
std::string read_file(const std::filesystem::path& path, const std::string& source);

class Loader {
 public:
  explicit Loader(std::string source, const SceneLoadOptions& options = {})
      : source_(std::move(source)), options_(options) {}

  Scene load(std::string_view text, std::span<const FieldOverride> overrides = {});

 private:
  // `required` names the top-level field an empty document lacks ("bodies", "queries").
  const Node& parse(std::string_view text, DocumentBuilder& doc, std::string_view required) const;
  // `root` with `value` put at the dotted path `keys` (scene_loader.cpp, FieldOverride).
  const Node* with_field(const Node* node, std::span<const std::string> keys, std::size_t depth,
                         const Node* value, DocumentBuilder& doc) const;
  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& field,
                         const std::string& reason) const {
    const int line = mark.line >= 0 ? mark.line + 1 : 0;
    const int column = mark.line >= 0 ? mark.column + 1 : 0;
    throw SceneError(source_, line, column, field, reason);
  }

  Fields read_map(const Node& node, const YAML::Mark& mark, const std::string& path,
                  std::string_view what, bool null_is_empty) const;
  void check_known(const Fields& fields, Keys allowed) const;

  Real read_real(const Node& n, const YAML::Mark& mark, const std::string& path,
                 const RealSpec& spec) const;
  Real read_real(const Entry& e, const std::string& path, const RealSpec& spec) const {
    return read_real(e.value, e.mark(), path, spec);
  }
  std::int64_t read_int(const Entry& e, const std::string& path, const IntSpec& spec) const;
  bool read_bool(const Entry& e, const std::string& path) const;
  std::string read_word(const Entry& e, const std::string& path, std::string_view what) const;
  std::string read_name(const Entry& e, const std::string& path, std::string_view what) const;
  template <int N>
  Eigen::Matrix<Real, N, 1> read_vector(const Entry& e, const std::string& path,
                                        std::string_view layout, std::string_view unit,
                                        const RealSpec& spec) const;

  void load_world(const Entry* e, WorldSettings& world) const;
  void load_randomize(const Entry* e, Randomization& randomize) const;
  void load_materials(const Entry* e, std::vector<Material>& materials) const;
  void load_bodies(const Fields& top, Scene& scene) const;
  BodyDesc load_body(const Node& node, const YAML::Mark& mark, std::size_t i,
                     const MaterialIndex& materials, std::optional<YAML::Mark>& name_mark) const;
  // `centre_of_mass` receives where the shape's centre of mass lies in the frame it was given in
  // (hulls and compounds are re-centred there); zero for every other shape.
  // Cached by YAML node: every alias of a shape (`*hull`) is the shape loaded once, so a file of
  // thousands of aliases of one large hull runs Qhull once, and a shape reached again while it
  // is being loaded (an alias cycle) is an error.
  Shape load_shape(const Entry& e, const std::string& path, Vec3* centre_of_mass = nullptr) const;
  Shape build_shape(const Entry& e, const std::string& path, Vec3* centre_of_mass) const;
  Shape load_train_shape(const Entry& e, const std::string& path, const Shape& detailed,
                         const Vec3& centre_of_mass) const;
  Shape load_hull(const Fields& f, const std::string& path, Vec3* centre_of_mass) const;
  Shape load_mesh(const Fields& f, const std::string& path) const;
  Shape load_compound(const Fields& f, const std::string& path, Vec3* centre_of_mass) const;
  Quat read_orientation(const Entry& e, const std::string& path) const;
  Camera load_camera(const Entry& e) const;

 public:
  // `tumble query` files (scenes/query_file.hpp), parsed with the same shape reader.
  std::vector<ShapeQuery> load_queries(std::string_view text);
  // `tumble sweep` files (scenes/sweep_file.hpp).
  SweepSpec load_sweep(std::string_view text);
  // A signed distance field on its own (scenes/sdf_section.hpp).
  SdfNode load_sdf(std::string_view text);
  // A neural SDF's weights file (scenes/neural_sdf_file.hpp).
  NeuralSdfDescription load_neural(std::string_view text) const;
  // A shape on its own (load_shape_text, include/tumble/load_scene.hpp).
  Shape load_lone_shape(std::string_view text, Vec3* centre_of_mass);

 private:
  ShapeQuery load_query(const Node& node, const YAML::Mark& mark, std::size_t i) const;
  SweepAxis load_sweep_axis(const Entry& e) const;
  // A file the document names, relative to its folder, refused (at `mark`, as `field`) where it
  // lies outside that folder and the options do not allow it (SceneLoadOptions).
  std::filesystem::path referenced_file(const std::string& name, const YAML::Mark& mark,
                                        const std::string& field) const;
  SdfNode load_sdf_grid(const Fields& params, const std::string& here) const;
  SdfNode load_sdf_node(const Node& node, const YAML::Mark& mark, const std::string& path,
                        int depth) const;
  SweepPlace place_of(const YAML::Mark& mark) const;
  void load_placed_shape(const Entry& e, const std::string& path, Shape& shape, Transform& pose,
                         Vec3* velocity, Vec3* angular_velocity) const;

  std::string source_;
  SceneLoadOptions options_;
  struct LoadedShape {
    Shape shape;
    Vec3 centre_of_mass;
  };
  mutable std::unordered_map<const Node*, LoadedShape> loaded_shapes_;
  mutable std::unordered_set<const Node*> shapes_loading_;
};

template <int N>
Eigen::Matrix<Real, N, 1> Loader::read_vector(const Entry& e, const std::string& path,
                                              std::string_view layout, std::string_view unit,
                                              const RealSpec& spec) const {
  const Node& n = e.value;
  if (!n.is_sequence() || n.size() != static_cast<std::size_t>(N)) {
    fail(e.mark(), path,
         "expected a list of " + std::to_string(N) + " numbers " + std::string(layout) +
             (unit.empty() ? "" : " in " + std::string(unit)) + ", got " + describe(n));
  }
  Eigen::Matrix<Real, N, 1> v;
  for (int k = 0; k < N; ++k) {
    const Node& item = *n.items[static_cast<std::size_t>(k)];
    v[k] = read_real(item, mark_or(item, e.mark()), index(path, static_cast<std::size_t>(k)), spec);
  }
  return v;
}

}  // namespace tumble::scene_yaml
