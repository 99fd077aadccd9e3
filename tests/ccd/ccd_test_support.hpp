// Shared helpers of the CCD tests (and of tests/benchmarks/ccd_benchmark.cpp): the random-case
// scale, random poses, and the sliding vertex-face queries that made the mesh CCD slow.
#pragma once

#include <array>
#include <cmath>
#include <cstdlib>
#include <random>
#include <vector>

#include "collision/math.hpp"
#include "tests/property_scale.hpp"

namespace tumble::testing {

inline Vec3 random_vector(std::mt19937_64& rng, Real lo, Real hi) {
  std::uniform_real_distribution<Real> u(lo, hi);
  const Real x = u(rng), y = u(rng), z = u(rng);
  return Vec3(x, y, z);
}

inline Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<Real> n(0, 1);
  const auto draw = [&] {
    const Real x = n(rng), y = n(rng), z = n(rng);
    return Vec3(x, y, z);
  };
  Vec3 v = draw();
  while (v.norm() < 1e-6)
    v = draw();
  return v.normalized();
}

inline Quat random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<Real> n(0, 1);
  const Real w = n(rng), x = n(rng), y = n(rng), z = n(rng);
  Quat q(w, x, y, z);
  return q.normalized();
}

// A vertex that slides in the plane of a triangle beside one of its edges: coplanar motion, the
// hard case of vertex-face CCD, as when a mesh vertex slides on a flat floor of triangles. In the
// triangle's frame the triangle is still and the vertex moves parallel to `edge` (0 = ab,
// 1 = bc, 2 = ca) from 10% to 90% of its length, `gap` outside it; with `crosses` it ends `gap`
// inside instead (a contact). The frame is random and translates; with `turns` it also turns by
// up to 1e-3 rad, so that the four points leave the plane by about 1e-8 m mid-step. The triangle
// is about 0.1 m across, somewhere in [-1, 1]^3. Vertex order: {p, a, b, c}.
struct SlidingQuery {
  std::array<Vec3, 4> start;
  std::array<Vec3, 4> end;
};

inline SlidingQuery sliding_vertex_face_query(std::mt19937_64& rng, Real gap, int edge,
                                              bool crosses, bool turns) {
  std::uniform_real_distribution<Real> unit(0, 1);
  const std::array<Vec3, 3> tri = {Vec3(0, 0, 0), Vec3(0.1, 0, 0),
                                   Vec3(0.02 + 0.06 * unit(rng), 0.06 + 0.04 * unit(rng), 0)};
  const Vec3& e0 = tri[edge];
  const Vec3& e1 = tri[(edge + 1) % 3];
  const Vec3 along = (e1 - e0).normalized();
  const Vec3 outward(along.y(), -along.x(), 0);  // the triangle is counter-clockwise in z = 0
  SlidingQuery q;
  const Vec3 from = e0 + 0.1 * (e1 - e0) + gap * outward;
  const Vec3 to = e0 + 0.9 * (e1 - e0) + (crosses ? -gap : gap) * outward;
  const Quat pose = random_rotation(rng);
  const Vec3 origin = random_vector(rng, -1, 1);
  const Quat turn =
      turns ? Quat(Eigen::AngleAxis<Real>(1e-3 * unit(rng), random_unit(rng))) : Quat::Identity();
  const Vec3 shift = random_vector(rng, -0.01, 0.01);
  for (int k = 0; k < 4; ++k) {
    const Vec3 local_start = k == 0 ? from : tri[k - 1];
    const Vec3 local_end = k == 0 ? to : tri[k - 1];
    q.start[k] = origin + pose * local_start;
    q.end[k] = origin + shift + pose * (turn * local_end);
  }
  return q;
}

// `count` sliding queries: gaps from 1e-5 to 1e-2 of the edge (log-uniform, so about 1e-6 m to
// 1e-3 m), every edge, one in four crossing into the triangle, half of them turning.
inline std::vector<SlidingQuery> sliding_vertex_face_queries(std::uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<Real> exponent(-5, -2);
  std::vector<SlidingQuery> out;
  for (int i = 0; i < count; ++i) {
    const Real gap = 0.1 * std::pow(Real(10), exponent(rng));
    out.push_back(sliding_vertex_face_query(rng, gap, i % 3, i % 4 == 3, i % 2 == 1));
  }
  return out;
}

}  // namespace tumble::testing
