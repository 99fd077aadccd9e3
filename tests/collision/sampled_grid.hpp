// A dense SDF grid sampled from an exact field at its nodes, for the tests and benchmarks of
// grids.
#pragma once

#include <array>
#include <cstddef>
#include <utility>
#include <vector>

#include "collision/sdf/sdf_grid.hpp"

namespace tumble::test {

// The grid of n[0] x n[1] x n[2] nodes `cell` apart from `origin` (x fastest), each holding
// exact(node).
template <class Exact>
SdfGrid sampled_grid(const Vec3& origin, Real cell, const std::array<int, 3>& n,
                     const Exact& exact) {
  std::vector<Real> values;
  values.reserve(std::size_t(n[0]) * std::size_t(n[1]) * std::size_t(n[2]));
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        values.push_back(exact(origin + cell * Vec3(Real(i), Real(j), Real(k))));
  return SdfGrid(origin, cell, n, std::move(values));
}

}  // namespace tumble::test
