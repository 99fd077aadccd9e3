// Shapes in a scene or query file: primitives, hulls, meshes, compounds (docs/scene-format.md,
// "Shapes"), and orientations.
#include <algorithm>
#include <cmath>
#include <string>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/shape.hpp"
#include "collision/shapes/triangle_mesh.hpp"
#include "scenes/obj_reader.hpp"
#include "scenes/yaml_reader.hpp"

namespace tumble::scene_yaml {
namespace {

constexpr std::array<std::string_view, 2> kSphereKeys{"type", "radius"};
constexpr std::array<std::string_view, 2> kBoxKeys{"type", "half_extents"};
constexpr std::array<std::string_view, 3> kCapsuleKeys{"type", "radius", "half_length"};
constexpr std::array<std::string_view, 1> kPlaneKeys{"type"};
constexpr std::array<std::string_view, 3> kCylinderKeys{"type", "radius", "half_length"};
constexpr std::array<std::string_view, 3> kHullKeys{"type", "points", "file"};
constexpr std::array<std::string_view, 4> kMeshKeys{"type", "vertices", "triangles", "file"};
constexpr std::array<std::string_view, 2> kCompoundKeys{"type", "parts"};
constexpr std::array<std::string_view, 3> kPartKeys{"shape", "position", "orientation"};
constexpr std::array<std::string_view, 3> kSdfKeys{"type", "sdf", "resolution"};
constexpr IntSpec kFieldResolution{"a whole number of cells", "8 to 96", SdfShape::kMinCells,
                                   SdfShape::kMaxCells};
constexpr IntSpec kVertexIndex{"a vertex index", "0 to the number of vertices - 1", 0,
                               std::int64_t(1) << 31};

}  // namespace

Shape Loader::load_shape(const Entry& e, const std::string& path, Vec3* centre_of_mass) const {
  const Node* key = &e.value;
  if (const auto it = loaded_shapes_.find(key); it != loaded_shapes_.end()) {
    if (centre_of_mass != nullptr)
      *centre_of_mass = it->second.centre_of_mass;
    return it->second.shape;
  }
  if (!shapes_loading_.insert(key).second)
    fail(e.mark(), path, "this shape contains itself through an alias");
  struct Done {
    std::unordered_set<const Node*>& loading;
    const Node* key;
    ~Done() { loading.erase(key); }
  } done{shapes_loading_, key};
  Vec3 centre = Vec3::Zero();
  Shape shape = build_shape(e, path, &centre);
  loaded_shapes_.emplace(key, LoadedShape{shape, centre});
  if (centre_of_mass != nullptr)
    *centre_of_mass = centre;
  return shape;
}

Shape Loader::build_shape(const Entry& e, const std::string& path, Vec3* centre_of_mass) const {
  if (centre_of_mass != nullptr)
    *centre_of_mass = Vec3::Zero();
  const Fields f = read_map(e.value, e.mark(), path,
                            "a map describing a shape, such as {type: sphere, radius: 0.5}", false);
  const Entry* type = f.find("type");
  if (type == nullptr) {
    fail(f.mark, child(path, "type"),
         "missing required field 'type'; expected one of: sphere, box, capsule, plane, cylinder, "
         "hull, mesh, compound, sdf");
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
  if (t == "sdf") {
    check_known(f, kSdfKeys);
    const Entry& field = require("sdf", "the field: an SDF node such as {torus: {...}}");
    // The resolution first: a grid or level set in the node may take seconds to build.
    int cells = SdfShape::kMassCells;
    if (const Entry* r = f.find("resolution"))
      cells = int(read_int(*r, child(path, "resolution"), kFieldResolution));
    const SdfNode root = load_sdf_node(field.value, field.mark(), child(path, "sdf"), 1);
    try {
      return sdf_shape(root, centre_of_mass, cells);
    } catch (const Error& error) {
      fail(field.mark(), child(path, "sdf"), error.what());
    }
  }
  fail(type->mark(), child(path, "type"),
       "expected one of: sphere, box, capsule, plane, cylinder, hull, mesh, compound, sdf, got " +
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
    if (n.size() > kMaxHullPoints)
      fail(where.mark(), field,
           "a hull is built from at most 1,000,000 points, got " + std::to_string(n.size()));
    for (std::size_t i = 0; i < n.size(); ++i) {
      const Node& item = *n.items[i];
      const Entry point{index(field, i), mark_or(item, where.mark()), item};
      points.push_back(read_vector<3>(point, index(field, i), "[x, y, z]", "metres", kCoordinate));
    }
  } else {
    const std::string name = read_name(*file_entry, field, "an OBJ file name");
    // Only the vertex lines matter for a hull, read by the OBJ reader meshes use (which names
    // a bad line by its number, without echoing the line).
    try {
      points = read_obj_points_file(referenced_file(name, where.mark(), field));
    } catch (const ObjError& error) {
      fail(where.mark(), field, error.what());
    }
    if (points.size() > kMaxHullPoints)
      fail(where.mark(), field,
           "a hull is built from at most 1,000,000 points, the file has " +
               std::to_string(points.size()));
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
    const std::filesystem::path obj = referenced_file(name, file->mark(), child(path, "file"));
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
    if (vertices->value.size() > kMaxMeshVertices)
      fail(vertices->mark(), vpath,
           "a mesh has at most 10,000,000 vertices, got " + std::to_string(vertices->value.size()));
    if (triangles->value.size() > kMaxTriangles)
      fail(triangles->mark(), tpath,
           "a mesh has at most 10,000,000 triangles, got " +
               std::to_string(triangles->value.size()));
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
    // The part's type is checked before the part is loaded: a compound inside a compound is
    // refused here, so an alias that makes a compound its own part ends at once instead of
    // recursing without end.
    if (shape->value.is_map()) {
      const std::vector<const Node*>& kv = shape->value.items;  // keys and values, alternating
      for (std::size_t k = 0; k + 1 < kv.size(); k += 2) {
        const Node& key = *kv[k];
        const Node& value = *kv[k + 1];
        if (key.is_scalar() && key.scalar == "type" && value.is_scalar() &&
            (value.scalar == "compound" || value.scalar == "mesh" || value.scalar == "plane"))
          fail(shape->mark(), child(at, "shape"),
               "a compound part must be a sphere, box, capsule, cylinder or hull, got " +
                   value.scalar);
      }
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
}  // namespace tumble::scene_yaml
