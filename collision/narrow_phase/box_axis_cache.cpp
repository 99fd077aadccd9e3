#include "collision/narrow_phase/box_axis_cache.hpp"

#include <cmath>
#include <limits>

namespace tumble {

namespace {

// Edge axes shorter than this (sine of the edges' angle) have no reliable direction; the face
// axes cover near-parallel edges (as in collision/narrow_phase/pairs/box_box.cpp).
constexpr Real kMinCrossSine = Real(1e-6);
// Separations are trusted beyond rounding only when they exceed the margin by this share of the
// pair's size: far below any separation that matters, far above the rounding of a few products.
constexpr Real kRelativeBand = Real(1e-9);

struct PairFrame {
  Mat3 r;      // B's axes in A's frame (columns)
  Mat3 abs_r;  // |r|
  Vec3 t;      // B's centre in A's frame
};

PairFrame pair_frame(const Transform& pose_a, const Transform& pose_b) {
  PairFrame f;
  const Quat back = pose_a.rotation.conjugate();
  f.r = (back * pose_b.rotation).toRotationMatrix();
  f.abs_r = f.r.cwiseAbs();
  f.t = back * (pose_b.translation - pose_a.translation);
  return f;
}

Real separation_in_frame(const Vec3& ha, const Vec3& hb, const PairFrame& f, std::uint8_t axis) {
  if (axis < 3) {
    const int i = axis;
    return std::abs(f.t[i]) - (ha[i] + f.abs_r.row(i).dot(hb));
  }
  if (axis < 6) {
    const int j = axis - 3;
    return std::abs(f.t.dot(f.r.col(j))) - (f.abs_r.col(j).dot(ha) + hb[j]);
  }
  if (axis < 15) {
    const int i = (axis - 6) / 3;
    const int j = (axis - 6) % 3;
    // L = e_i x r_j in A's frame; its length is sqrt(1 - r_ij^2), written without cancellation.
    const Vec3 l = Vec3::Unit(i).cross(f.r.col(j));
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    const Real length = std::sqrt(f.r(i1, j) * f.r(i1, j) + f.r(i2, j) * f.r(i2, j));
    if (!(length > kMinCrossSine))
      return -std::numeric_limits<Real>::infinity();
    // B's extent along L: sum over B's axes k of hb_k |r_k . L|.
    const Vec3 l_in_b = f.r.transpose() * l;
    const Real extent = l.cwiseAbs().dot(ha) + l_in_b.cwiseAbs().dot(hb);
    return (std::abs(f.t.dot(l)) - extent) / length;
  }
  return -std::numeric_limits<Real>::infinity();
}

Real band(const Vec3& ha, const Vec3& hb, const PairFrame& f, Real margin) {
  return kRelativeBand * (f.t.cwiseAbs().maxCoeff() + ha.maxCoeff() + hb.maxCoeff() + margin);
}

}  // namespace

Real box_axis_separation(const Vec3& half_a, const Transform& pose_a, const Vec3& half_b,
                         const Transform& pose_b, std::uint8_t axis) {
  return separation_in_frame(half_a, half_b, pair_frame(pose_a, pose_b), axis);
}

bool box_axis_separates(const Vec3& half_a, const Transform& pose_a, const Vec3& half_b,
                        const Transform& pose_b, std::uint8_t axis, Real margin) {
  if (axis >= 15)
    return false;
  const PairFrame f = pair_frame(pose_a, pose_b);
  return separation_in_frame(half_a, half_b, f, axis) > margin + band(half_a, half_b, f, margin);
}

std::uint8_t best_separating_box_axis(const Vec3& half_a, const Transform& pose_a,
                                      const Vec3& half_b, const Transform& pose_b, Real margin) {
  const PairFrame f = pair_frame(pose_a, pose_b);
  Real best = margin + band(half_a, half_b, f, margin);
  std::uint8_t best_axis = kNoBoxAxis;
  for (std::uint8_t axis = 0; axis < 15; ++axis) {
    const Real s = separation_in_frame(half_a, half_b, f, axis);
    if (s > best) {
      best = s;
      best_axis = axis;
    }
  }
  return best_axis;
}

}  // namespace tumble
