// Transform's rotations (include/tumble/math.hpp) are written out rather than Eigen's quaternion
// product, so that they inline; they must be Eigen's to the bit (the golden state hashes rest on
// it): random unit and non-unit quaternions, axis turns, the identity, and vectors from tiny to
// huge, signed zeros among them.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tumble/math.hpp"

namespace tumble {
namespace {

bool same_bits(const Vec3& a, const Vec3& b) {
  for (int i = 0; i < 3; ++i) {
    if (!(a[i] == b[i] && std::signbit(a[i]) == std::signbit(b[i])))
      return false;
  }
  return true;
}

TEST(Transform, RotationsAreEigensQuaternionProductToTheBit) {
  std::mt19937_64 rng(3121);
  std::normal_distribution<Real> n(0, 1);
  std::uniform_int_distribution<int> exponent(-30, 30);
  const auto vector = [&](int k) -> Vec3 {
    switch (k % 5) {
      case 0:
        return Vec3(0, -0.0, n(rng));
      case 1:
        return Vec3(n(rng), n(rng), n(rng)) * std::ldexp(Real(1), exponent(rng));
      default:
        return Vec3(n(rng), n(rng), n(rng));
    }
  };
  for (int k = 0; k < 100000; ++k) {
    Quat q;
    switch (k % 4) {
      case 0:
        q = Quat::Identity();
        break;
      case 1:
        q = Quat(Eigen::AngleAxis<Real>(Real(M_PI / 2), Vec3::Unit(k % 3)));
        break;
      case 2:
        q = Quat(n(rng), n(rng), n(rng), n(rng));  // not normalised: the formula is the same
        break;
      default:
        q = Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
    }
    const Transform t{vector(k + 1), q};
    const Vec3 v = vector(k);
    ASSERT_TRUE(same_bits(t.rotate(v), q * v)) << k;
    ASSERT_TRUE(same_bits(t.rotate_inverse(v), q.conjugate() * v)) << k;
    ASSERT_TRUE(same_bits(t.apply(v), q * v + t.translation)) << k;
    ASSERT_TRUE(same_bits(t.apply_inverse(v), q.conjugate() * (v - t.translation))) << k;
  }
}

}  // namespace
}  // namespace tumble
