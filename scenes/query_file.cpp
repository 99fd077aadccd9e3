// `tumble query` files: self-contained, so other kinds of query (time of impact) add a kind
// and their fields here without touching the scene format.
#include "scenes/yaml_reader.hpp"

#include <fstream>
#include <sstream>

namespace tumble::scene_yaml {
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
  // The shape cache is keyed by the nodes of one document.
  loaded_shapes_.clear();
  DocumentBuilder doc;
  const Node& root = parse(text, doc, "queries");
  const YAML::Mark start = text_start();
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

}  // namespace tumble::scene_yaml

namespace tumble {

using scene_yaml::Loader;
using scene_yaml::read_file;

std::vector<ShapeQuery> load_query_string(std::string_view yaml, std::string_view source_name,
                                          const SceneLoadOptions& options) {
  const std::string source(source_name);
  Loader loader{source, options};
  return scene_yaml::with_yaml_errors(source, [&] { return loader.load_queries(yaml); });
}

std::vector<ShapeQuery> load_query_file(const std::filesystem::path& path,
                                        const SceneLoadOptions& options) {
  const std::string source = path.string();
  const std::string text = read_file(path, source);
  return load_query_string(text, source, options);
}

}  // namespace tumble
