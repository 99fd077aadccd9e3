// Exact, conservative continuous collision of mesh features under linear vertex motion (Provot
// 1997; Bridson, Fedkiw and Anderson 2002; docs/ccd.md): a point against a triangle (vertex-face)
// and a segment against a segment (edge-edge), each vertex moving on a straight line from its
// position at t = 0 to t = 1.
//
// Conservative: a query that touches at some t in [0, 1] (exact geometry, closed triangle and
// segments, no minimum separation) always reports a hit, whatever the rounding; a query whose
// features stay farther apart than about `tolerance` reports no hit. Between the two a hit may
// be reported (a false positive). mesh_ccd.cpp says how.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "collision/math.hpp"

namespace tumble {

enum class MeshCcdStatus : std::uint8_t {
  separated,       // no contact for t in [0, 1]
  hit,             // contact at time_of_impact (within the tolerance)
  max_iterations,  // the search ran out of boxes: reported as a hit at the earliest open time
  invalid_input,   // a coordinate is NaN or infinite; reported as a hit at t = 0
};

struct MeshCcdSettings {
  // Features closer than this [m] may be reported as touching. Must be > 0.
  Real tolerance = Real(1e-6);
  // How many parameter boxes the search may test before it gives up (conservatively).
  std::int32_t max_boxes = 100000;
};

struct MeshCcdResult {
  MeshCcdStatus status = MeshCcdStatus::separated;
  // A lower bound of the first time of contact in [0, 1]; 1 when separated.
  Real time_of_impact = 1;
  std::int32_t boxes = 0;  // parameter boxes tested (work done)

  bool hit() const { return status != MeshCcdStatus::separated; }
};

// `start` = {p, a, b, c} at t = 0, `end` the same vertices at t = 1.
MeshCcdResult vertex_face_ccd(const std::array<Vec3, 4>& start, const std::array<Vec3, 4>& end,
                              const MeshCcdSettings& settings = {});

// `start` = {a0, a1, b0, b1} at t = 0 (segment a0a1 and segment b0b1), `end` at t = 1.
MeshCcdResult edge_edge_ccd(const std::array<Vec3, 4>& start, const std::array<Vec3, 4>& end,
                            const MeshCcdSettings& settings = {});

std::string_view mesh_ccd_status_name(MeshCcdStatus status);

}  // namespace tumble
