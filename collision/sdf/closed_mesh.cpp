// The closed-mesh check (collision/sdf/closed_mesh.hpp).
#include "collision/sdf/closed_mesh.hpp"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "tumble/error.hpp"

namespace tumble {

void require_closed_mesh(std::span<const Vec3> vertices,
                         std::span<const std::array<std::int32_t, 3>> triangles, const char* what) {
  const std::string prefix = std::string(what) + ": ";
  if (vertices.empty() || triangles.empty())
    throw Error(prefix + "the mesh has no triangles");
  for (const Vec3& v : vertices)
    if (!v.allFinite())
      throw Error(prefix + "a vertex is not finite");
  for (const auto& t : triangles)
    for (std::int32_t i : t)
      if (i < 0 || std::size_t(i) >= vertices.size())
        throw Error(prefix + "triangle index " + std::to_string(i) + " out of range");
  // A ray-parity or flood-fill sign cannot see every opening (a bowl's inner face alone gives
  // every line an even count), so closedness is checked edge by edge.
  std::vector<std::pair<std::int32_t, std::int32_t>> forward, backward;
  forward.reserve(3 * triangles.size());
  backward.reserve(3 * triangles.size());
  for (const auto& t : triangles)
    for (int e = 0; e < 3; ++e) {
      const std::int32_t a = t[std::size_t(e)], b = t[std::size_t((e + 1) % 3)];
      forward.push_back({a, b});
      backward.push_back({b, a});
    }
  std::sort(forward.begin(), forward.end());
  std::sort(backward.begin(), backward.end());
  if (forward != backward || std::adjacent_find(forward.begin(), forward.end()) != forward.end())
    throw Error(prefix +
                "the mesh is not closed (an edge is not shared by exactly two triangles running "
                "it in opposite directions); an SDF needs a closed, consistently oriented mesh");
}

}  // namespace tumble
