// Internal to the narrow phase: gathers the contacts of several sub-pairs (the triangles of a
// mesh under a convex shape, the parts of a compound) into one manifold. The engine keeps one
// manifold, with one normal, per body pair, so the sub-contacts are merged onto the normal of
// the deepest one: each point keeps its position on A, its depth is measured along the common
// normal (depth times the cosine between the normals), points whose normal is more than 60
// degrees from it are left out, and the rest are reduced to four by manifold_reduction (deepest,
// farthest, largest area). Exact duplicates (two coplanar triangles giving the same face contact
// at their shared edge) are kept once, and of points closer together than a merge distance only
// the deepest is kept: a corner on a mesh vertex where several triangles meet gets a contact from
// each, a hair apart, and four such rows are one row four times over for the solver (its block
// solve of a manifold's rows is then singular in all but one direction).
//
// Fixed capacity and no allocation: when full, a deeper candidate replaces the shallowest.
#pragma once

#include <array>
#include <cstdint>

#include "collision/contact.hpp"

namespace tumble::detail {

class ContactCollector {
 public:
  static constexpr int kCapacity = 64;
  // The merge distance the pairs use, as a fraction of the convex (or compound) shape's bounding
  // radius: points closer than this add nothing to how the manifold holds the body up.
  static constexpr Real kMergeFraction = Real(0.01);

  // `normal` from B to A, unit; `point_on_a` and the depth as in ContactPoint; `kind` tells where
  // the candidate came from, for the normal rules below.
  void add(const Vec3& normal, const Vec3& point_on_a, Real depth, FeatureId feature,
           std::uint8_t kind = 0);
  bool empty() const { return count_ == 0; }
  // Which normal the manifold takes: the deepest candidate's, or the mean of the normals within
  // 60 degrees of it weighted by how deep each point is (depth + margin), for surfaces whose
  // normal turns from point to point (a field's): a box resting in a round bowl then gets the
  // bowl's axis, not the tilt of whichever corner is a hair deeper, and stays where it is put.
  // The mean may be kept to the candidates whose normal is the better guess, the others keeping
  // their points and depths:
  //  - weighted_mean_of_deepest_kind: those of the deepest candidate's kind (a hull's corner
  //    poking into a curved field is a point of the hull in the field, whose gradient is the
  //    normal; a field bulging into a hull's face is a point of the field in the hull, whose
  //    nearest face gives it);
  //  - weighted_mean_of_kind_zero: those of kind 0 while one lies within the 60 degrees (a flat
  //    mesh face's points measured in a field lean toward the field's centre; the field's points
  //    under the face carry the face's normal).
  enum class NormalRule {
    deepest,
    weighted_mean,
    weighted_mean_of_deepest_kind,
    weighted_mean_of_kind_zero
  };
  // Writes the merged manifold (at most 4 points with depth >= -margin, no two closer than
  // `merge_distance`) and returns its count.
  int finish(Real margin, Real merge_distance, Manifold& out,
             NormalRule rule = NormalRule::deepest) const;

 private:
  struct Candidate {
    Vec3 normal;
    Vec3 point_on_a;
    Real depth;
    FeatureId feature;
    std::uint8_t kind;
  };
  std::array<Candidate, kCapacity> candidates_;
  int count_ = 0;
};

}  // namespace tumble::detail
