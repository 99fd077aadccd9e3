// Interpolation of values at the nodes of a regular grid, with the exact gradient of the
// interpolant: trilinear (C0) and tricubic (Catmull-Rom in each axis, C1; Catmull and Rom, "A
// class of local interpolating splines", 1974). Shared by tumble's dense grid
// (collision/sdf/sdf_grid.hpp) and OpenVDB's sparse level sets (collision/sdf/vdb_level_set.hpp),
// which differ only in how a node's value is fetched.
#pragma once

#include "collision/math.hpp"
#include "collision/sdf/sdf_primitives.hpp"

namespace tumble {

enum class GridInterpolation : std::uint8_t { trilinear, tricubic };

namespace sdf {

// Catmull-Rom weights of the four nodes around a point at fraction t of its cell, and their
// derivatives in t.
inline void catmull_rom(Real t, Real w[4], Real dw[4]) {
  const Real t2 = t * t, t3 = t2 * t;
  w[0] = (-t3 + 2 * t2 - t) / 2;
  w[1] = (3 * t3 - 5 * t2 + 2) / 2;
  w[2] = (-3 * t3 + 4 * t2 + t) / 2;
  w[3] = (t3 - t2) / 2;
  dw[0] = (-3 * t2 + 4 * t - 1) / 2;
  dw[1] = (9 * t2 - 10 * t) / 2;
  dw[2] = (-9 * t2 + 8 * t + 1) / 2;
  dw[3] = (3 * t2 - 2 * t) / 2;
}

// The interpolant at fraction t (each in [0, 1]) of the cell whose lowest node is `cell_index`,
// for cells of size h; value(i, j, k) fetches a node's value (tricubic asks for the nodes one
// before and two after the cell along each axis: the fetch clamps or pads as its grid needs).
template <class Value>
Sample interpolate(const int cell_index[3], const Real t[3], Real h, GridInterpolation how,
                   Value&& value) {
  Sample s;
  s.distance = 0;
  s.gradient = Vec3::Zero();
  if (how == GridInterpolation::trilinear) {
    for (int c = 0; c < 8; ++c) {
      const int ox = c & 1, oy = (c >> 1) & 1, oz = (c >> 2) & 1;
      const Real v = value(cell_index[0] + ox, cell_index[1] + oy, cell_index[2] + oz);
      const Real wx = ox ? t[0] : 1 - t[0], wy = oy ? t[1] : 1 - t[1], wz = oz ? t[2] : 1 - t[2];
      const Real gx = ox ? 1 : -1, gy = oy ? 1 : -1, gz = oz ? 1 : -1;
      s.distance += wx * wy * wz * v;
      s.gradient += v * Vec3(gx * wy * wz, wx * gy * wz, wx * wy * gz);
    }
    s.gradient /= h;
    return s;
  }
  Real w[3][4], dw[3][4];
  for (int k = 0; k < 3; ++k)
    catmull_rom(t[k], w[k], dw[k]);
  for (int c = 0; c < 4; ++c)
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a) {
        const Real v = value(cell_index[0] + a - 1, cell_index[1] + b - 1, cell_index[2] + c - 1);
        s.distance += w[0][a] * w[1][b] * w[2][c] * v;
        s.gradient += v * Vec3(dw[0][a] * w[1][b] * w[2][c], w[0][a] * dw[1][b] * w[2][c],
                               w[0][a] * w[1][b] * dw[2][c]);
      }
  s.gradient /= h;
  return s;
}

}  // namespace sdf
}  // namespace tumble
