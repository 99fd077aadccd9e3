// A compound shape: several convex primitives, each with a pose in the compound's frame. The
// compound is re-centred at its centre of mass when built, so that, like every other shape, its
// local frame has the centre of mass at the origin; `build` reports the shift so a loader can
// move the body by it and leave the parts where the author put them.
//
// Mass properties assume one uniform density over all parts and parts that do not overlap
// (overlaps are counted twice, as in Bullet's btCompoundShape::calculatePrincipalAxisTransform):
// volumes add, and each part's inertia is moved to the common centre of mass by the
// parallel-axis theorem, I = R I_part R^T + m (|d|^2 E - d d^T).
#pragma once

#include <stdexcept>
#include <vector>

#include "collision/aabb.hpp"
#include "tumble/shape.hpp"

namespace tumble {

struct CompoundError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

class CompoundShape {
 public:
  // Parts may be spheres, boxes, capsules, cylinders or hulls (bounded convex shapes); at most
  // kMaxParts of them. `centre_of_mass` receives the centre of mass of the parts as given, in
  // the frame they were given in; the stored part poses are shifted by minus that. Throws
  // CompoundError naming the part on bad input.
  static constexpr int kMaxParts = 256;  // the part index is 8 bits of a feature id
  // With `recentre` false (a training shape, which stays in its body's frame) the poses are kept
  // as given and unit_inertia() is about the frame's origin.
  static CompoundShape build(std::vector<CompoundPart> parts, Vec3* centre_of_mass = nullptr,
                             bool recentre = true);

  const std::vector<CompoundPart>& parts() const { return parts_; }
  Real volume() const { return volume_; }
  const Mat3& unit_inertia() const { return unit_inertia_; }
  Real bounding_radius() const { return bounding_radius_; }
  Vec3 support(const Vec3& direction) const;
  Aabb world_aabb(const Transform& pose) const;

 private:
  std::vector<CompoundPart> parts_;
  Real volume_ = 0;
  Mat3 unit_inertia_ = Mat3::Zero();
  Real bounding_radius_ = 0;
};

// The pose of a part in the world: compound pose composed with the part's local pose.
inline Transform compose(const Transform& outer, const Transform& inner) {
  return {outer.apply(inner.translation), outer.rotation * inner.rotation};
}

}  // namespace tumble
