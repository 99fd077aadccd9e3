// The check every SDF built from a mesh needs: the mesh is closed and consistently oriented, so
// that inside and outside mean something.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "collision/math.hpp"

namespace tumble {

// Throws tumble::Error unless the mesh has triangles, finite vertices, indices in range, and every
// edge a -> b is run once the other way, b -> a, by another triangle. `what` starts the message
// ("SDF grid", "OpenVDB level set").
void require_closed_mesh(std::span<const Vec3> vertices,
                         std::span<const std::array<std::int32_t, 3>> triangles, const char* what);

}  // namespace tumble
