// Signed distance fields in YAML (scenes/sdf_section.hpp), read with the scene loader's strict
// readers; the tree's own checks (collision/sdf/sdf_tree.hpp) then find nothing a field did not.
#include "scenes/sdf_section.hpp"

#include <filesystem>
#include <memory>

#include "engine/printable_text.hpp"
#include "scenes/neural_sdf_file.hpp"
#include "scenes/obj_reader.hpp"
#include "scenes/scene_files.hpp"
#include "scenes/yaml_reader.hpp"

namespace tumble {
namespace scene_yaml {
namespace {

constexpr std::array<std::string_view, 13> kSdfKinds{
    "sphere", "box",   "capsule",      "cylinder",   "torus",        "plane", "grid",
    "neural", "union", "intersection", "difference", "smooth_union", "morph"};
constexpr std::array<std::string_view, 6> kGridKeys{"file",    "cell", "interpolation",
                                                    "builder", "band", "refine"};
constexpr std::array<std::string_view, 1> kNeuralKeys{"file"};
constexpr RealSpec kCell{"a cell size in metres", "1e-6 to 1e3", 1e-6, 1e3};
constexpr RealSpec kBandVoxels{"a band width in voxels", "1 to 64", 1, 64};
constexpr IntSpec kRefine{"a whole refinement factor", "1 to 16", 1, GridRefinement::kMaxRefine};
constexpr std::array<std::string_view, 1> kRadiusKeys{"radius"};
constexpr std::array<std::string_view, 1> kHalfExtentsKeys{"half_extents"};
constexpr std::array<std::string_view, 2> kRadiusLengthKeys{"radius", "half_length"};
constexpr std::array<std::string_view, 2> kTorusKeys{"major_radius", "minor_radius"};
constexpr std::array<std::string_view, 2> kSmoothKeys{"k", "of"};
constexpr std::array<std::string_view, 4> kMorphKeys{"from", "to", "start", "duration"};
constexpr RealSpec kMorphStart{"a time in seconds", "-1e9 to 1e9", -1e9, 1e9};
constexpr RealSpec kMorphDuration{"a duration in seconds", "greater than 0, at most 1e9", 0, 1e9,
                                  true};
// SdfTree's own limits (collision/sdf/sdf_tree.hpp: kMaxSize), read here so that a size beyond
// them is blamed on its line.
constexpr RealSpec kSdfSize{"a positive number in metres", "1e-9 to 1e6", kMinSize,
                            SdfTree::kMaxSize};
constexpr RealSpec kSdfCoordinate{"a coordinate in metres", "-1e6 to 1e6", -SdfTree::kMaxSize,
                                  SdfTree::kMaxSize};
constexpr RealSpec kSharpness{"a sharpness in 1/m", "greater than 0, at most 1e9", 0, 1e9, true};

}  // namespace

SdfNode Loader::load_sdf_node(const Node& node, const YAML::Mark& mark, const std::string& path,
                              int depth) const {
  if (depth > SdfTree::kMaxDepth)
    fail(mark, path, "SDF nodes nested deeper than " + std::to_string(SdfTree::kMaxDepth));
  const Fields f = read_map(node, mark, path,
                            "an SDF node: a map with one of sphere, box, capsule, cylinder, torus, "
                            "plane, grid, neural, union, intersection, difference, smooth_union, "
                            "morph",
                            false);
  const Entry* kind = nullptr;
  for (const Entry& e : f.entries) {
    if (e.key == "position" || e.key == "orientation")
      continue;
    if (!contains(kSdfKinds, e.key)) {
      std::vector<std::string_view> allowed(kSdfKinds.begin(), kSdfKinds.end());
      allowed.push_back("position");
      allowed.push_back("orientation");
      check_known(f, allowed);
    }
    if (kind != nullptr)
      fail(e.key_mark, child(path, e.key),
           "an SDF node has one kind; this one already is a '" + kind->key + "'");
    kind = &e;
  }
  if (kind == nullptr)
    fail(f.mark, path,
         "an SDF node needs a kind: one of sphere, box, capsule, cylinder, torus, plane, grid, "
         "neural, union, intersection, difference, smooth_union, morph");
  const std::string here = child(path, kind->key);
  SdfNode n;
  const auto require = [&](const Fields& params, std::string_view key) -> const Entry& {
    const Entry* x = params.find(key);
    if (x == nullptr)
      fail(params.mark, child(here, key), "missing required field '" + std::string(key) + "'");
    return *x;
  };
  const auto operands = [&](const Entry& list, const std::string& list_path) {
    if (!list.value.is_sequence() || list.value.size() < 2)
      fail(list.mark(), list_path,
           "expected a list of at least two SDF nodes, got " + describe(list.value));
    std::vector<SdfNode> out;
    for (std::size_t i = 0; i < list.value.items.size(); ++i) {
      const Node& item = *list.value.items[i];
      out.push_back(
          load_sdf_node(item, mark_or(item, list.mark()), index(list_path, i), depth + 1));
    }
    return out;
  };
  const std::string& k = kind->key;
  if (k == "union" || k == "intersection" || k == "difference") {
    const SdfKind op = k == "union"          ? SdfKind::union_of
                       : k == "intersection" ? SdfKind::intersection_of
                                             : SdfKind::difference_of;
    n = SdfNode::combine(op, operands(*kind, here));
  } else if (k == "smooth_union") {
    const Fields params = read_map(kind->value, kind->mark(), here, "{k, of: [nodes]}", false);
    check_known(params, kSmoothKeys);
    const Real sharpness = read_real(require(params, "k"), child(here, "k"), kSharpness);
    n = SdfNode::combine(SdfKind::smooth_union_of,
                         operands(require(params, "of"), child(here, "of")), sharpness);
  } else if (k == "morph") {
    // {morph: {from: NODE, to: NODE, start: 0, duration: 2}}: a field changing from one solid
    // to another (collision/sdf/sdf_tree.hpp).
    const Fields params =
        read_map(kind->value, kind->mark(), here, "{from: node, to: node, start, duration}", false);
    check_known(params, kMorphKeys);
    const Entry& from = require(params, "from");
    const Entry& to = require(params, "to");
    const Entry* start_at = params.find("start");
    const Real start =
        start_at != nullptr ? read_real(*start_at, child(here, "start"), kMorphStart) : Real(0);
    const Real duration =
        read_real(require(params, "duration"), child(here, "duration"), kMorphDuration);
    n = SdfNode::morph(load_sdf_node(from.value, from.mark(), child(here, "from"), depth + 1),
                       load_sdf_node(to.value, to.mark(), child(here, "to"), depth + 1), start,
                       duration);
  } else {
    const Fields params = read_map(kind->value, kind->mark(), here, "the primitive's sizes", true);
    if (k == "sphere") {
      check_known(params, kRadiusKeys);
      n = SdfNode::sphere(read_real(require(params, "radius"), child(here, "radius"), kSdfSize));
    } else if (k == "box") {
      check_known(params, kHalfExtentsKeys);
      n = SdfNode::box(read_vector<3>(require(params, "half_extents"), child(here, "half_extents"),
                                      "[x, y, z]", "metres", kSdfSize));
    } else if (k == "capsule" || k == "cylinder") {
      check_known(params, kRadiusLengthKeys);
      const Real r = read_real(require(params, "radius"), child(here, "radius"), kSdfSize);
      const Real h =
          read_real(require(params, "half_length"), child(here, "half_length"), kSdfSize);
      n = k == "capsule" ? SdfNode::capsule(r, h) : SdfNode::cylinder(r, h);
    } else if (k == "torus") {
      check_known(params, kTorusKeys);
      const Entry& major = require(params, "major_radius");
      const Entry& minor = require(params, "minor_radius");
      const Real big = read_real(major, child(here, "major_radius"), kSdfSize);
      const Real small = read_real(minor, child(here, "minor_radius"), kSdfSize);
      if (!(small < big))
        fail(minor.mark(), child(here, "minor_radius"),
             "expected less than major_radius " + fmt(big) + " (a ring torus), got " + fmt(small));
      n = SdfNode::torus(big, small);
    } else if (k == "grid") {
      n = load_sdf_grid(params, here);
    } else if (k == "neural") {
      check_known(params, kNeuralKeys);
      const Entry& file = require(params, "file");
      const std::filesystem::path where =
          referenced_file(read_name(file, child(here, "file"), "a weights file name (JSON)"),
                          file.mark(), child(here, "file"));
      try {
        n = SdfNode::from_network(std::make_shared<const NeuralSdf>(load_neural_sdf_file(where)));
      } catch (const Error& error) {
        fail(file.mark(), child(here, "file"), error.what());
      }
    } else {  // plane
      check_known(params, {});
      n = SdfNode::plane();
    }
  }
  if (const Entry* x = f.find("position"))
    n.pose.translation =
        read_vector<3>(*x, child(path, "position"), "[x, y, z]", "metres", kSdfCoordinate);
  if (const Entry* x = f.find("orientation"))
    n.pose.rotation = read_orientation(*x, child(path, "orientation"));
  return n;
}

std::filesystem::path Loader::referenced_file(const std::string& name, const YAML::Mark& mark,
                                              const std::string& field) const {
  const std::filesystem::path path = file_beside(source_, name);
  if (!options_.allow_outside_files) {
    if (const auto folder = outside_folder_of(source_, path))
      fail(mark, field,
           "'" + printable(name) + "' lies outside the scene's folder (" +
               printable(folder->string()) +
               "): a scene may name only files in its folder or below it (run with "
               "--allow-outside-files, or set SceneLoadOptions::allow_outside_files, to lift "
               "this)");
  }
  return path;
}

// {grid: {file: mesh.obj, cell: 0.01, interpolation: tricubic, builder: tumble | openvdb,
// band: 3}}: a grid SDF of a closed OBJ mesh, tumble's dense grid (collision/sdf/sdf_grid.hpp) or
// OpenVDB's narrow-band level set (collision/sdf/vdb_level_set.hpp); {grid: {file: part.vdb}}: a
// level set read from an OpenVDB file. Files are relative to the scene's folder.
SdfNode Loader::load_sdf_grid(const Fields& params, const std::string& here) const {
  check_known(params, kGridKeys);
  const Entry* file = params.find("file");
  if (file == nullptr)
    fail(params.mark, child(here, "file"),
         "a grid needs 'file' (a closed OBJ mesh, with 'cell', or an OpenVDB .vdb file)");
  const std::string name = read_name(*file, child(here, "file"), "an OBJ or .vdb file name");
  const bool vdb_file = std::filesystem::path(name).extension() == ".vdb";
  GridInterpolation how = GridInterpolation::tricubic;
  if (const Entry* x = params.find("interpolation")) {
    const std::string word = read_word(*x, child(here, "interpolation"), "an interpolation");
    if (word == "trilinear")
      how = GridInterpolation::trilinear;
    else if (word != "tricubic")
      fail(x->mark(), child(here, "interpolation"),
           "expected tricubic or trilinear, got '" + word + "'");
  }
  bool openvdb = vdb_file;
  if (const Entry* x = params.find("builder")) {
    const std::string word = read_word(*x, child(here, "builder"), "a builder");
    if (word != "tumble" && word != "openvdb")
      fail(x->mark(), child(here, "builder"), "expected tumble or openvdb, got '" + word + "'");
    if (vdb_file)
      fail(x->mark(), child(here, "builder"),
           "a .vdb file is read as it is; 'builder' is for grids built from an OBJ mesh");
    openvdb = word == "openvdb";
  }
  const Entry* cell = params.find("cell");
  if (vdb_file && cell != nullptr)
    fail(cell->mark(), child(here, "cell"),
         "a .vdb file carries its own voxel size; leave 'cell' out");
  if (!vdb_file && cell == nullptr)
    fail(params.mark, child(here, "cell"),
         "a grid built from a mesh needs 'cell' (the cell size in metres)");
  const Entry* band = params.find("band");
  if (band != nullptr && (vdb_file || !openvdb))
    fail(band->mark(), child(here, "band"),
         "'band' (voxels each side of the surface) is for grids built with builder: openvdb");
  const Real band_voxels = band != nullptr ? read_real(*band, child(here, "band"), kBandVoxels) : 3;
  const Entry* refine_entry = params.find("refine");
  if (refine_entry != nullptr && (vdb_file || openvdb))
    fail(refine_entry->mark(), child(here, "refine"),
         "'refine' (the band near the surface sampled that many times finer) is for grids built "
         "with builder: tumble (a level set is all band)");
  const int refine =
      refine_entry != nullptr ? int(read_int(*refine_entry, child(here, "refine"), kRefine)) : 1;
  if (openvdb && !VdbLevelSet::available())
    fail(file->mark(), child(here, "file"),
         std::string(vdb_file ? "OpenVDB volumes (.vdb)" : "builder: openvdb") +
             " needs a build with OpenVDB, which this one does not have; give a closed OBJ "
             "mesh with builder: tumble instead");
  const Real size = vdb_file ? 0 : read_real(*cell, child(here, "cell"), kCell);
  const std::filesystem::path where = referenced_file(name, file->mark(), child(here, "file"));
  if (std::string why; vdb_file && !is_regular_file_within_limits(where, why))
    fail(file->mark(), child(here, "file"),
         "cannot read '" + printable_name(where.string()) + "': " + why);
  try {
    if (vdb_file)
      return SdfNode::from_level_set(VdbLevelSet::load(where), how);
    const ObjMesh mesh = read_obj_file(where);
    if (openvdb)
      return SdfNode::from_level_set(
          VdbLevelSet::from_mesh(mesh.vertices, mesh.triangles, size, band_voxels), how);
    return SdfNode::from_grid(
        std::make_shared<const SdfGrid>(SdfGrid::from_mesh(mesh.vertices, mesh.triangles, size,
                                                           SdfGrid::kBand + 1, nullptr, refine)),
        how);
  } catch (const ObjError& error) {
    fail(file->mark(), child(here, "file"), error.what());
  } catch (const Error& error) {
    fail(file->mark(), child(here, "file"), error.what());
  }
}

SdfNode Loader::load_sdf(std::string_view text) {
  DocumentBuilder doc;
  const Node& root = parse(text, doc, "sdf");
  const YAML::Mark start = text_start();
  SdfNode n = load_sdf_node(root, mark_or(root, start), "sdf", 1);
  try {
    (void)SdfTree(n);  // every field was read against the tree's own ranges: nothing new here
  } catch (const Error& e) {
    fail(start, "sdf", e.what());
  }
  return n;
}

}  // namespace scene_yaml

SdfNode load_sdf_string(std::string_view yaml, std::string_view source_name,
                        const SceneLoadOptions& options) {
  const std::string source(source_name);
  scene_yaml::Loader loader{source, options};
  return scene_yaml::with_yaml_errors(source, [&] { return loader.load_sdf(yaml); });
}

}  // namespace tumble
