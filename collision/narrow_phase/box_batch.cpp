// Box-box manifolds over many pairs (see box_batch.hpp): the query of pairs/box_box.cpp rewritten
// so that several pairs run side by side, one per lane of a vector, every choice a select.
//
// Pairs go in chunks of 64: their order in collide() (detail::runs_first) is found first, in
// scalar code; the lanes (box_batch_lanes.inc) answer them a block of lanes at a time, writing the
// manifolds; the few pairs the lanes flag are answered by collide() afterwards. The lanes:
//   - the separating-axis test of Gottschalk, Lin and Manocha (1996) in A's frame, the fifteen
//     axes and the choice among them as box_box.cpp makes it (the same formulas and preferences);
//   - for a face axis, the overlap of the reference face and the incident face found directly
//     (Ericson 8.3.4's Sutherland-Hodgman clip gives the same polygon; here its vertices come out
//     as 24 fixed candidates: 4 incident corners, 16 crossings of the 4 incident edges with the 4
//     side planes, 4 reference corners, each with a keep mask, packed to 12 since at most two per
//     incident edge can be vertices), then the four points kept by the rule of
//     manifold_reduction.hpp (the deepest, the farthest from it, the largest triangle, the
//     largest added area; Catto 2007, Gregorius 2015) as masked maxima over the 12 slots;
//   - for an edge axis, the closest points of the two extreme edges (Ericson 5.1.9), clamped by
//     selects.
// A vector pass costs the same for every lane whichever way its pair goes, so face and edge
// contacts take separate passes: when many pairs of the last chunk were apart or edge contacts,
// the separating-axis test runs alone first and sorts the chunk's pairs into face pairs and edge
// pairs (the apart ones are done); otherwise every pair takes the face pass, which leaves the
// edge pairs to the edge pass. Each pass runs the test again rather than store its results.
//
// The lanes are GCC vector extensions as wide as the target's registers (8 doubles for AVX-512,
// 4 for AVX2, 2 for the SSE2 baseline), the lanes file compiled once per instruction set, each
// lane with the same IEEE operations in the same order (-ffp-contract=off; no FMA), so every
// machine gives the same bits. The versions differ only in speed.
#include "collision/narrow_phase/box_batch.hpp"

#include <immintrin.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"

namespace tumble {
namespace {

// The feature ids of face-contact slot `slot` (see the lanes file) as box_box.cpp names them,
// for each reference face (axis, side) and incident face (axis, side): a table built at compile
// time, so that writing a manifold looks them up instead of calling out of the vector code.
struct SlotFeatures {
  std::uint16_t reference;
  std::uint16_t incident;
};

constexpr SlotFeatures face_slot_features(int face_axis, bool face_positive, int incident_axis,
                                          bool incident_positive, int slot) {
  const int u = (face_axis + 1) % 3;
  const int v = (face_axis + 2) % 3;
  const int face_bit = face_positive ? 1 << face_axis : 0;
  const auto side_bit = [&](int side) {
    const int tangent = side < 2 ? u : v;
    return side % 2 == 0 ? 1 << tangent : 0;
  };
  const int a = (incident_axis + 1) % 3;
  const int b = (incident_axis + 2) % 3;
  constexpr std::array<int, 4> a_positive = {1, 0, 0, 1};
  constexpr std::array<int, 4> b_positive = {1, 1, 0, 0};
  const auto corner_bits = [&](int i) {
    return (incident_positive ? 1 << incident_axis : 0) | (a_positive[std::size_t(i)] << a) |
           (b_positive[std::size_t(i)] << b);
  };
  if (slot < 4) {
    return {detail::feature::box_face(face_axis, face_positive),
            detail::feature::box_vertex(corner_bits(slot))};
  }
  if (slot < 20) {
    const int i = (slot - 4) / 4;
    const int side = (slot - 4) % 4;
    const int tangent = side < 2 ? u : v;
    return {detail::feature::box_edge(3 - face_axis - tangent, face_bit | side_bit(side)),
            detail::feature::box_edge(i % 2 == 0 ? a : b, corner_bits(i))};
  }
  constexpr std::array<int, 4> u_side = {0, 1, 1, 0};
  constexpr std::array<int, 4> v_side = {2, 2, 3, 3};
  const int j = slot - 20;
  return {detail::feature::box_vertex(face_bit | side_bit(u_side[std::size_t(j)]) |
                                      side_bit(v_side[std::size_t(j)])),
          detail::feature::box_face(incident_axis, incident_positive)};
}

// [face axis][face positive][incident axis][incident positive][slot]
using SlotFeatureTable =
    std::array<std::array<std::array<std::array<std::array<SlotFeatures, 24>, 2>, 3>, 2>, 3>;

constexpr SlotFeatureTable make_slot_feature_table() {
  SlotFeatureTable table{};
  for (int fa = 0; fa < 3; ++fa)
    for (int fp = 0; fp < 2; ++fp)
      for (int ia = 0; ia < 3; ++ia)
        for (int ip = 0; ip < 2; ++ip)
          for (int slot = 0; slot < 24; ++slot)
            table[std::size_t(fa)][std::size_t(fp)][std::size_t(ia)][std::size_t(ip)]
                 [std::size_t(slot)] = face_slot_features(fa, fp != 0, ia, ip != 0, slot);
  return table;
}

constexpr SlotFeatureTable kSlotFeatures = make_slot_feature_table();

// Pairs go through the lanes in chunks: the order of each pair (detail::boxes_run_first) is found
// before a chunk, and the pairs the lanes leave are answered by collide() after it, both outside
// the vector code.
constexpr int kChunk = 64;

}  // namespace

// The lanes file compiled once per instruction set (collision/simd/lane_versions.inc).
#define TUMBLE_LANES_FILE "collision/narrow_phase/box_batch_lanes.inc"
#include "collision/simd/lane_versions.inc"
#undef TUMBLE_LANES_FILE

namespace {

template <class Lists>
using ChunkFunction = int (*)(const BoxPairQuery*, const bool*, int, bool, Manifold*, Lists&);

template <class Lists>
int collide_in_chunks(std::span<const BoxPairQuery> pairs, std::span<Manifold> out,
                      ChunkFunction<Lists> chunk,
                      detail::BoxBatchOrder order = detail::BoxBatchOrder::adaptive) {
  using detail::BoxBatchOrder;
  int points = 0;
  bool classify_first = order != BoxBatchOrder::face_first;
  Lists lists;
  for (std::size_t start = 0; start < pairs.size(); start += kChunk) {
    const int count = int(std::min<std::size_t>(kChunk, pairs.size() - start));
    const BoxPairQuery* chunk_pairs = pairs.data() + start;
    std::array<bool, kChunk> a_first{};
    for (int i = 0; i < count; ++i) {
      const BoxPairQuery& q = chunk_pairs[i];
      a_first[std::size_t(i)] = detail::boxes_run_first(q.half_a, q.pose_a, q.half_b, q.pose_b);
    }
    points += chunk(chunk_pairs, a_first.data(), count, classify_first, out.data() + start, lists);
    // Sorting first pays when many pairs are apart or touch edge to edge: decide by the chunk
    // just done (the data alone decide, so the same input takes the same path; the answers do
    // not depend on it).
    if (order == BoxBatchOrder::adaptive)
      classify_first = 4 * (lists.apart_count + lists.edge_count) >= count;
    for (int k = 0; k < lists.unanswered_count; ++k) {
      const int i = lists.unanswered[std::size_t(k)];
      const BoxPairQuery& q = chunk_pairs[i];
      points += collide(Shape::box(q.half_a), q.pose_a, Shape::box(q.half_b), q.pose_b, q.margin,
                        out[start + std::size_t(i)]);
    }
  }
  return points;
}

}  // namespace

namespace detail {

int collide_box_pairs_avx512(std::span<const BoxPairQuery> pairs, std::span<Manifold> out) {
  return collide_in_chunks(pairs, out, lanes8::collide_chunk);
}

int collide_box_pairs_avx2(std::span<const BoxPairQuery> pairs, std::span<Manifold> out) {
  return collide_in_chunks(pairs, out, lanes4::collide_chunk);
}

int collide_box_pairs_portable(std::span<const BoxPairQuery> pairs, std::span<Manifold> out) {
  return collide_in_chunks(pairs, out, lanes2::collide_chunk);
}

int collide_box_pairs_in_order(std::span<const BoxPairQuery> pairs, std::span<Manifold> out,
                               int lanes, BoxBatchOrder order) {
  switch (lanes) {
    case 8:
      return collide_in_chunks(pairs, out, lanes8::collide_chunk, order);
    case 4:
      return collide_in_chunks(pairs, out, lanes4::collide_chunk, order);
    case 2:
      return collide_in_chunks(pairs, out, lanes2::collide_chunk, order);
    default:
      throw std::invalid_argument("collide_box_pairs_in_order: lanes must be 8, 4 or 2, not " +
                                  std::to_string(lanes));
  }
}

}  // namespace detail

int collide_box_pairs(std::span<const BoxPairQuery> pairs, std::span<Manifold> out) {
  if (out.size() < pairs.size()) {
    throw std::invalid_argument("collide_box_pairs: " + std::to_string(pairs.size()) +
                                " pairs but room for " + std::to_string(out.size()) + " manifolds");
  }
  using Version = int (*)(std::span<const BoxPairQuery>, std::span<Manifold>);
  static const Version version = [] {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f"))
      return Version(detail::collide_box_pairs_avx512);
    if (__builtin_cpu_supports("avx2"))
      return Version(detail::collide_box_pairs_avx2);
    return Version(detail::collide_box_pairs_portable);
  }();
  return version(pairs, out);
}

}  // namespace tumble
