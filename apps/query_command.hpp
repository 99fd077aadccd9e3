// `tumble query FILE.yaml`: collision queries between pairs of shapes (docs/scene-format.md,
// "Query files"). Prints one JSON object per query and line:
//   contact: {"name", "kind", "status", "status_source", "state", "distance", "normal",
//             "point_a", "point_b", "contacts": [{"position", "depth", "feature": [a, b]}]}
//   toi:     {"name", "kind", "status", "toi", "duration", "distance", "normal", "pose_a",
//             "pose_b"}
// distance is signed (negative = penetration), the normal points from b to a, and point_a and
// point_b are the witness points on a and b. Convex pairs are answered by GJK/EPA, the others
// by the narrow phase's manifold (query_command.cpp says which status comes from where).
#pragma once

#include <filesystem>
#include <iosfwd>

#include "scenes/query_file.hpp"

namespace tumble::app {

// Returns 0 when every query ran (whatever its status), 1 on a bad file (SceneError thrown).
int query_command(const std::filesystem::path& file);

// One query's JSON line (no newline).
std::string answer_query(const ShapeQuery& query);

}  // namespace tumble::app
