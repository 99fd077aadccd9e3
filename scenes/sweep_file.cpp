// `tumble sweep` files, read with the scene loader's strict readers so that a mistake names the
// file, line, column and field like a scene's does.
#include "scenes/sweep_file.hpp"

#include <charconv>
#include <cmath>

#include "scenes/scene_files.hpp"
#include "scenes/yaml_reader.hpp"

namespace tumble {

std::string SweepPlace::text() const {
  if (line <= 0) {
    return file;
  }
  return file + ":" + std::to_string(line) + ":" + std::to_string(column);
}

std::string sweep_number_text(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

namespace scene_yaml {
namespace {

constexpr std::array<std::string_view, 6> kSweepKeys{"scene", "duration",  "vary",
                                                     "seeds", "reference", "trajectory"};
constexpr std::array<std::string_view, 4> kRangeKeys{"from", "to", "count", "scale"};
constexpr RealSpec kSweepDuration{"a duration in seconds", "greater than 0, at most 1e9", 0, 1e9,
                                  true};
constexpr RealSpec kRangeEnd{"a finite number", "finite", -1e300, 1e300};
constexpr IntSpec kRangeCount{"a whole number of values", "1 to 1e6", 1, 1000000};
constexpr IntSpec kSeedCount{"a whole number of seeds", "1 to 1e6", 1, 1000000};
constexpr IntSpec kSeed{"a seed", "0 to 2^53", 0, std::int64_t(1) << 53};
constexpr double kMaxRuns = 1e6;

// The YAML text of a node, as flow style: the scene loader parses it back to the same node.
std::string node_text(const Node& n) {
  switch (n.kind) {
    case Node::Kind::null:
      return "null";
    case Node::Kind::scalar: {
      // A plain scalar goes back as written unless it holds a character that would end it
      // inside a flow collection ({name: steel, polished} would read as two fields).
      if (!n.is_string() && n.scalar.find_first_of(",[]{}#:") == std::string::npos) {
        return n.scalar;
      }
      std::string quoted = "\"";
      for (const char c : n.scalar) {
        if (c == '"' || c == '\\') {
          quoted += '\\';
        }
        quoted += c;
      }
      quoted += '"';
      return quoted;
    }
    case Node::Kind::sequence: {
      std::string s = "[";
      for (std::size_t i = 0; i < n.items.size(); ++i) {
        s += i > 0 ? ", " : "";
        s += node_text(*n.items[i]);
      }
      s += "]";
      return s;
    }
    case Node::Kind::map: {
      std::string s = "{";
      for (std::size_t i = 0; i + 1 < n.items.size(); i += 2) {
        s += i > 0 ? ", " : "";
        s += node_text(*n.items[i]);
        s += ": ";
        s += node_text(*n.items[i + 1]);
      }
      s += "}";
      return s;
    }
  }
  return "null";
}

}  // namespace

SweepPlace Loader::place_of(const YAML::Mark& mark) const {
  SweepPlace p;
  p.file = source_;
  p.line = mark.line >= 0 ? mark.line + 1 : 0;
  p.column = mark.line >= 0 ? mark.column + 1 : 0;
  return p;
}

SweepAxis Loader::load_sweep_axis(const Entry& e) const {
  SweepAxis axis;
  axis.field = e.key;
  axis.place = place_of(e.key_mark);
  const std::string path = child("vary", e.key);
  if (e.key.empty() || e.key.front() == '.' || e.key.back() == '.' ||
      e.key.find("..") != std::string::npos) {
    fail(e.key_mark, path, "expected a dotted field path such as world.dt");
  }
  if (e.value.is_sequence()) {
    if (e.value.items.empty()) {
      fail(e.mark(), path, "an empty list of values: a sweep axis needs at least one");
    }
    for (const Node* item : e.value.items) {
      axis.values.push_back(node_text(*item));
      axis.places.push_back(place_of(mark_or(*item, e.mark())));
    }
    return axis;
  }
  if (!e.value.is_map()) {
    fail(e.mark(), path,
         "expected a list of values or a range {from, to, count}, got " + describe(e.value));
  }
  const Fields f = read_map(e.value, e.mark(), path, "a range {from, to, count, scale}", false);
  check_known(f, kRangeKeys);
  for (const char* key : {"from", "to", "count"}) {
    if (f.find(key) == nullptr) {
      fail(f.mark, child(path, key),
           std::string("missing required field '") + key + "' of the range {from, to, count}");
    }
  }
  const Real from = read_real(*f.find("from"), child(path, "from"), kRangeEnd);
  const Real to = read_real(*f.find("to"), child(path, "to"), kRangeEnd);
  const Entry& count_entry = *f.find("count");
  const Real count_value = read_real(count_entry, child(path, "count"), kRangeEnd);
  if (count_value < 1 && std::floor(count_value) == count_value) {
    fail(count_entry.mark(), child(path, "count"),
         "an empty range (count " + describe(count_entry.value) +
             "): a sweep axis needs at least one value");
  }
  const auto count = read_int(count_entry, child(path, "count"), kRangeCount);
  bool log_scale = false;
  if (const Entry* x = f.find("scale")) {
    const std::string scale = read_word(*x, child(path, "scale"), "a scale");
    if (scale == "log") {
      log_scale = true;
    } else if (scale != "linear") {
      fail(x->mark(), child(path, "scale"), "expected one of: linear, log, got '" + scale + "'");
    }
    if (log_scale && !(from > 0 && to > 0)) {
      fail(x->mark(), child(path, "scale"),
           "a log range needs from and to greater than 0, got " + fmt(from) + " and " + fmt(to));
    }
  }
  for (std::int64_t k = 0; k < count; ++k) {
    // The ends are exact (one value is `from`); the points between are spaced evenly (in the
    // logarithm for log).
    const double t = count == 1 ? 0.0 : static_cast<double>(k) / static_cast<double>(count - 1);
    double v = from;
    if (k > 0 && k == count - 1) {
      v = to;
    } else if (k > 0) {
      v = log_scale ? std::exp(std::log(from) + t * (std::log(to) - std::log(from)))
                    : from + t * (to - from);
    }
    axis.values.push_back(sweep_number_text(v));
    axis.places.push_back(place_of(e.mark()));
  }
  return axis;
}

SweepSpec Loader::load_sweep(std::string_view text) {
  DocumentBuilder doc;
  const Node& root = parse(text, doc, "scene");
  const YAML::Mark start = text_start();
  const Fields top = read_map(root, mark_or(root, start), "",
                              "a map with the fields scene, duration, vary, seeds, reference and "
                              "trajectory",
                              false);
  check_known(top, kSweepKeys);
  SweepSpec spec;
  spec.source = source_;
  const Entry* scene = top.find("scene");
  if (scene == nullptr) {
    fail(top.mark, "scene", "missing required field 'scene' (the scene file to vary)");
  }
  const std::string scene_text = read_name(*scene, "scene", "a scene file path");
  // Like the scene a command line names: the study's own input, not a file a scene reads
  // behind it (the scene's own files follow SceneLoadOptions when it is loaded).
  spec.scene = file_beside(source_, scene_text);
  if (const Entry* x = top.find("duration")) {
    spec.duration = read_real(*x, "duration", kSweepDuration);
  }
  const Entry* vary = top.find("vary");
  if (vary == nullptr) {
    fail(top.mark, "vary", "missing required field 'vary' (a map from field paths to values)");
  }
  const Fields axes = read_map(vary->value, vary->mark(), "vary",
                               "a map from field paths (world.dt) to lists or ranges", false);
  if (axes.entries.empty()) {
    fail(vary->mark(), "vary", "expected at least one field to vary");
  }
  double runs = 1;
  for (const Entry& e : axes.entries) {
    spec.axes.push_back(load_sweep_axis(e));
    runs *= static_cast<double>(spec.axes.back().values.size());
  }
  if (const Entry* x = top.find("seeds")) {
    if (x->value.is_sequence()) {
      if (x->value.items.empty()) {
        fail(x->mark(), "seeds", "an empty list of seeds: give at least one, or leave it out");
      }
      for (std::size_t i = 0; i < x->value.items.size(); ++i) {
        const Node& item = *x->value.items[i];
        const Entry entry{"", mark_or(item, x->mark()), item};
        spec.seeds.push_back(static_cast<std::uint64_t>(read_int(entry, index("seeds", i), kSeed)));
      }
    } else {
      const Real count_value = read_real(*x, "seeds", kRangeEnd);
      if (count_value < 1 && std::floor(count_value) == count_value) {
        fail(x->mark(), "seeds",
             "expected at least one seed, got " + describe(x->value) +
                 " (leave it out to run "
                 "the scene as written)");
      }
      const auto count = read_int(*x, "seeds", kSeedCount);
      for (std::int64_t s = 0; s < count; ++s) {
        spec.seeds.push_back(static_cast<std::uint64_t>(s));
      }
    }
    runs *= static_cast<double>(spec.seeds.size());
  }
  if (runs > kMaxRuns) {
    fail(vary->mark(), "vary",
         "the axes and seeds make " + fmt(runs) + " runs; a sweep holds at most 1e6");
  }
  if (const Entry* x = top.find("reference")) {
    spec.reference_place = place_of(x->mark());
    const Fields fields = read_map(x->value, x->mark(), "reference",
                                   "a map from field paths to the reference's values", false);
    if (fields.entries.empty()) {
      fail(x->mark(), "reference", "expected at least one field (leave it out for no reference)");
    }
    for (const Entry& e : fields.entries) {
      if (e.value.is_null()) {
        fail(e.mark(), child("reference", e.key), "expected a value, got nothing");
      }
      spec.reference.push_back({e.key, node_text(e.value)});
    }
  }
  if (const Entry* x = top.find("trajectory")) {
    spec.trajectory = read_bool(*x, "trajectory");
  }
  return spec;
}

}  // namespace scene_yaml

SweepSpec load_sweep_string(std::string_view yaml, std::string_view source_name) {
  const std::string source(source_name);
  scene_yaml::Loader loader{source};
  return scene_yaml::with_yaml_errors(source, [&] { return loader.load_sweep(yaml); });
}

SweepSpec load_sweep_file(const std::filesystem::path& path) {
  const std::string source = path.string();
  const std::string text = scene_yaml::read_file(path, source);
  return load_sweep_string(text, source);
}

}  // namespace tumble
