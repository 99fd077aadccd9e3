// Small geometry helpers every part of tumble shares, on the public aliases of
// include/tumble/math.hpp.
#pragma once

#include <array>

#include "tumble/math.hpp"

namespace tumble {

inline Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Two unit vectors completing `n` to a right-handed orthonormal basis. Branch-free choice from
// Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017.
inline void orthonormal_basis(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Real sign = n.z() >= 0 ? Real(1) : Real(-1);
  const Real a = Real(-1) / (sign + n.z());
  const Real b = n.x() * n.y() * a;
  t1 = Vec3(Real(1) + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  t2 = Vec3(b, sign + n.y() * n.y() * a, -n.y());
}

// A symmetric matrix kept as its upper triangle, row by row: xx, xy, xz, yy, yz, zz.
using PackedSymmetric = std::array<Real, 6>;

inline PackedSymmetric packed_symmetric(const Mat3& m) {
  return {m(0, 0), m(0, 1), m(0, 2), m(1, 1), m(1, 2), m(2, 2)};
}

inline Mat3 unpacked_symmetric(const PackedSymmetric& p) {
  Mat3 m;
  m << p[0], p[1], p[2], p[1], p[3], p[4], p[2], p[4], p[5];
  return m;
}

}  // namespace tumble
