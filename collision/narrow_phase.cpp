// The narrow phase entry point and its dispatch table (seed 4.1.4; the table reads like
// MuJoCo's mjCOLLISIONFUNC). Each unordered pair of shape types has one pair function, written
// for one order (collision/pairs/); the table runs it directly or through `flipped`, which swaps
// the arguments and then flips the normal and swaps the feature ids. So calling with A and B
// swapped gives the mirrored answer by construction, bit for bit.
//
// Pair-local frame: every pair function runs with the translations re-expressed relative to the
// first shape of its own order (the sphere in sphere-box, the bounded shape against a plane), and
// the contact positions are moved back at the end. Bodies 1e6 m from the origin then keep the
// precision they have at the origin, a plane's translation can be anywhere on the plane, and a
// swapped call runs exactly the same arithmetic as the unswapped one.
//
// Two shapes of the same type have no natural order, so `ordered` picks one with a fixed rule
// (runs_first below) that depends on the shapes and poses but not on the argument order.
#include "collision/narrow_phase.hpp"

#include <array>
#include <cmath>
#include <tuple>

#include "collision/pairs/pairs.hpp"

namespace tumble {
namespace {

using detail::PairFunction;

template <PairFunction pair>
int in_pair_frame(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
                  Real margin, Manifold& out) {
  const Vec3 origin = pose_a.translation;
  const Transform local_a{Vec3::Zero(), pose_a.rotation};
  const Transform local_b{pose_b.translation - origin, pose_b.rotation};
  const int count = pair(a, local_a, b, local_b, margin, out);
  for (int i = 0; i < count; ++i)
    out.points[i].position += origin;
  return count;
}

template <PairFunction pair>
int flipped(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out) {
  const int count = in_pair_frame<pair>(b, pose_b, a, pose_a, margin, out);
  out.normal = -out.normal;
  for (int i = 0; i < count; ++i)
    out.points[i].feature = out.points[i].feature.swapped();
  return count;
}

// Whether `a` goes first in a same-type pair. The shapes' dimensions decide first (they never
// change, so the order is stable for the life of the pair); equal shapes are ordered by their
// offset along a fixed generic direction (1, sqrt2, sqrt3)/sqrt6, which no axis-aligned or
// diagonal offset is perpendicular to, so the order of two bodies stacked, side by side or in a
// row does not flip from noise. Exact ties fall to the pose coefficients.
bool runs_first(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b) {
  const auto dimensions = [](const Shape& s) {
    return std::make_tuple(s.radius, s.half_length, s.half_extents.x(), s.half_extents.y(),
                           s.half_extents.z());
  };
  if (dimensions(a) != dimensions(b))
    return dimensions(a) < dimensions(b);
  // (1, sqrt2, sqrt3) / sqrt6
  constexpr Real kGeneric[3] = {Real(0.40824829046386302), Real(0.57735026918962584),
                                Real(0.70710678118654757)};
  const Vec3 offset = pose_a.translation - pose_b.translation;
  const Real along = kGeneric[0] * offset.x() + kGeneric[1] * offset.y() + kGeneric[2] * offset.z();
  if (along != 0)
    return along < 0;
  const auto coefficients = [](const Transform& p) {
    return std::make_tuple(p.translation.x(), p.translation.y(), p.translation.z(), p.rotation.w(),
                           p.rotation.x(), p.rotation.y(), p.rotation.z());
  };
  return coefficients(pose_a) <= coefficients(pose_b);
}

template <PairFunction pair>
int ordered(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out) {
  return runs_first(a, pose_a, b, pose_b) ? in_pair_frame<pair>(a, pose_a, b, pose_b, margin, out)
                                          : flipped<pair>(a, pose_a, b, pose_b, margin, out);
}

int no_contact(const Shape&, const Transform&, const Shape&, const Transform&, Real, Manifold&) {
  // Planes and meshes are static: two static shapes never need contacts (plane-plane,
  // plane-mesh, mesh-mesh).
  return 0;
}

// Cylinder and hull pairs belong to the convex core (GJK/EPA, branch `narrow`); until it is
// merged their cells report no contact.
int not_implemented(const Shape&, const Transform&, const Shape&, const Transform&, Real,
                    Manifold&) {
  return 0;
}

static_assert(int(ShapeType::sphere) == 0 && int(ShapeType::box) == 1 &&
                  int(ShapeType::capsule) == 2 && int(ShapeType::plane) == 3 &&
                  int(ShapeType::cylinder) == 4 && int(ShapeType::hull) == 5 &&
                  int(ShapeType::mesh) == 6 && int(ShapeType::compound) == 7 &&
                  kShapeTypeCount == 8,
              "the table below is indexed by ShapeType");

using namespace detail;

// collide_table[type of A][type of B]: `in_pair_frame<f>` runs f as written, `flipped<f>` runs
// f with the arguments swapped and mirrors its answer, `ordered<f>` does one or the other for
// two shapes of one type.
// clang-format off
constexpr PairFunction cyl = not_implemented;
constexpr std::array<std::array<PairFunction, kShapeTypeCount>, kShapeTypeCount> collide_table = {{
  //              sphere                    box                         capsule                       plane                          cylinder hull mesh                         compound
  /* sphere  */ {{ordered<sphere_sphere>,  in_pair_frame<sphere_box>,  in_pair_frame<sphere_capsule>, in_pair_frame<sphere_plane>,  cyl, cyl, in_pair_frame<convex_mesh>,  flipped<compound_any>}},
  /* box     */ {{flipped<sphere_box>,     ordered<box_box>,           flipped<capsule_box>,          in_pair_frame<box_plane>,     cyl, cyl, in_pair_frame<convex_mesh>,  flipped<compound_any>}},
  /* capsule */ {{flipped<sphere_capsule>, in_pair_frame<capsule_box>, ordered<capsule_capsule>,      in_pair_frame<capsule_plane>, cyl, cyl, in_pair_frame<convex_mesh>,  flipped<compound_any>}},
  /* plane   */ {{flipped<sphere_plane>,   flipped<box_plane>,         flipped<capsule_plane>,        no_contact,                   cyl, cyl, no_contact,                  flipped<compound_any>}},
  /* cylinder*/ {{cyl,                     cyl,                        cyl,                           cyl,                          cyl, cyl, in_pair_frame<convex_mesh>,  flipped<compound_any>}},
  /* hull    */ {{cyl,                     cyl,                        cyl,                           cyl,                          cyl, cyl, in_pair_frame<convex_mesh>,  flipped<compound_any>}},
  /* mesh    */ {{flipped<convex_mesh>,    flipped<convex_mesh>,       flipped<convex_mesh>,          no_contact,                   flipped<convex_mesh>, flipped<convex_mesh>, no_contact, flipped<compound_any>}},
  /* compound*/ {{in_pair_frame<compound_any>, in_pair_frame<compound_any>, in_pair_frame<compound_any>, in_pair_frame<compound_any>, in_pair_frame<compound_any>, in_pair_frame<compound_any>, in_pair_frame<compound_any>, ordered<compound_any>}},
}};
// clang-format on

}  // namespace

int collide(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out) {
  out = Manifold{};
  const int count =
      collide_table[std::size_t(a.type)][std::size_t(b.type)](a, pose_a, b, pose_b, margin, out);
  // No points, no normal: an empty manifold looks the same whichever way it was asked.
  if (count == 0)
    out = Manifold{};
  return count;
}

}  // namespace tumble
