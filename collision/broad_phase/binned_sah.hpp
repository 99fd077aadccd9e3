// One split of a top-down BVH build by the surface area heuristic evaluated at bin boundaries
// (internal): Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies", IEEE
// Symposium on Interactive Ray Tracing 2007. Shared by the dynamic tree's rebuild and the
// linear BVH's binned build.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>

#include "collision/broad_phase/tree_box.hpp"

namespace tumble::detail {

struct BinnedSplit {
  TreeBox bounds;    // of every box in the range
  std::int32_t mid;  // the range splits into [begin, mid) and [mid, end)
};

// Partitions refs[begin, end) (at least two; each with a `.box` TreeBox) at the best of the 15
// boundaries of 16 equal bins of the box centres, on the best axis, by the cost
// A(left) N(left) + A(right) N(right). Coincident centres split in the middle.
template <class Ref>
BinnedSplit binned_sah_split(Ref* refs, std::int32_t begin, std::int32_t end) {
  constexpr int bins = 16;
  constexpr Real inf = std::numeric_limits<Real>::infinity();
  const TreeBox empty = {{inf, inf, inf}, {-inf, -inf, -inf}};
  // Pass 1: the range's box and the bounds of its centres (min + max, twice the centre: only
  // the order matters).
  TreeBox bounds = empty;
  Real lo[3] = {inf, inf, inf};
  Real hi[3] = {-inf, -inf, -inf};
  for (std::int32_t i = begin; i < end; ++i) {
    const TreeBox& b = refs[i].box;
    bounds = TreeBox::merge(bounds, b);
    for (int k = 0; k < 3; ++k) {
      const Real c = b.min[k] + b.max[k];
      lo[k] = std::min(lo[k], c);
      hi[k] = std::max(hi[k], c);
    }
  }
  // Fewer bins than objects would only add empty bins: a small range uses one per object.
  const int nb = std::min(bins, static_cast<int>(end - begin));
  Real scale[3];
  for (int k = 0; k < 3; ++k)
    scale[k] = hi[k] > lo[k] ? nb / (hi[k] - lo[k]) : 0;
  const auto bin_of = [&](const TreeBox& b, int k) {
    return std::min(nb - 1, static_cast<int>((b.min[k] + b.max[k] - lo[k]) * scale[k]));
  };
  // Pass 2: bin on all three axes.
  std::int32_t count[3][bins] = {};
  TreeBox box[3][bins];
  for (int k = 0; k < 3; ++k)
    std::fill(box[k], box[k] + nb, empty);
  for (std::int32_t i = begin; i < end; ++i) {
    const TreeBox& b = refs[i].box;
    for (int k = 0; k < 3; ++k) {
      const int j = bin_of(b, k);
      ++count[k][j];
      box[k][j] = TreeBox::merge(box[k][j], b);
    }
  }
  int best_axis = -1;
  int best_split = 0;
  Real best_cost = inf;
  for (int k = 0; k < 3; ++k) {
    if (scale[k] == 0)
      continue;  // all centres equal on this axis
    // Right-hand sweep: area and count of bins [b, bins).
    Real right_area[bins];
    std::int32_t right_count[bins];
    TreeBox acc = empty;
    std::int32_t cnt = 0;
    for (int b = nb - 1; b > 0; --b) {
      acc = TreeBox::merge(acc, box[k][b]);
      cnt += count[k][b];
      right_area[b] = cnt > 0 ? acc.half_area() : 0;
      right_count[b] = cnt;
    }
    acc = empty;
    cnt = 0;
    for (int b = 1; b < nb; ++b) {  // split between bins b-1 and b
      acc = TreeBox::merge(acc, box[k][b - 1]);
      cnt += count[k][b - 1];
      if (cnt == 0 || right_count[b] == 0)
        continue;
      const Real cost = acc.half_area() * cnt + right_area[b] * right_count[b];
      if (cost < best_cost) {
        best_cost = cost;
        best_axis = k;
        best_split = b;
      }
    }
  }
  // Pass 3: partition.
  if (best_axis < 0)
    return {bounds, begin + (end - begin) / 2};
  const auto it = std::partition(refs + begin, refs + end, [&](const Ref& r) {
    return bin_of(r.box, best_axis) < best_split;
  });
  return {bounds, static_cast<std::int32_t>(it - refs)};
}

}  // namespace tumble::detail
