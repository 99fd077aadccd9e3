#include "scenes/obj_reader.hpp"

#define TINYOBJLOADER_IMPLEMENTATION
#define TINYOBJLOADER_USE_DOUBLE
#include <tiny_obj_loader.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <system_error>

#include "engine/printable_text.hpp"
#include "engine/scene_limits.hpp"
#include "scenes/scene_files.hpp"

namespace tumble {
namespace {

// tinyobjloader reads a coordinate it cannot parse ("nan", "abc") as 0, reads 0e1001 as NaN,
// wraps an index too large for an int, and converts a record it parses as float to int without a
// range check (a vertex weight's joint id): the records tumble uses are checked first, each
// refused with its line, and the library is given those alone, rewritten: `v x y z` and `f` with
// the vertex numbers of its corners. Every other record (normals, texture coordinates, groups,
// materials) is blank. The vertices are the ones read here (std::from_chars, correctly rounded);
// the library's own reading of them is not used.
struct CheckedRecords {
  std::string text;
  std::vector<Vec3> vertices;
};

CheckedRecords checked_records(const std::string& text, const std::string& name) {
  std::istringstream lines(text);
  CheckedRecords out;
  std::string& kept = out.text;
  kept.reserve(text.size());
  std::string line;
  std::size_t triangles = 0;
  for (int number = 1; std::getline(lines, line); ++number) {
    std::istringstream fields(line);
    std::string tag;
    fields >> tag;
    const auto refuse = [&](const std::string& why) {
      throw ObjError("cannot read OBJ file '" + printable_name(name) + "': line " +
                     std::to_string(number) + ": " + why);
    };
    if (tag == "v") {
      kept += "v 0 0 0";
      Vec3 vertex = Vec3::Zero();
      int count = 0;
      for (std::string token; count < 3 && fields >> token; ++count) {
        double value = 0;
        const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
        if (error != std::errc() || end != token.data() + token.size() || !std::isfinite(value))
          refuse("vertex coordinate " + std::to_string(count + 1) + " is not a finite number");
        vertex[count] = value;
      }
      if (count < 3)
        refuse("a vertex needs three coordinates");
      if (out.vertices.size() >= scene_limits::kMaxMeshVertices)
        refuse("more than 10,000,000 vertices, the limit for a mesh");
      out.vertices.push_back(vertex);
    } else if (tag == "f") {
      kept += 'f';
      std::size_t corners = 0;
      for (std::string token; fields >> token; ++corners) {
        const std::string first = token.substr(0, token.find('/'));
        long long index = 0;
        const auto [end, error] = std::from_chars(first.data(), first.data() + first.size(), index);
        if (error != std::errc() || end != first.data() + first.size() || index == 0 ||
            index > 2147483647LL || index < -2147483647LL)
          refuse("face vertex '" + printable(first) +
                 "' is not a vertex number (1 to 2147483647, or "
                 "negative to count back)");
        kept.append(" ").append(first);
      }
      // A face of n corners is n - 2 triangles.
      triangles += corners > 2 ? corners - 2 : 0;
      if (triangles > scene_limits::kMaxTriangles)
        refuse("more than 10,000,000 triangles, the limit for a mesh");
    }
    kept += '\n';  // one line for each of the file's, so that the library's line numbers hold
  }
  return out;
}

}  // namespace

namespace {

// The vertices and triangles of the text, faces or none.
ObjMesh parse_obj(const std::string& text, const std::string& name) {
  CheckedRecords records = checked_records(text, name);
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // No material text: a mesh is geometry only, and no other file is opened behind the scene's back.
  if (!reader.ParseFromString(records.text, "", config) || !reader.Valid()) {
    std::string why = reader.Error();
    while (!why.empty() && (why.back() == '\n' || why.back() == '\r'))
      why.pop_back();
    throw ObjError("cannot read OBJ file '" + printable_name(name) +
                   "': " + (why.empty() ? "parse error" : why));
  }
  ObjMesh mesh;
  mesh.vertices = std::move(records.vertices);
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const auto& indices = shape.mesh.indices;
    for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
      TriangleMesh::Triangle t{};
      for (int k = 0; k < 3; ++k) {
        const int index = indices[i + std::size_t(k)].vertex_index;
        if (index < 0 || std::size_t(index) >= mesh.vertices.size())
          throw ObjError("cannot read OBJ file '" + printable_name(name) + "': face " +
                         std::to_string(i / 3) + " uses vertex " + std::to_string(index + 1) +
                         " but the file has " + std::to_string(mesh.vertices.size()) + " vertices");
        t[k] = std::int32_t(index);
      }
      mesh.triangles.push_back(t);
    }
  }
  return mesh;
}

std::string obj_text(const std::filesystem::path& path) {
  std::string why;
  if (std::optional<std::string> text = regular_file_text(path, why))
    return std::move(*text);
  throw ObjError("cannot open OBJ file '" + printable_name(path.string()) + "': " + why);
}

}  // namespace

ObjMesh read_obj_string(const std::string& text, const std::string& name) {
  ObjMesh mesh = parse_obj(text, name);
  if (mesh.triangles.empty())
    throw ObjError("cannot read OBJ file '" + printable_name(name) +
                   "': it has no faces ('f' lines)");
  return mesh;
}

ObjMesh read_obj_file(const std::filesystem::path& path) {
  return read_obj_string(obj_text(path), path.string());
}

std::vector<Vec3> read_obj_points_file(const std::filesystem::path& path) {
  ObjMesh mesh = parse_obj(obj_text(path), path.string());
  return std::move(mesh.vertices);
}

}  // namespace tumble
