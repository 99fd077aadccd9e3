// The CCD routines: the exact mesh-feature queries (collision/ccd/mesh_ccd.hpp) and conservative
// advancement of shapes under linear and screw motions
// (collision/ccd/conservative_advancement.hpp). Checked on each input:
//   * a status is set and the time of impact lies in [0, 1];
//   * no false negative where the answer is exact: with small integer coordinates, a vertex in
//     its triangle or two edges crossing at t = 0 or t = 1 is decided exactly, and must be a hit;
//   * conservative advancement reports a hit where two solids already overlap at s = 0.
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "collision/ccd/conservative_advancement.hpp"
#include "collision/ccd/mesh_ccd.hpp"
#include "collision/ccd/rigid_motion.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"
#include "tests/fuzz/fuzz_input.hpp"

namespace {

using namespace tumble;

[[noreturn]] void finding(const char* what) {
  fuzz::finding("ccd", what);
}

// Small integers: every product below is exact in double.
Vec3 lattice_point(FuzzedDataProvider& in) {
  const Real x = in.ConsumeIntegralInRange<int>(-8, 8);
  const Real y = in.ConsumeIntegralInRange<int>(-8, 8);
  return {x, y, Real(in.ConsumeIntegralInRange<int>(-8, 8))};
}

Real orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).cross(c - a).dot(d - a);
}

// Exact for lattice points: p lies in the closed triangle abc (a proper triangle).
bool point_in_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  if (n.isZero(0) || orient(a, b, c, p) != 0)
    return false;
  const Real s0 = (b - a).cross(p - a).dot(n);
  const Real s1 = (c - b).cross(p - b).dot(n);
  const Real s2 = (a - c).cross(p - c).dot(n);
  return s0 >= 0 && s1 >= 0 && s2 >= 0;
}

// Exact for lattice points: segments pq and rs (proper, not parallel) meet.
bool segments_cross(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
  if (orient(p, q, r, s) != 0)
    return false;  // not coplanar
  const Vec3 n = (q - p).cross(s - r);
  if (n.isZero(0))
    return false;  // parallel or degenerate: left out of the exact check
  const Real a = (q - p).cross(r - p).dot(n);
  const Real b = (q - p).cross(s - p).dot(n);
  const Real c = (s - r).cross(p - r).dot(n);
  const Real d = (s - r).cross(q - r).dot(n);
  return ((a <= 0 && b >= 0) || (a >= 0 && b <= 0)) && ((c <= 0 && d >= 0) || (c >= 0 && d <= 0));
}

void mesh_features(FuzzedDataProvider& in) {
  std::array<Vec3, 4> start;
  std::array<Vec3, 4> end;
  for (Vec3& v : start)
    v = lattice_point(in);
  for (Vec3& v : end)
    v = in.ConsumeBool() ? lattice_point(in) : start[static_cast<std::size_t>(&v - end.data())];
  MeshCcdSettings settings;
  settings.max_boxes = 20000;
  const MeshCcdResult vf = vertex_face_ccd(start, end, settings);
  const MeshCcdResult ee = edge_edge_ccd(start, end, settings);
  for (const MeshCcdResult& r : {vf, ee}) {
    if (!(r.time_of_impact >= 0 && r.time_of_impact <= 1))
      finding("mesh CCD time of impact outside [0, 1]");
  }
  for (const auto* at : {&start, &end}) {
    const std::array<Vec3, 4>& v = *at;
    if (point_in_triangle(v[0], v[1], v[2], v[3]) && !vf.hit())
      finding("vertex-face: a vertex in its triangle at t = 0 or 1 was missed");
    if (segments_cross(v[0], v[1], v[2], v[3]) && !ee.hit())
      finding("edge-edge: edges crossing at t = 0 or 1 were missed");
  }
}

void shapes(FuzzedDataProvider& in) {
  const std::optional<Shape> a = fuzz::shape(in, true);
  const std::optional<Shape> b = fuzz::shape(in);
  if (!a || !b || a->type == ShapeType::mesh || a->type == ShapeType::sdf ||
      b->type == ShapeType::sdf)
    return;  // a mesh is static; fields are swept by their own path
  const Transform start_a = fuzz::pose(in, 2);
  const Transform end_a = fuzz::pose(in, 4);
  const Transform pose_b = fuzz::pose(in, 2);
  const MotionKind kind = in.ConsumeBool() ? MotionKind::linear : MotionKind::screw;
  const RigidMotion motion_a(start_a, end_a, kind);
  const RigidMotion motion_b = RigidMotion::stationary(pose_b);
  const ToiResult r = time_of_impact(*a, motion_a, *b, motion_b);
  if (!(r.time_of_impact >= 0 && r.time_of_impact <= 1))
    finding("time of impact outside [0, 1]");
  if (r.hit() && !r.normal.allFinite())
    finding("a hit without a finite normal");
  Manifold at_start;
  collide(*a, start_a, *b, pose_b, 0, at_start);
  Real deepest = 0;
  for (int i = 0; i < at_start.count; ++i)
    deepest = std::max(deepest, at_start.points[static_cast<std::size_t>(i)].depth);
  const Real size = std::max(bounding_radius(*a), bounding_radius(*b));
  // A mesh is a one-sided surface: the narrow phase counts a body behind a triangle, within its
  // face, as deep in it, while the time of impact measures the distance to the triangles
  // themselves. The check is for solids.
  if (b->type != ShapeType::mesh && deepest > Real(1e-6) * (1 + size) &&
      r.status == ToiStatus::separated)
    finding("shapes that overlap at the start reported as separated");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  if (in.ConsumeBool())
    mesh_features(in);
  else
    shapes(in);
  return 0;
}
