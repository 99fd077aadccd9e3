// The YAML scene loader. yaml-cpp's parser turns the text into events and a small tree is built
// from them; everything after that is ours: every field is read through a handful of strict readers
// (number, integer, boolean, name, list of numbers, map of known fields) that know the field's
// path, unit and allowed range, so that each mistake becomes one SceneError with file, line, column
// and a message that says what was expected. The reference for every field is docs/scene-format.md;
// keep the two in step.
#include "scenes/scene_loader.hpp"

#include "collision/convex_hull.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "collision/broad_phase_factory.hpp"
#include "collision/compound_shape.hpp"
#include "collision/triangle_mesh.hpp"
#include "engine/scene_limits.hpp"
#include "scenes/obj_reader.hpp"
#include "scenes/query_file.hpp"
#include "tumble/model.hpp"

namespace tumble {

namespace {

using Keys = std::span<const std::string_view>;

using namespace scene_limits;

// Field names per map. Order is the order messages list them in.
constexpr std::array<std::string_view, 4> kTopKeys{"world", "materials", "bodies", "camera"};
// clang-format off
constexpr std::array<std::string_view, 23> kWorldKeys{
    "gravity", "dt", "duration", "steps", "substeps", "max_substeps", "solver", "iterations",
    "relax_iterations", "broadphase", "ccd", "contact_recycling", "contact_margin",
    "penetration_slop", "contact_hertz", "sag_tolerance", "contact_damping_ratio",
    "max_push_velocity", "restitution_threshold", "sleeping", "sleep_speed", "sleep_time",
    "threads"};
// clang-format on
constexpr std::array<std::string_view, 4> kMaterialKeys{"friction", "restitution", "stiffness",
                                                        "damping"};
constexpr std::array<std::string_view, 13> kBodyKeys{
    "name", "shape",   "position", "orientation", "velocity", "angular_velocity",  //
    "mass", "density", "inertia",  "material",    "static",   "kinematic",        "fast"};
constexpr std::array<std::string_view, 3> kCameraKeys{"position", "target", "fov"};
constexpr std::array<std::string_view, 2> kSphereKeys{"type", "radius"};
constexpr std::array<std::string_view, 2> kBoxKeys{"type", "half_extents"};
constexpr std::array<std::string_view, 3> kCapsuleKeys{"type", "radius", "half_length"};
constexpr std::array<std::string_view, 1> kPlaneKeys{"type"};
constexpr std::array<std::string_view, 3> kCylinderKeys{"type", "radius", "half_length"};
constexpr std::array<std::string_view, 3> kHullKeys{"type", "points", "file"};
constexpr std::array<std::string_view, 4> kMeshKeys{"type", "vertices", "triangles", "file"};
constexpr std::array<std::string_view, 2> kCompoundKeys{"type", "parts"};
constexpr std::array<std::string_view, 3> kPartKeys{"shape", "position", "orientation"};
constexpr IntSpec kVertexIndex{"a vertex index", "0 to the number of vertices - 1", 0,
                               std::int64_t(1) << 31};

// Shape names the scene format reserves for later (docs/scene-format.md, "Shapes"); they get "not
// implemented yet" rather than "unknown".
constexpr std::array<std::string_view, 1> kPlannedShapes{"sdf"};

// ---------------------------------------------------------------------------------------------
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

// ---------------------------------------------------------------------------------------------
// Text helpers.

std::string join(Keys keys) {
  std::string s;
  for (std::string_view k : keys) {
    if (!s.empty()) {
      s += ", ";
    }
    s += k;
  }
  return s;
}

bool contains(Keys keys, std::string_view key) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

std::string index(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

// Shortest text that reads back to the same double.
std::string fmt(Real v) {
  std::array<char, 64> buf{};
  const auto result = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), result.ptr);
}

// A value as the user wrote it, made safe for a one-line message: control bytes escaped, long
// text cut.
std::string printable(std::string_view s) {
  constexpr std::size_t kMax = 60;
  std::string out;
  for (std::size_t i = 0; i < s.size() && i < kMax; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 || c == 0x7f) {
      constexpr std::string_view hex = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    } else {
      out += static_cast<char>(c);
    }
  }
  if (s.size() > kMax) {
    out += "...";
  }
  return out;
}

// The path of a field in a map. Keys come from the file and may hold anything, so they are made
// printable: a field path must never break the one-line message.
std::string child(const std::string& path, std::string_view key) {
  const std::string k = printable(key);
  return path.empty() ? k : path + "." + k;
}

// What a node holds, for the "got ..." end of a message.
std::string describe(const Node& n) {
  switch (n.kind) {
    case Node::Kind::null:
      return "nothing (an empty value)";
    case Node::Kind::sequence:
      return n.size() == 0
                 ? std::string("an empty list")
                 : "a list of " + std::to_string(n.size()) + (n.size() == 1 ? " item" : " items");
    case Node::Kind::map:
      return n.size() == 0 ? "an empty map" : "a map";
    case Node::Kind::scalar:
      // Say so when it was quoted: a quoted number is a string.
      if (n.style == Node::Style::quoted) {
        return "the quoted string \"" + printable(n.scalar) + "\"";
      }
      return printable(n.scalar);
  }
  return "an undefined value";
}

// Edit distance for "did you mean" hints; field names are short, so O(n m) is nothing.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) {
    row[j] = j;
  }
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

enum class NumberStatus : std::uint8_t { ok, not_a_number, not_finite, out_of_range };

// Strict YAML 1.2 core-schema decimal: [-+]? (.[0-9]+ | [0-9]+(.[0-9]*)?) ([eE][-+]?[0-9]+)?
// yaml-cpp's own conversion goes through a stringstream and accepts more than this (and quietly
// maps .nan and .inf), so numbers are parsed here. Hex, octal and '_' separators are rejected.
NumberStatus parse_number(const std::string& s, Real& out) {
  std::size_t j = 0;
  // Advances j over a run of digits and says how many there were.
  const auto skip_digits = [&] {
    const std::size_t start = j;
    while (j < s.size() && s[j] >= '0' && s[j] <= '9') {
      ++j;
    }
    return j - start;
  };
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) {
    j = 1;
  }
  std::string rest = s.substr(j);
  std::transform(rest.begin(), rest.end(), rest.begin(), [](char c) {
    return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;
  });
  if (rest == ".inf" || rest == "inf" || rest == "infinity" || rest == ".nan" || rest == "nan") {
    return NumberStatus::not_finite;
  }
  std::size_t mantissa_digits = skip_digits();
  if (j < s.size() && s[j] == '.') {
    ++j;
    mantissa_digits += skip_digits();
  }
  if (mantissa_digits == 0) {
    return NumberStatus::not_a_number;
  }
  if (j < s.size() && (s[j] == 'e' || s[j] == 'E')) {
    ++j;
    if (j < s.size() && (s[j] == '+' || s[j] == '-')) {
      ++j;
    }
    if (skip_digits() == 0) {
      return NumberStatus::not_a_number;
    }
  }
  if (j != s.size()) {
    return NumberStatus::not_a_number;
  }
  // from_chars is locale-independent but takes no leading '+'.
  const char* first = s.data() + (s[0] == '+' ? 1 : 0);
  const char* last = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(first, last, out);
  if (ec == std::errc::result_out_of_range) {
    return NumberStatus::out_of_range;
  }
  if (ec != std::errc() || ptr != last) {
    return NumberStatus::not_a_number;
  }
  if (!std::isfinite(out)) {
    return NumberStatus::not_finite;
  }
  return NumberStatus::ok;
}

// ---------------------------------------------------------------------------------------------
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

YAML::Mark mark_or(const Node& n, const YAML::Mark& fallback) {
  if (n.is_null() || n.mark.line < 0) {
    return fallback;
  }
  return n.mark;
}

class Loader {
 public:
  explicit Loader(std::string source) : source_(std::move(source)) {}

  Scene load(std::string_view text);

 private:
  const Node& parse(std::string_view text, DocumentBuilder& doc) const;
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
  void load_materials(const Entry* e, std::vector<Material>& materials) const;
  void load_bodies(const Fields& top, Scene& scene) const;
  BodyDesc load_body(const Node& node, const YAML::Mark& mark, std::size_t i,
                     const MaterialIndex& materials, std::optional<YAML::Mark>& name_mark) const;
  // `centre_of_mass` receives where the shape's centre of mass lies in the frame it was given in
  // (hulls and compounds are re-centred there); zero for every other shape.
  Shape load_shape(const Entry& e, const std::string& path, Vec3* centre_of_mass = nullptr) const;
  Shape load_hull(const Fields& f, const std::string& path, Vec3* centre_of_mass) const;
  Shape load_mesh(const Fields& f, const std::string& path) const;
  Shape load_compound(const Fields& f, const std::string& path, Vec3* centre_of_mass) const;
  Quat read_orientation(const Entry& e, const std::string& path) const;
  Camera load_camera(const Entry& e) const;

 public:
  // `tumble query` files (scenes/query_file.hpp), parsed with the same shape reader.
  std::vector<ShapeQuery> load_queries(std::string_view text);

 private:
  ShapeQuery load_query(const Node& node, const YAML::Mark& mark, std::size_t i) const;
  void load_placed_shape(const Entry& e, const std::string& path, Shape& shape, Transform& pose,
                         Vec3* velocity, Vec3* angular_velocity) const;

  std::string source_;
};

Fields Loader::read_map(const Node& node, const YAML::Mark& mark, const std::string& path,
                        std::string_view what, bool null_is_empty) const {
  Fields fields;
  fields.path = path;
  fields.mark = mark_or(node, mark);
  if (node.is_null() && null_is_empty) {
    return fields;
  }
  if (!node.is_map()) {
    fail(mark, path, "expected " + std::string(what) + ", got " + describe(node));
  }
  fields.entries.reserve(node.size());
  // Index of each key seen so far: a generated file may hold very many materials.
  std::unordered_map<std::string, std::size_t> seen;
  for (std::size_t i = 0; i + 1 < node.items.size(); i += 2) {
    const Node& key = *node.items[i];
    const Node& value = *node.items[i + 1];
    const YAML::Mark key_mark = mark_or(key, fields.mark);
    if (!key.is_scalar()) {
      fail(key_mark, path, "expected a field name, got " + describe(key) + " as a key");
    }
    const std::string& name = key.scalar;
    const auto [first, inserted] = seen.try_emplace(name, fields.entries.size());
    if (!inserted) {
      fail(key_mark, child(path, name),
           "duplicate field '" + printable(name) + "' (first given on line " +
               std::to_string(fields.entries[first->second].key_mark.line + 1) + ")");
    }
    fields.entries.push_back({name, key_mark, value});
  }
  return fields;
}

void Loader::check_known(const Fields& fields, Keys allowed) const {
  for (const Entry& e : fields.entries) {
    if (contains(allowed, e.key)) {
      continue;
    }
    const std::string where = fields.path.empty() ? "at the top level" : "in " + fields.path;
    std::string reason =
        "unknown field '" + printable(e.key) + "' " + where + "; expected one of: " + join(allowed);
    if (e.key == "<<") {
      reason += " (YAML merge keys '<<' are not supported; write the fields out)";
    } else {
      // A near miss is almost always a typo of a real field.
      std::string_view best;
      std::size_t best_distance = 3;
      for (std::string_view k : allowed) {
        const std::size_t d = edit_distance(e.key, k);
        if (d < best_distance) {
          best_distance = d;
          best = k;
        }
      }
      if (!best.empty()) {
        reason += " (did you mean '" + std::string(best) + "'?)";
      }
    }
    fail(e.key_mark, child(fields.path, e.key), reason);
  }
}

Real Loader::read_real(const Node& n, const YAML::Mark& mark, const std::string& path,
                       const RealSpec& spec) const {
  // Built only on failure: a scene can hold millions of numbers.
  const auto reject = [&](std::string_view why) {
    std::string reason = "expected " + std::string(spec.what);
    if (!spec.range.empty()) {
      reason += " (" + std::string(spec.range) + ")";
    }
    fail(mark, path, reason + ", got " + describe(n) + std::string(why));
  };
  // Quoted or !!str-tagged scalars are strings even when they look like numbers.
  if (!n.is_scalar() || n.is_string()) {
    reject("");
  }
  Real v = 0;
  switch (parse_number(n.scalar, v)) {
    case NumberStatus::ok:
      break;
    case NumberStatus::not_a_number:
      reject("");
      break;
    case NumberStatus::not_finite:
      reject(", which is not a finite number");
      break;
    case NumberStatus::out_of_range:
      reject(", which is too large or too small for a double");
      break;
  }
  if (v < spec.lo || v > spec.hi || (spec.lo_open && v == spec.lo)) {
    reject("");
  }
  return v;
}

std::int64_t Loader::read_int(const Entry& e, const std::string& path, const IntSpec& spec) const {
  // Parsed as a real first so that 1e6 is accepted as the integer it is; 2.5 is not.
  const Real v = read_real(e, path, RealSpec{spec.what, spec.range, -kInf, kInf});
  const auto reject = [&](std::string_view why) {
    fail(e.mark(), path,
         "expected " + std::string(spec.what) + " (" + std::string(spec.range) + "), got " +
             describe(e.value) + std::string(why));
  };
  if (std::floor(v) != v) {
    reject(", which is not an integer");
  }
  // Compared as reals before the cast, so an absurd count never overflows the conversion.
  if (v < static_cast<Real>(spec.lo) || v > static_cast<Real>(spec.hi)) {
    reject("");
  }
  return static_cast<std::int64_t>(v);
}

bool Loader::read_bool(const Entry& e, const std::string& path) const {
  // Only the YAML 1.2 core spellings: 'yes', 'on' and 'y' are YAML 1.1 booleans that yaml-cpp
  // would accept, and 'n' for 'no' (the Norway problem) is exactly the surprise to avoid.
  const Node& n = e.value;
  if (n.is_scalar() && !n.is_string()) {
    const std::string& s = n.scalar;
    if (s == "true" || s == "True" || s == "TRUE") {
      return true;
    }
    if (s == "false" || s == "False" || s == "FALSE") {
      return false;
    }
  }
  fail(e.mark(), path, "expected true or false, got " + describe(n));
}

std::string Loader::read_word(const Entry& e, const std::string& path,
                              std::string_view what) const {
  if (!e.value.is_scalar() || e.value.scalar.empty()) {
    fail(e.mark(), path, "expected " + std::string(what) + ", got " + describe(e.value));
  }
  return e.value.scalar;
}

std::string Loader::read_name(const Entry& e, const std::string& path,
                              std::string_view what) const {
  const std::string name = read_word(e, path, what);
  // Body names go unquoted into the trajectory CSV and into one-line messages.
  const bool clean = std::none_of(name.begin(), name.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u < 0x20 || u == 0x7f || c == ',' || c == '"';
  });
  if (!clean || name.size() > kMaxNameLength) {
    fail(e.mark(), path,
         "expected " + std::string(what) +
             " of at most 256 bytes without commas, double quotes or control characters "
             "(names are written unquoted to CSV), got " +
             describe(e.value));
  }
  return name;
}

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

// ---------------------------------------------------------------------------------------------
// Sections.

void Loader::load_world(const Entry* e, WorldSettings& w) const {
  if (e == nullptr) {
    return;
  }
  const Fields f = read_map(e->value, e->mark(), "world", "a map of world settings", true);
  check_known(f, kWorldKeys);
  const auto path = [](std::string_view key) { return child("world", key); };

  if (const Entry* x = f.find("gravity")) {
    w.gravity = read_vector<3>(*x, path("gravity"), "[x, y, z]", "m/s^2", kAcceleration);
  }
  if (const Entry* x = f.find("dt")) {
    w.dt = read_real(*x, path("dt"), kTimeStep);
  }
  const Entry* duration = f.find("duration");
  const Entry* steps = f.find("steps");
  if (duration != nullptr && steps != nullptr) {
    fail(steps->key_mark, path("steps"),
         "give either duration or steps, not both (duration is on line " +
             std::to_string(duration->key_mark.line + 1) + ")");
  }
  if (duration != nullptr) {
    w.duration = read_real(*duration, path("duration"), kDuration);
  }
  if (steps != nullptr) {
    w.steps = read_int(*steps, path("steps"), kSteps);
    // Keep duration consistent with the steps actually run, for summaries that print it.
    w.duration = static_cast<Real>(*w.steps) * w.dt;
  } else {
    // The run length is ceil(duration / dt): bound it like an explicit step count.
    const Real n = std::ceil(w.duration / w.dt);
    if (!(n <= static_cast<Real>(kMaxSteps))) {
      const Entry* culprit = duration != nullptr ? duration : f.find("dt");
      const YAML::Mark where = culprit != nullptr ? culprit->mark() : f.mark;
      fail(where, path(culprit != nullptr ? culprit->key : "dt"),
           "duration / dt gives " + fmt(n) +
               " steps; at most 1e9 are allowed (raise dt or shorten duration)");
    }
  }
  if (const Entry* x = f.find("substeps")) {
    w.substeps = static_cast<int>(read_int(*x, path("substeps"), kSubsteps));
  }
  if (const Entry* x = f.find("max_substeps")) {
    w.max_substeps = static_cast<int>(read_int(*x, path("max_substeps"), kSubsteps));
  }
  if (const Entry* x = f.find("solver")) {
    const std::string s = read_word(*x, path("solver"), "a solver name (impulse, penalty)");
    if (s == "impulse") {
      w.solver = SolverType::impulse;
    } else if (s == "penalty") {
      w.solver = SolverType::penalty;
    } else {
      fail(x->mark(), path("solver"),
           "expected one of: impulse, penalty, got " + describe(x->value));
    }
  }
  if (const Entry* x = f.find("iterations")) {
    w.iterations = static_cast<int>(read_int(*x, path("iterations"), kIterations));
  }
  if (const Entry* x = f.find("relax_iterations")) {
    w.relax_iterations = static_cast<int>(read_int(*x, path("relax_iterations"), kRelaxIterations));
  }
  if (const Entry* x = f.find("broadphase")) {
    const std::string s = read_word(*x, path("broadphase"), "a broad phase name");
    if (const auto type = parse_broad_phase(s)) {
      w.broadphase = *type;
    } else {
      fail(x->mark(), path("broadphase"),
           "expected one of: auto, brute, sap, hash, bvh, lbvh, octree, kdtree, grid, hgrid, "
           "got " +
               describe(x->value));
    }
  }

  if (const Entry* x = f.find("ccd")) {
    // Read as a word: YAML 1.1 would turn the bare on/off into booleans, but the text is kept.
    const std::string s = read_word(*x, path("ccd"), "one of: auto, on, off");
    if (s == "auto") {
      w.ccd = CcdMode::automatic;
    } else if (s == "on") {
      w.ccd = CcdMode::on;
    } else if (s == "off") {
      w.ccd = CcdMode::off;
    } else {
      fail(x->mark(), path("ccd"), "expected one of: auto, on, off, got " + describe(x->value));
    }
  }
  if (const Entry* x = f.find("contact_recycling")) {
    w.contact_recycling = read_bool(*x, path("contact_recycling"));
  }
  if (const Entry* x = f.find("contact_margin")) {
    w.contact_margin = read_real(*x, path("contact_margin"), kDistance);
  }
  if (const Entry* x = f.find("penetration_slop")) {
    w.penetration_slop = read_real(*x, path("penetration_slop"), kDistance);
  }
  if (const Entry* x = f.find("contact_hertz")) {
    if (x->value.kind == Node::Kind::scalar && x->value.scalar == "auto")
      w.contact_hertz.reset();
    else
      w.contact_hertz = read_real(*x, path("contact_hertz"), kFrequency);
  }
  if (const Entry* x = f.find("threads")) {
    if (x->value.kind == Node::Kind::scalar && x->value.scalar == "auto")
      w.threads = 0;
    else
      w.threads = static_cast<int>(read_int(*x, path("threads"), kThreads));
  }
  if (const Entry* x = f.find("sag_tolerance")) {
    w.sag_tolerance = read_real(*x, path("sag_tolerance"), kSagTolerance);
  }
  if (const Entry* x = f.find("contact_damping_ratio")) {
    w.contact_damping_ratio = read_real(*x, path("contact_damping_ratio"), kDampingRatio);
  }
  if (const Entry* x = f.find("max_push_velocity")) {
    w.max_push_velocity = read_real(*x, path("max_push_velocity"), kPushSpeed);
  }
  if (const Entry* x = f.find("restitution_threshold")) {
    w.restitution_threshold = read_real(*x, path("restitution_threshold"), kSpeedThreshold);
  }
  if (const Entry* x = f.find("sleeping")) {
    w.sleeping = read_bool(*x, path("sleeping"));
  }
  if (const Entry* x = f.find("sleep_speed")) {
    w.sleep_speed = read_real(*x, path("sleep_speed"), kPushSpeed);
  }
  if (const Entry* x = f.find("sleep_time")) {
    w.sleep_time = read_real(*x, path("sleep_time"), kDuration);
  }
}

void Loader::load_materials(const Entry* e, std::vector<Material>& materials) const {
  materials.clear();
  materials.push_back(Material{"default", Real(0.5), 0, 1e6, 1e3});
  if (e == nullptr) {
    return;
  }
  const Fields f =
      read_map(e->value, e->mark(), "materials",
               "a map from material names to {friction, restitution, stiffness, damping}", true);
  for (const Entry& m : f.entries) {
    const std::string path = child("materials", m.key);
    Node key;  // the name as a node, so that it reads like any other value
    key.kind = Node::Kind::scalar;
    key.mark = m.key_mark;
    key.scalar = m.key;
    const Entry name_entry{m.key, m.key_mark, key};
    const std::string name = read_name(name_entry, path, "a material name");
    const Fields props = read_map(m.value, m.mark(), path, "a map {friction, restitution}", false);
    check_known(props, kMaterialKeys);
    Material mat;
    mat.name = name;
    if (const Entry* x = props.find("friction")) {
      mat.friction = read_real(*x, child(path, "friction"), kFriction);
    }
    if (const Entry* x = props.find("restitution")) {
      mat.restitution = read_real(*x, child(path, "restitution"), kRestitution);
    }
    if (const Entry* x = props.find("stiffness")) {
      mat.stiffness = read_real(*x, child(path, "stiffness"), kStiffness);
    }
    if (const Entry* x = props.find("damping")) {
      mat.damping = read_real(*x, child(path, "damping"), kDamping);
    }
    // `default` keeps slot 0 so that a body without a material needs no lookup.
    if (name == "default") {
      materials[0] = mat;
    } else {
      materials.push_back(mat);
    }
  }
}

Shape Loader::load_shape(const Entry& e, const std::string& path, Vec3* centre_of_mass) const {
  if (centre_of_mass != nullptr)
    *centre_of_mass = Vec3::Zero();
  const Fields f = read_map(e.value, e.mark(), path,
                            "a map describing a shape, such as {type: sphere, radius: 0.5}", false);
  const Entry* type = f.find("type");
  if (type == nullptr) {
    fail(f.mark, child(path, "type"),
         "missing required field 'type'; expected one of: sphere, box, capsule, plane, cylinder, "
         "hull, mesh, compound");
  }
  const std::string t = read_word(*type, child(path, "type"), "a shape type");
  const auto require = [&](std::string_view key, std::string_view what) -> const Entry& {
    const Entry* x = f.find(key);
    if (x == nullptr) {
      fail(f.mark, child(path, key),
           "missing required field '" + std::string(key) + "' (" + std::string(what) + ")");
    }
    return *x;
  };
  if (t == "sphere") {
    check_known(f, kSphereKeys);
    const Entry& r = require("radius", "the sphere's radius in metres");
    return Shape::sphere(read_real(r, child(path, "radius"), kSize));
  }
  if (t == "box") {
    check_known(f, kBoxKeys);
    const Entry& h = require("half_extents", "half the box's size along x, y, z in metres");
    return Shape::box(read_vector<3>(h, child(path, "half_extents"), "[x, y, z]", "metres", kSize));
  }
  if (t == "capsule") {
    check_known(f, kCapsuleKeys);
    const Entry& r = require("radius", "the capsule's radius in metres");
    const Entry& h = require("half_length", "half the length of the core segment in metres");
    const Real radius = read_real(r, child(path, "radius"), kSize);
    return Shape::capsule(radius, read_real(h, child(path, "half_length"), kHalfLength));
  }
  if (t == "plane") {
    check_known(f, kPlaneKeys);
    return Shape::plane();
  }
  if (t == "cylinder") {
    check_known(f, kCylinderKeys);
    const Entry& r = require("radius", "the cylinder's radius in metres");
    const Entry& h =
        require("half_length", "half the cylinder's height along its local z in metres");
    const Real radius = read_real(r, child(path, "radius"), kSize);
    return Shape::cylinder(radius, read_real(h, child(path, "half_length"), kSize));
  }
  if (t == "hull") {
    check_known(f, kHullKeys);
    return load_hull(f, path, centre_of_mass);
  }
  if (t == "mesh") {
    check_known(f, kMeshKeys);
    return load_mesh(f, path);
  }
  if (t == "compound") {
    check_known(f, kCompoundKeys);
    return load_compound(f, path, centre_of_mass);
  }
  if (contains(kPlannedShapes, t)) {
    fail(type->mark(), child(path, "type"),
         "shape type '" + t +
             "' is not implemented yet; available: sphere, box, capsule, plane, cylinder, hull, "
             "mesh, compound");
  }
  fail(type->mark(), child(path, "type"),
       "expected one of: sphere, box, capsule, plane, cylinder, hull, mesh, compound, got " +
           describe(type->value));
}

// A convex hull from `points: [[x, y, z], ...]` or `file: X.obj` (only the OBJ's "v x y z" vertex
// lines are read, by the minimal parser below; faces are ignored since the hull is rebuilt by
// Qhull). The path is relative to the scene file's directory. Degenerate points (fewer than 4,
// flat, needle, coincident) are refused with Qhull-free messages from ConvexHull.
Shape Loader::load_hull(const Fields& f, const std::string& path, Vec3* centre_of_mass) const {
  const Entry* points_entry = f.find("points");
  const Entry* file_entry = f.find("file");
  if ((points_entry == nullptr) == (file_entry == nullptr)) {
    fail(f.mark, child(path, "points"),
         "a hull needs exactly one of 'points' (a list of [x, y, z]) or 'file' (an OBJ file)");
  }
  std::vector<Vec3> points;
  const Entry& where = points_entry != nullptr ? *points_entry : *file_entry;
  const std::string field = child(path, points_entry != nullptr ? "points" : "file");
  if (points_entry != nullptr) {
    const Node& n = points_entry->value;
    if (!n.is_sequence()) {
      fail(where.mark(), field, "expected a list of points [x, y, z], got " + describe(n));
    }
    for (std::size_t i = 0; i < n.size(); ++i) {
      const Node& item = *n.items[i];
      const Entry point{index(field, i), mark_or(item, where.mark()), item};
      points.push_back(read_vector<3>(point, index(field, i), "[x, y, z]", "metres", kCoordinate));
    }
  } else {
    const std::string name = read_word(*file_entry, field, "an OBJ file name");
    const std::filesystem::path file = std::filesystem::path(source_).parent_path() / name;
    std::ifstream in(file);
    if (!in) {
      fail(where.mark(), field, "cannot open OBJ file '" + file.string() + "'");
    }
    std::string line;
    int line_number = 0;
    while (std::getline(in, line)) {
      ++line_number;
      if (line.size() < 2 || line[0] != 'v' || (line[1] != ' ' && line[1] != '\t')) {
        continue;  // only vertex lines matter for a hull
      }
      std::istringstream fields(line.substr(2));
      Vec3 p;
      if (!(fields >> p.x() >> p.y() >> p.z()) || !p.allFinite()) {
        fail(where.mark(), field,
             "OBJ file '" + file.string() + "' line " + std::to_string(line_number) +
                 ": expected 'v x y z' with three finite numbers, got '" + line + "'");
      }
      points.push_back(p);
    }
  }
  try {
    auto hull = std::make_shared<const ConvexHull>(ConvexHull::from_points(points));
    if (centre_of_mass != nullptr)
      *centre_of_mass = hull->centre_of_mass_offset();
    return Shape::convex_hull(std::move(hull));
  } catch (const DegenerateHullError& e) {
    fail(where.mark(), field, e.what());
  }
}

Quat Loader::read_orientation(const Entry& x, const std::string& path) const {
  const Eigen::Matrix<Real, 4, 1> q = read_vector<4>(x, path, "[w, x, y, z]", "", kQuatComponent);
  if (!(std::abs(q.norm() - 1) <= kQuatTolerance)) {
    fail(x.mark(), path,
         "expected a unit quaternion [w, x, y, z] (norm within 1e-6 of 1), got norm " +
             fmt(q.norm()));
  }
  return Quat(q[0], q[1], q[2], q[3]).normalized();
}

// A static triangle mesh: inline `vertices` and `triangles`, or an OBJ `file` (read by
// obj_reader.hpp, relative to the scene file's folder).
Shape Loader::load_mesh(const Fields& f, const std::string& path) const {
  const Entry* file = f.find("file");
  const Entry* vertices = f.find("vertices");
  const Entry* triangles = f.find("triangles");
  std::vector<Vec3> points;
  std::vector<TriangleMesh::Triangle> faces;
  const Entry* blame = nullptr;  // where a MeshError points
  if (file != nullptr) {
    for (const Entry* x : {vertices, triangles}) {
      if (x != nullptr) {
        fail(x->key_mark, child(path, x->key),
             "give either 'file' or 'vertices' and 'triangles', not both (file is on line " +
                 std::to_string(file->key_mark.line + 1) + ")");
      }
    }
    const std::string name = read_name(*file, child(path, "file"), "an OBJ file name");
    std::filesystem::path obj(name);
    if (obj.is_relative())
      obj = std::filesystem::path(source_).parent_path() / obj;
    try {
      ObjMesh m = read_obj_file(obj);
      points = std::move(m.vertices);
      faces = std::move(m.triangles);
    } catch (const ObjError& error) {
      fail(file->mark(), child(path, "file"), error.what());
    }
    blame = file;
  } else {
    if (vertices == nullptr || triangles == nullptr) {
      fail(f.mark, child(path, vertices == nullptr ? "vertices" : "triangles"),
           "a mesh needs 'vertices' ([[x, y, z], ...] in metres) and 'triangles' ([[i, j, k], "
           "...], 0-based, counter-clockwise seen from the front), or 'file' (an OBJ file)");
    }
    const std::string vpath = child(path, "vertices");
    const std::string tpath = child(path, "triangles");
    if (!vertices->value.is_sequence() || vertices->value.size() < 3) {
      fail(vertices->mark(), vpath,
           "expected a list of at least 3 vertices [x, y, z], got " + describe(vertices->value));
    }
    if (!triangles->value.is_sequence() || triangles->value.size() < 1) {
      fail(triangles->mark(), tpath,
           "expected a list of at least 1 triangle [i, j, k], got " + describe(triangles->value));
    }
    for (std::size_t i = 0; i < vertices->value.items.size(); ++i) {
      const Node& item = *vertices->value.items[i];
      const Entry entry{"", mark_or(item, vertices->mark()), item};
      points.push_back(read_vector<3>(entry, index(vpath, i), "[x, y, z]", "metres", kCoordinate));
    }
    for (std::size_t i = 0; i < triangles->value.items.size(); ++i) {
      const Node& item = *triangles->value.items[i];
      const std::string ipath = index(tpath, i);
      const YAML::Mark mark = mark_or(item, triangles->mark());
      if (!item.is_sequence() || item.size() != 3) {
        fail(mark, ipath,
             "expected a triangle [i, j, k] of 3 vertex indices, got " + describe(item));
      }
      TriangleMesh::Triangle t{};
      for (std::size_t k = 0; k < 3; ++k) {
        const Node& v = *item.items[k];
        const Entry entry{"", mark_or(v, mark), v};
        const std::int64_t value = read_int(entry, index(ipath, k), kVertexIndex);
        if (value >= std::int64_t(points.size())) {
          fail(entry.mark(), index(ipath, k),
               "vertex index " + std::to_string(value) + " is out of range: the mesh has " +
                   std::to_string(points.size()) + " vertices (indices 0 to " +
                   std::to_string(points.size() - 1) + ")");
        }
        t[k] = std::int32_t(value);
      }
      faces.push_back(t);
    }
    blame = triangles;
  }
  try {
    return Shape::triangle_mesh(std::make_shared<const TriangleMesh>(
        TriangleMesh::build(std::move(points), std::move(faces))));
  } catch (const MeshError& error) {
    fail(blame->mark(), child(path, blame->key), error.what());
  }
}

// A compound: parts [{shape, position, orientation}], each a bounded convex shape.
Shape Loader::load_compound(const Fields& f, const std::string& path, Vec3* centre_of_mass) const {
  const Entry* parts = f.find("parts");
  const std::string ppath = child(path, "parts");
  if (parts == nullptr) {
    fail(f.mark, ppath,
         "missing required field 'parts' (a list of {shape, position, orientation})");
  }
  if (!parts->value.is_sequence() || parts->value.size() < 1 ||
      parts->value.size() > std::size_t(CompoundShape::kMaxParts)) {
    fail(parts->mark(), ppath,
         "expected a list of 1 to " + std::to_string(CompoundShape::kMaxParts) +
             " parts {shape, position, orientation}, got " + describe(parts->value));
  }
  std::vector<CompoundPart> list;
  for (std::size_t i = 0; i < parts->value.items.size(); ++i) {
    const Node& item = *parts->value.items[i];
    const std::string at = index(ppath, i);
    const Fields pf = read_map(item, mark_or(item, parts->mark()), at,
                               "a part {shape, position, orientation}", false);
    check_known(pf, kPartKeys);
    const Entry* shape = pf.find("shape");
    if (shape == nullptr) {
      fail(pf.mark, child(at, "shape"), "missing required field 'shape'");
    }
    CompoundPart part;
    Vec3 part_centre = Vec3::Zero();
    part.shape = load_shape(*shape, child(at, "shape"), &part_centre);
    if (!part.shape.is_bounded() || part.shape.type == ShapeType::mesh ||
        part.shape.type == ShapeType::compound) {
      fail(shape->mark(), child(at, "shape"),
           "a compound part must be a sphere, box, capsule, cylinder or hull, got " +
               std::string(shape_type_name(part.shape.type)));
    }
    if (const Entry* x = pf.find("position")) {
      part.pose.translation =
          read_vector<3>(*x, child(at, "position"), "[x, y, z]", "metres", kCoordinate);
    }
    if (const Entry* x = pf.find("orientation")) {
      part.pose.rotation = read_orientation(*x, child(at, "orientation"));
    }
    part.pose.translation += part.pose.rotation * part_centre;  // a hull part stays put
    list.push_back(part);
  }
  try {
    Vec3 com = Vec3::Zero();
    Shape s = Shape::compound_of(
        std::make_shared<const CompoundShape>(CompoundShape::build(std::move(list), &com)));
    if (centre_of_mass != nullptr)
      *centre_of_mass = com;
    return s;
  } catch (const CompoundError& error) {
    fail(parts->mark(), ppath, error.what());
  }
}

// `name_mark` is set when the body names itself; uniqueness is the caller's business.
BodyDesc Loader::load_body(const Node& node, const YAML::Mark& mark, std::size_t i,
                           const MaterialIndex& materials,
                           std::optional<YAML::Mark>& name_mark) const {
  const std::string path = index("bodies", i);
  const Fields f = read_map(node, mark, path, "a map describing a body", false);
  check_known(f, kBodyKeys);
  const auto at = [&](std::string_view key) { return child(path, key); };
  BodyDesc b;
  if (const Entry* x = f.find("name")) {
    b.name = read_name(*x, at("name"), "a body name");
    name_mark = x->mark();
  } else {
    b.name = "body" + std::to_string(i);
    name_mark.reset();
  }

  const Entry* shape = f.find("shape");
  if (shape == nullptr) {
    fail(f.mark, at("shape"),
         "missing required field 'shape', such as {type: sphere, radius: 0.5}");
  }
  Vec3 centre_of_mass = Vec3::Zero();
  b.shape = load_shape(*shape, at("shape"), &centre_of_mass);

  const Entry* is_static = f.find("static");
  if (is_static != nullptr) {
    b.is_static = read_bool(*is_static, at("static"));
  }
  const Entry* kinematic = f.find("kinematic");
  if (kinematic != nullptr) {
    b.kinematic = read_bool(*kinematic, at("kinematic"));
    if (b.kinematic && b.is_static)
      fail(kinematic->mark(), at("kinematic"),
           "a body is static or kinematic, not both; remove one of them");
    if (b.kinematic && (!b.shape.is_bounded() || b.shape.type == ShapeType::mesh))
      fail(kinematic->mark(), at("kinematic"),
           std::string("a ") + (b.shape.is_bounded() ? "triangle mesh" : "plane") +
               " can only be static");
  }
  if (const Entry* x = f.find("fast")) {
    b.fast = read_bool(*x, at("fast"));
  }
  if (!b.shape.is_bounded() && !b.is_static) {
    const YAML::Mark where = is_static != nullptr ? is_static->mark() : shape->mark();
    fail(where, at("static"),
         "a plane is infinite, so it has no finite mass and must be static; add 'static: true'");
  }
  if (b.shape.type == ShapeType::mesh && !b.is_static) {
    const YAML::Mark where = is_static != nullptr ? is_static->mark() : shape->mark();
    fail(where, at("static"),
         "a triangle mesh is a surface without a solid inside for collision, so it must be "
         "static; add 'static: true' (use a compound of boxes, spheres or capsules for a moving "
         "body)");
  }

  if (const Entry* x = f.find("position")) {
    b.position = read_vector<3>(*x, at("position"), "[x, y, z]", "metres", kCoordinate);
  }
  if (const Entry* x = f.find("orientation")) {
    const Eigen::Matrix<Real, 4, 1> q =
        read_vector<4>(*x, at("orientation"), "[w, x, y, z]", "", kQuatComponent);
    const Real norm = q.norm();
    // A quaternion typed by hand with few digits is caught here rather than silently
    // renormalised, since a wrong component usually means a wrong rotation, not rounding.
    if (!(std::abs(norm - 1) <= kQuatTolerance)) {
      fail(
          x->mark(), at("orientation"),
          "expected a unit quaternion [w, x, y, z] (norm within 1e-6 of 1), got norm " + fmt(norm));
    }
    b.orientation = Quat(q[0], q[1], q[2], q[3]);
    b.orientation.normalize();
  }
  // Hulls and compounds are re-centred at their centre of mass: move the body there so the
  // shape stays where the scene put it.
  b.position += b.orientation * centre_of_mass;
  const auto check_still = [&](const Entry& x, const Vec3& v, std::string_view what) {
    if (b.is_static && !v.isZero(0)) {
      fail(x.mark(), at(x.key),
           "a static body never moves, so its " + std::string(what) +
               " must be zero or absent, got [" + fmt(v.x()) + ", " + fmt(v.y()) + ", " +
               fmt(v.z()) + "]");
    }
  };
  if (const Entry* x = f.find("velocity")) {
    b.velocity = read_vector<3>(*x, at("velocity"), "[x, y, z]", "m/s", kVelocity);
    check_still(*x, b.velocity, "velocity");
  }
  if (const Entry* x = f.find("angular_velocity")) {
    b.angular_velocity =
        read_vector<3>(*x, at("angular_velocity"), "[x, y, z]", "rad/s", kAngularVelocity);
    check_still(*x, b.angular_velocity, "angular velocity");
  }

  const Entry* mass = f.find("mass");
  const Entry* density = f.find("density");
  const Entry* inertia = f.find("inertia");
  if (b.is_static || b.kinematic) {
    for (const Entry* x : {mass, density, inertia}) {
      if (x != nullptr) {
        fail(x->key_mark, at(x->key),
             std::string(b.is_static ? "static" : "kinematic") +
                 " bodies have no mass (it is infinite); remove '" + x->key + "' or set '" +
                 (b.is_static ? "static" : "kinematic") + ": false'");
      }
    }
  } else {
    if (mass != nullptr && density != nullptr) {
      fail(density->key_mark, at("density"),
           "give either mass or density, not both (mass is on line " +
               std::to_string(mass->key_mark.line + 1) + ")");
    }
    if (mass != nullptr) {
      b.mass = read_real(*mass, at("mass"), kMass);
    } else {
      const Real rho =
          density != nullptr ? read_real(*density, at("density"), kDensity) : kDefaultDensity;
      b.mass = rho * volume(b.shape);
      // Sizes and density are each bounded, but their product can still leave the mass range.
      if (!(b.mass >= kMinMass && b.mass <= kMaxMass)) {
        const Entry* culprit = density != nullptr ? density : shape;
        fail(culprit->mark(), at(culprit->key),
             "density " + fmt(rho) + " kg/m^3 times the shape's volume " + fmt(volume(b.shape)) +
                 " m^3 gives a mass of " + fmt(b.mass) +
                 " kg; expected a mass of 1e-12 to 1e15 kg");
      }
    }
    if (inertia != nullptr) {
      const Vec3 m = read_vector<3>(*inertia, at("inertia"), "[Ixx, Iyy, Izz]", "kg m^2", kMoment);
      // Principal moments of any real mass distribution obey the triangle inequality; a
      // tensor that does not is unphysical and makes the solver gain energy.
      const Real tol = 1e-9 * m.sum();
      if (m.x() > m.y() + m.z() + tol || m.y() > m.x() + m.z() + tol ||
          m.z() > m.x() + m.y() + tol) {
        fail(inertia->mark(), at("inertia"),
             "principal moments must satisfy the triangle inequality (each at most the sum of "
             "the other two), got [" +
                 fmt(m.x()) + ", " + fmt(m.y()) + ", " + fmt(m.z()) + "]");
      }
      b.inertia = m.asDiagonal();
    } else {
      b.inertia = b.mass * unit_inertia(b.shape);
    }
  }

  if (const Entry* x = f.find("material")) {
    const std::string name = read_word(*x, at("material"), "a material name");
    const auto found = materials.index.find(name);
    if (found == materials.index.end()) {
      std::string defined;
      for (const Material& m : materials.list) {
        defined += (defined.empty() ? "" : ", ") + m.name;
      }
      fail(x->mark(), at("material"),
           "undefined material '" + printable(name) + "'; defined: " + defined);
    }
    b.material = found->second;
  }
  return b;
}

void Loader::load_bodies(const Fields& top, Scene& scene) const {
  const Entry* e = top.find("bodies");
  if (e == nullptr) {
    fail(top.mark, "bodies", "missing required field 'bodies' (a list of at least one body)");
  }
  const Node& list = e->value;
  if (!list.is_sequence() || list.size() == 0) {
    fail(e->mark(), "bodies", "expected a non-empty list of bodies, got " + describe(list));
  }
  if (list.size() > kMaxBodies) {
    fail(e->mark(), "bodies",
         "expected at most 1000000 bodies, got " + std::to_string(list.size()));
  }
  struct NameUse {
    std::size_t body;
    bool is_default;
  };
  std::unordered_map<std::string, NameUse> names;
  const MaterialIndex materials(scene.materials);
  scene.bodies.reserve(list.size());
  for (std::size_t i = 0; i < list.items.size(); ++i) {
    const Node& node = *list.items[i];
    const YAML::Mark mark = mark_or(node, e->mark());
    std::optional<YAML::Mark> name_mark;
    BodyDesc body = load_body(node, mark, i, materials, name_mark);
    const auto [used, inserted] = names.try_emplace(body.name, NameUse{i, !name_mark});
    if (!inserted) {
      const std::string other = "bodies[" + std::to_string(used->second.body) + "]";
      const std::string path = child(index("bodies", i), "name");
      if (!name_mark) {
        fail(mark, path,
             "the default name '" + body.name + "' is already used by " + other +
                 "; give this body a name");
      }
      fail(*name_mark, path,
           "duplicate body name '" + printable(body.name) + "', already used by " + other +
               (used->second.is_default ? " (its default name)" : ""));
    }
    scene.bodies.push_back(std::move(body));
  }
}

Camera Loader::load_camera(const Entry& e) const {
  const Fields f = read_map(e.value, e.mark(), "camera", "a map {position, target, fov}", true);
  check_known(f, kCameraKeys);
  Camera c;
  if (const Entry* x = f.find("position")) {
    c.position = read_vector<3>(*x, "camera.position", "[x, y, z]", "metres", kCoordinate);
  }
  if (const Entry* x = f.find("target")) {
    c.target = read_vector<3>(*x, "camera.target", "[x, y, z]", "metres", kCoordinate);
  }
  if (const Entry* x = f.find("fov")) {
    c.fov = read_real(*x, "camera.fov", kFov);
  }
  if (c.position == c.target) {
    const Entry* x = f.find("target") != nullptr ? f.find("target") : f.find("position");
    const YAML::Mark where = x != nullptr ? x->mark() : f.mark;
    fail(where, "camera.target",
         "the camera's target equals its position, so it has no view direction");
  }
  return c;
}

// Parses the text into `doc` and returns the root of its one document. yaml-cpp 0.7 can get
// stuck on some malformed input such as a lone ',' (jbeder/yaml-cpp#1040, fixed upstream after
// 0.8 by PR #1319): it reports an empty document without consuming the offending token, again
// and again, and LoadAll allocates until the process is killed. So documents are read here, at
// most three, and one that starts where the previous one did means the parser is stuck.
const Node& Loader::parse(std::string_view text, DocumentBuilder& doc) const {
  std::istringstream in{std::string(text)};
  YAML::Parser parser(in);
  // A third document is read only to tell a stuck parser from a genuine second document.
  while (doc.starts.size() < 3 && parser.HandleNextDocument(doc)) {
  }
  for (std::size_t i = 1; i < doc.starts.size(); ++i) {
    const YAML::Mark& mark = doc.starts[i];
    if (mark.pos == doc.starts[i - 1].pos) {
      const auto at = static_cast<std::size_t>(mark.pos);
      const std::string token = at < text.size() ? printable(text.substr(at, 1)) : "end of input";
      fail(mark, "", "YAML syntax error: unexpected '" + token + "'");
    }
  }
  if (doc.starts.size() > 1) {
    fail(doc.starts[1], "",
         "the file holds more than one YAML document ('---'); a scene file holds exactly one");
  }
  if (doc.roots.empty() || doc.roots[0]->is_null()) {
    fail(YAML::Mark(), "bodies",
         "missing required field 'bodies' (the file holds no YAML document, or an empty one)");
  }
  return *doc.roots[0];
}

Scene Loader::load(std::string_view text) {
  DocumentBuilder doc;
  const Node& root = parse(text, doc);
  YAML::Mark start;  // line 0, column 0: the start of the text
  start.line = 0;
  start.column = 0;
  const Fields top = read_map(root, mark_or(root, start), "",
                              "a map with the fields world, materials, bodies and camera", false);
  check_known(top, kTopKeys);

  Scene scene;
  scene.source = source_;
  load_world(top.find("world"), scene.world);
  load_materials(top.find("materials"), scene.materials);
  load_bodies(top, scene);
  if (const Entry* x = top.find("camera")) {
    scene.camera = load_camera(*x);
  }
  // The check every scene passes, from a file or from code (tumble/model.hpp): the fields above
  // were read against the same table, so this finds only what no single field shows.
  check_scene(scene);
  return scene;
}

std::string read_file(const std::filesystem::path& path, const std::string& source) {
  const auto cannot_open = [&](const std::string& why) {
    return SceneError(source, 0, 0, "", "cannot open scene file (" + why + ")");
  };
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec) {
    throw cannot_open(ec.message());
  }
  if (status.type() == std::filesystem::file_type::not_found) {
    throw cannot_open(std::make_error_code(std::errc::no_such_file_or_directory).message());
  }
  if (status.type() == std::filesystem::file_type::directory) {
    throw cannot_open(std::make_error_code(std::errc::is_a_directory).message());
  }
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw cannot_open(errno != 0 ? std::generic_category().message(errno) : "unreadable");
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    throw cannot_open("read error");
  }
  return text.str();
}

}  // namespace

Scene load_scene_string(std::string_view yaml, std::string_view source_name) {
  const std::string source(source_name);
  try {
    return Loader(source).load(yaml);
  } catch (const SceneError&) {
    throw;
  } catch (const YAML::Exception& e) {
    // Parser errors carry yaml-cpp's own position and message; keep both.
    const int line = e.mark.line >= 0 ? e.mark.line + 1 : 0;
    const int column = e.mark.line >= 0 ? e.mark.column + 1 : 0;
    throw SceneError(source, line, column, "", "YAML syntax error: " + e.msg);
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

// ---------------------------------------------------------------------------------------------
// `tumble query` files: self-contained, so other kinds of query (time of impact) add a kind
// and their fields here without touching the scene format.
namespace tumble {
namespace {

constexpr std::array<std::string_view, 1> kQueryTopKeys{"queries"};
constexpr std::array<std::string_view, 7> kQueryKeys{"name",   "kind", "margin", "duration",
                                                     "method", "a",    "b"};
constexpr std::array<std::string_view, 3> kPlacedShapeKeys{"shape", "position", "orientation"};
constexpr std::array<std::string_view, 5> kMovingShapeKeys{"shape", "position", "orientation",
                                                           "velocity", "angular_velocity"};
constexpr RealSpec kQueryMargin{"a margin in metres", "0 to 1e6", 0, 1e6};
constexpr RealSpec kQueryDuration{"a duration in seconds", "greater than 0, at most 1e6", 0, 1e6,
                                  true};

}  // namespace

// velocity and angular_velocity are read only when the query moves its shapes (kind toi); for
// the other kinds they are unknown fields.
void Loader::load_placed_shape(const Entry& e, const std::string& path, Shape& shape,
                               Transform& pose, Vec3* velocity, Vec3* angular_velocity) const {
  const Fields f =
      read_map(e.value, e.mark(), path, "a placed shape {shape, position, orientation}", false);
  if (velocity != nullptr) {
    check_known(f, kMovingShapeKeys);
    if (const Entry* x = f.find("velocity")) {
      *velocity = read_vector<3>(*x, child(path, "velocity"), "[x, y, z]", "m/s", kVelocity);
    }
    if (const Entry* x = f.find("angular_velocity")) {
      *angular_velocity = read_vector<3>(*x, child(path, "angular_velocity"), "[x, y, z]", "rad/s",
                                         kAngularVelocity);
    }
  } else {
    check_known(f, kPlacedShapeKeys);
  }
  const Entry* s = f.find("shape");
  if (s == nullptr) {
    fail(f.mark, child(path, "shape"),
         "missing required field 'shape', such as {type: sphere, radius: 0.5}");
  }
  Vec3 centre_of_mass = Vec3::Zero();
  shape = load_shape(*s, child(path, "shape"), &centre_of_mass);
  pose = Transform{};
  if (const Entry* x = f.find("position")) {
    pose.translation =
        read_vector<3>(*x, child(path, "position"), "[x, y, z]", "metres", kCoordinate);
  }
  if (const Entry* x = f.find("orientation")) {
    pose.rotation = read_orientation(*x, child(path, "orientation"));
  }
  pose.translation += pose.rotation * centre_of_mass;  // a hull or compound stays put
}

ShapeQuery Loader::load_query(const Node& node, const YAML::Mark& mark, std::size_t i) const {
  const std::string path = index("queries", i);
  const Fields f = read_map(node, mark, path, "a query {name, a, b}", false);
  check_known(f, kQueryKeys);
  ShapeQuery q;
  q.name = "query" + std::to_string(i);
  if (const Entry* x = f.find("name")) {
    q.name = read_name(*x, child(path, "name"), "a query name");
  }
  if (const Entry* x = f.find("kind")) {
    const std::string kind = read_word(*x, child(path, "kind"), "a query kind");
    if (kind == "contact") {
      q.kind = QueryKind::contact;
    } else if (kind == "toi") {
      q.kind = QueryKind::toi;
    } else {
      fail(x->mark(), child(path, "kind"), "expected one of: contact, toi, got '" + kind + "'");
    }
  }
  if (const Entry* x = f.find("margin")) {
    q.margin = read_real(*x, child(path, "margin"), kQueryMargin);
  }
  const bool moving = q.kind == QueryKind::toi;
  if (const Entry* x = f.find("duration")) {
    if (!moving) {
      fail(x->mark(), child(path, "duration"), "'duration' is only read by queries of kind: toi");
    }
    q.duration = read_real(*x, child(path, "duration"), kQueryDuration);
  }
  const Entry* method = f.find("method");
  if (method != nullptr) {
    if (!moving) {
      fail(method->mark(), child(path, "method"), "'method' is only read by queries of kind: toi");
    }
    const std::string m = read_word(*method, child(path, "method"), "a time-of-impact method");
    if (m == "advancement") {
      q.method = ToiMethod::advancement;
    } else if (m == "sat") {
      q.method = ToiMethod::sat;
    } else {
      fail(method->mark(), child(path, "method"),
           "expected one of: advancement, sat, got '" + m + "'");
    }
  }
  for (const char* side : {"a", "b"}) {
    const Entry* x = f.find(side);
    if (x == nullptr) {
      fail(f.mark, child(path, side),
           std::string("missing required field '") + side +
               "' (a placed shape {shape, position, orientation})");
    }
    if (side[0] == 'a') {
      load_placed_shape(*x, child(path, side), q.a, q.pose_a, moving ? &q.velocity_a : nullptr,
                        moving ? &q.angular_velocity_a : nullptr);
    } else {
      load_placed_shape(*x, child(path, side), q.b, q.pose_b, moving ? &q.velocity_b : nullptr,
                        moving ? &q.angular_velocity_b : nullptr);
    }
  }
  auto polytope = [](const Shape& shape) {
    return shape.type == ShapeType::box || shape.type == ShapeType::hull;
  };
  if (q.method == ToiMethod::sat && !(polytope(q.a) && polytope(q.b))) {
    fail(method->mark(), child(path, "method"),
         "method sat needs a box or hull on both sides, got " +
             std::string(shape_type_name(q.a.type)) + " and " +
             std::string(shape_type_name(q.b.type)));
  }
  return q;
}

std::vector<ShapeQuery> Loader::load_queries(std::string_view text) {
  DocumentBuilder doc;
  const Node& root = parse(text, doc);
  YAML::Mark start;
  start.line = 0;
  start.column = 0;
  const Fields top =
      read_map(root, mark_or(root, start), "", "a map with the field queries", false);
  check_known(top, kQueryTopKeys);
  const Entry* e = top.find("queries");
  if (e == nullptr) {
    fail(top.mark, "queries", "missing required field 'queries' (a list of at least one query)");
  }
  if (!e->value.is_sequence() || e->value.size() == 0) {
    fail(e->mark(), "queries", "expected a non-empty list of queries, got " + describe(e->value));
  }
  std::vector<ShapeQuery> queries;
  for (std::size_t i = 0; i < e->value.items.size(); ++i) {
    const Node& node = *e->value.items[i];
    queries.push_back(load_query(node, mark_or(node, e->mark()), i));
  }
  return queries;
}

std::vector<ShapeQuery> load_query_string(std::string_view yaml, std::string_view source_name) {
  Loader loader{std::string(source_name)};
  return loader.load_queries(yaml);
}

std::vector<ShapeQuery> load_query_file(const std::filesystem::path& path) {
  const std::string source = path.string();
  const std::string text = read_file(path, source);
  return load_query_string(text, source);
}

}  // namespace tumble
