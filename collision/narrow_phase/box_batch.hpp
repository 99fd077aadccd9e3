// Box-box contact manifolds for many pairs at once (docs/narrow-phase.md, "Many box pairs at
// once"): the separating-axis test, the face clipping and the choice of four points of eight
// pairs run side by side, one pair per vector lane, with no branch on any pair's geometry.
//
// Each pair is answered as collide() answers it: the same order of the two boxes (so the normal
// points from B to A of the query), the same axis and normal up to rounding, the same number of
// points, each a vertex of the same overlap polygon with the same depth and feature ids up to
// rounding; where the choice of four points among more has exact ties, another of the tied
// vertices may be kept. Pairs that the vector pass does not cover (apart but within the margin,
// non-finite poses, rounding cases the clipper flags) are answered by collide() itself.
#pragma once

#include <span>

#include "collision/contact.hpp"
#include "collision/math.hpp"

namespace tumble {

struct BoxPairQuery {
  Vec3 half_a;
  Transform pose_a;
  Vec3 half_b;
  Transform pose_b;
  Real margin = 0;  // as collide()'s: points up to this far apart are kept
};

// out[i] gets the manifold of pairs[i] (out.size() >= pairs.size()); returns the total number of
// contact points. Allocates nothing.
int collide_box_pairs(std::span<const BoxPairQuery> pairs, std::span<Manifold> out);

namespace detail {
// The instruction-set versions, for tests (calling one on a CPU without its instructions is an
// illegal instruction); collide_box_pairs runs the best the CPU has.
int collide_box_pairs_avx512(std::span<const BoxPairQuery> pairs, std::span<Manifold> out);
int collide_box_pairs_avx2(std::span<const BoxPairQuery> pairs, std::span<Manifold> out);
int collide_box_pairs_portable(std::span<const BoxPairQuery> pairs, std::span<Manifold> out);

// For tests: the version of `lanes` lanes (8: AVX-512, 4: AVX2, 2: baseline) with the order of
// passes forced for every chunk (sorted by the separating-axis test first, or the face pass
// first) or chosen as collide_box_pairs chooses it. Every order gives the same bits.
enum class BoxBatchOrder { adaptive, sort_first, face_first };
int collide_box_pairs_in_order(std::span<const BoxPairQuery> pairs, std::span<Manifold> out,
                               int lanes, BoxBatchOrder order);
}  // namespace detail

}  // namespace tumble
