// Small geometry helpers every part of tumble shares, on the public aliases of
// include/tumble/math.hpp.
#pragma once

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

}  // namespace tumble
