// The input of `tumble query` (design.md): a YAML file with a list of shape pairs,
//   queries: [{name, kind, margin, a: {shape, position, orientation}, b: {...}}]
// Shapes are written exactly as in scene files (the same parser reads them). Errors are the
// loader's SceneError, with file, line, column and field.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "collision/shape.hpp"

namespace tumble {

// What a query asks. Only `contact` exists today; `toi` (time of impact) is reserved for
// continuous collision and is added next to it in scene_loader.cpp's kQueryKinds.
enum class QueryKind { contact };

struct ShapeQuery {
  std::string name;
  QueryKind kind = QueryKind::contact;
  Real margin = 10;  // m: contacts are reported while the shapes are closer than this
  Shape a;
  Transform pose_a;
  Shape b;
  Transform pose_b;
};

std::vector<ShapeQuery> load_query_file(const std::filesystem::path& path);
std::vector<ShapeQuery> load_query_string(std::string_view yaml, std::string_view source_name);

}  // namespace tumble
