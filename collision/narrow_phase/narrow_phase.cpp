// The narrow phase entry point and its dispatch table (the table reads like MuJoCo's
// mjCOLLISIONFUNC). Each unordered pair of shape types has one pair function, written
// for one order (collision/narrow_phase/pairs/); the table runs it directly or through `flipped`,
// which swaps the arguments and then flips the normal and swaps the feature ids. So calling with A
// and B swapped gives the mirrored answer by construction, bit for bit.
//
// Pair-local frame: every pair function runs with the translations re-expressed relative to the
// first shape of its own order (the sphere in sphere-box, the bounded shape against a plane), and
// the contact positions are moved back at the end. Bodies 1e6 m from the origin then keep the
// precision they have at the origin, a plane's translation can be anywhere on the plane, and a
// swapped call runs exactly the same arithmetic as the unswapped one. The one exception is
// sphere-sphere: its function is symmetric in A and B by construction and runs on the world
// translations as they are (their difference is as precise as in a pair frame), which keeps it
// cheap enough to batch (collision/narrow_phase/sphere_batch.hpp gives the same bits over arrays).
//
// Two shapes of the same type have no natural order, so `ordered` picks one with a fixed rule
// (runs_first below) that depends on the shapes and poses but not on the argument order.
#include "collision/narrow_phase/narrow_phase.hpp"

#include <array>
#include <cmath>
#include <span>
#include <tuple>
#include <utility>

#include "collision/narrow_phase/compound_collide.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"
#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/triangle_mesh.hpp"

namespace tumble {

namespace detail {

namespace {

int compare_values(Real x, Real y) {
  return x < y ? -1 : (y < x ? 1 : 0);
}

int compare_poses(const Transform& p, const Transform& q) {
  const std::array<Real, 7> x{p.translation.x(), p.translation.y(), p.translation.z(),
                              p.rotation.w(),    p.rotation.x(),    p.rotation.y(),
                              p.rotation.z()};
  const std::array<Real, 7> y{q.translation.x(), q.translation.y(), q.translation.z(),
                              q.rotation.w(),    q.rotation.x(),    q.rotation.y(),
                              q.rotation.z()};
  for (std::size_t k = 0; k < x.size(); ++k)
    if (const int c = compare_values(x[k], y[k]))
      return c;
  return 0;
}

// Two shapes of equal dimensions: ordered by their offset along a fixed generic direction (1,
// sqrt2, sqrt3)/sqrt6, which no axis-aligned or diagonal offset is perpendicular to, so the order
// of two bodies stacked, side by side or in a row does not flip from noise. Exact ties fall to the
// pose coefficients.
bool runs_first_by_pose(const Transform& pose_a, const Transform& pose_b) {
  constexpr Real kGeneric[3] = {Real(0.40824829046386302), Real(0.57735026918962584),
                                Real(0.70710678118654757)};
  const Vec3 offset = pose_a.translation - pose_b.translation;
  const Real along = kGeneric[0] * offset.x() + kGeneric[1] * offset.y() + kGeneric[2] * offset.z();
  if (along != 0)
    return along < 0;
  return compare_poses(pose_a, pose_b) <= 0;
}

int compare_points(std::span<const Vec3> p, std::span<const Vec3> q) {
  if (p.size() != q.size())
    return p.size() < q.size() ? -1 : 1;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (const int c = compare_values(p[i][k], q[i][k]))
        return c;
  return 0;
}

// -1, 0 or 1: an order on shapes by everything they are made of (dimensions, vertices, parts and
// their poses, a field's surface points), never by address. Only asked when the summaries of
// runs_first tie and the poses are equal, so its cost (a walk over the data) is paid almost never.
int compare_content(const Shape& a, const Shape& b) {
  if (a.type != b.type)
    return a.type < b.type ? -1 : 1;
  for (const auto& [x, y] : {std::pair{a.radius, b.radius},
                             {a.half_length, b.half_length},
                             {a.half_extents.x(), b.half_extents.x()},
                             {a.half_extents.y(), b.half_extents.y()},
                             {a.half_extents.z(), b.half_extents.z()},
                             {a.field_time, b.field_time}})
    if (const int c = compare_values(x, y))
      return c;
  if (a.hull && b.hull && a.hull != b.hull)
    return compare_points(a.hull->vertices(), b.hull->vertices());
  if (a.mesh && b.mesh && a.mesh != b.mesh)
    return compare_points(a.mesh->vertices(), b.mesh->vertices());
  if (a.sdf && b.sdf && a.sdf != b.sdf)
    return compare_points(a.sdf->surface_points(), b.sdf->surface_points());
  if (a.compound && b.compound && a.compound != b.compound) {
    const auto& p = a.compound->parts();
    const auto& q = b.compound->parts();
    if (p.size() != q.size())
      return p.size() < q.size() ? -1 : 1;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (const int c = compare_poses(p[i].pose, q[i].pose))
        return c;
      if (const int c = compare_content(p[i].shape, q[i].shape))
        return c;
    }
  }
  return 0;
}

}  // namespace

// Whether `a` goes first in a same-type pair (declared in pairs.hpp). The shapes' dimensions
// decide first (they never change, so the order is stable for the life of the pair); equal shapes
// are ordered by their poses.
bool runs_first(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b) {
  // Hulls, compounds and fields are summarised by content (volume, vertex or part count), never
  // by address, so the order is the same in every run. Two that differ only where these do not
  // look (two fields of one volume) fall to their poses; at one pose, to the whole of their
  // content (compare_content); twins (the same shape at the same pose) have no order.
  const auto dimensions = [](const Shape& s) {
    const Real hull_volume = s.hull ? s.hull->volume() : Real(0);
    const int hull_vertices = s.hull ? int(s.hull->vertices().size()) : 0;
    const Real compound_volume = s.compound ? s.compound->volume() : Real(0);
    const int compound_parts = s.compound ? int(s.compound->parts().size()) : 0;
    const Real field_volume = s.sdf ? s.sdf->volume() : Real(0);
    const Real field_radius = s.sdf ? s.sdf->bounding_radius() : Real(0);
    return std::make_tuple(s.radius, s.half_length, s.half_extents.x(), s.half_extents.y(),
                           s.half_extents.z(), hull_volume, hull_vertices, compound_volume,
                           compound_parts, field_volume, field_radius);
  };
  const auto summary_a = dimensions(a);
  const auto summary_b = dimensions(b);
  if (summary_a != summary_b)
    return summary_a < summary_b;
  if (compare_poses(pose_a, pose_b) != 0)
    return runs_first_by_pose(pose_a, pose_b);
  return compare_content(a, b) <= 0;
}

// runs_first for two boxes, whose other dimensions are all 0, without making Shapes.
bool boxes_run_first(const Vec3& half_a, const Transform& pose_a, const Vec3& half_b,
                     const Transform& pose_b) {
  const auto extents = [](const Vec3& h) { return std::make_tuple(h.x(), h.y(), h.z()); };
  if (extents(half_a) != extents(half_b))
    return extents(half_a) < extents(half_b);
  return runs_first_by_pose(pose_a, pose_b);
}

}  // namespace detail

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

template <PairFunction pair>
int ordered(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out) {
  return detail::runs_first(a, pose_a, b, pose_b)
             ? in_pair_frame<pair>(a, pose_a, b, pose_b, margin, out)
             : flipped<pair>(a, pose_a, b, pose_b, margin, out);
}

int no_contact(const Shape&, const Transform&, const Shape&, const Transform&, Real, Manifold&) {
  // Planes and meshes are static: two static shapes never need contacts (plane-plane,
  // plane-mesh, mesh-mesh).
  return 0;
}

static_assert(int(ShapeType::sphere) == 0 && int(ShapeType::box) == 1 &&
                  int(ShapeType::capsule) == 2 && int(ShapeType::plane) == 3 &&
                  int(ShapeType::cylinder) == 4 && int(ShapeType::hull) == 5 &&
                  int(ShapeType::mesh) == 6 && int(ShapeType::compound) == 7 &&
                  int(ShapeType::sdf) == 8 && kShapeTypeCount == 9,
              "the table below is indexed by ShapeType");

using namespace detail;

// Short names so the table reads as a grid.
template <PairFunction f>
constexpr PairFunction as = in_pair_frame<f>;
template <PairFunction f>
constexpr PairFunction fl = flipped<f>;
template <PairFunction f>
constexpr PairFunction same = ordered<f>;
constexpr PairFunction cvx = in_pair_frame<convex_convex>;
constexpr PairFunction xvc = flipped<convex_convex>;

// collide_table[type of A][type of B]: `as<f>` runs f as written, `fl<f>` runs f with the
// arguments swapped and mirrors its answer, `same<f>` does one or the other for two shapes of one
// type; sphere_sphere is called as it is (symmetric by construction). cvx / xvc: the generic
// GJK/EPA pair (convex_pairs.cpp), as written / flipped; hull-hull has its own separating-axis
// pair (hull_hull_sat.cpp: faster than GJK+EPA and exact, see docs/narrow-phase-benchmark.md).
// Signed distance fields meet everything through any_sdf and each other through sdf_sdf
// (sdf_pairs.cpp); a compound meets them part by part.
// Planes
// and meshes are static, so plane-plane, plane-mesh and mesh-mesh never need contacts.
// clang-format off
constexpr std::array<std::array<PairFunction, kShapeTypeCount>, kShapeTypeCount> collide_table = {{
  //              sphere              box                 capsule                 plane                  cylinder                  hull                    mesh             compound            sdf
  /* sphere   */ {{sphere_sphere,      as<sphere_box>,   as<sphere_capsule>,     as<sphere_plane>,      as<sphere_cylinder>,      cvx,                    as<convex_mesh>, fl<compound_any>,   as<any_sdf>}},
  /* box      */ {{fl<sphere_box>,    same<box_box>,      fl<capsule_box>,        as<box_plane>,         cvx,                      cvx,                    as<convex_mesh>, fl<compound_any>,   as<any_sdf>}},
  /* capsule  */ {{fl<sphere_capsule>, as<capsule_box>,   same<capsule_capsule>,  as<capsule_plane>,     as<capsule_cylinder>,     cvx,                    as<convex_mesh>, fl<compound_any>,   as<any_sdf>}},
  /* plane    */ {{fl<sphere_plane>,  fl<box_plane>,      fl<capsule_plane>,      no_contact,            fl<cylinder_plane>,       fl<hull_plane>,         no_contact,      fl<compound_any>,   as<any_sdf>}},
  /* cylinder */ {{fl<sphere_cylinder>, xvc,              fl<capsule_cylinder>,   as<cylinder_plane>,    same<convex_convex>,      cvx,                    as<convex_mesh>, fl<compound_any>,   as<any_sdf>}},
  /* hull     */ {{xvc,               xvc,                xvc,                    as<hull_plane>,        xvc,                      same<hull_hull>,        as<convex_mesh>, fl<compound_any>,   as<any_sdf>}},
  /* mesh     */ {{fl<convex_mesh>,   fl<convex_mesh>,    fl<convex_mesh>,        no_contact,            fl<convex_mesh>,          fl<convex_mesh>,        no_contact,      fl<compound_any>,   as<any_sdf>}},
  /* compound */ {{as<compound_any>,  as<compound_any>,   as<compound_any>,       as<compound_any>,      as<compound_any>,         as<compound_any>,       as<compound_any>, same<compound_any>, as<compound_any>}},
  /* sdf      */ {{fl<any_sdf>,       fl<any_sdf>,        fl<any_sdf>,            fl<any_sdf>,           fl<any_sdf>,              fl<any_sdf>,            fl<any_sdf>,     fl<compound_any>,   same<sdf_sdf>}},
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

bool twins(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b) {
  if (detail::compare_content(a, b) != 0)
    return false;
  if (a.type == ShapeType::sphere)
    return pose_a.translation == pose_b.translation;
  return detail::compare_poses(pose_a, pose_b) == 0;
}

bool collides_by_gjk(ShapeType a, ShapeType b) {
  const PairFunction f = collide_table[std::size_t(a)][std::size_t(b)];
  return f == cvx || f == xvc;
}

int collide(const Shape& a, const Transform& pose_a, const Shape& b, const Transform& pose_b,
            Real margin, Manifold& out, GjkCache& cache) {
  const PairFunction f = collide_table[std::size_t(a.type)][std::size_t(b.type)];
  if (f != cvx && f != xvc)
    return collide(a, pose_a, b, pose_b, margin, out);
  out = Manifold{};
  // As in_pair_frame and flipped do for the table's entries: the cache lives in the frame of the
  // shape that runs first, which a flipped entry makes B.
  const bool flip = f == xvc;
  const Shape& first = flip ? b : a;
  const Shape& second = flip ? a : b;
  const Transform& pose_first = flip ? pose_b : pose_a;
  const Transform& pose_second = flip ? pose_a : pose_b;
  const Vec3 origin = pose_first.translation;
  const Transform local_first{Vec3::Zero(), pose_first.rotation};
  const Transform local_second{pose_second.translation - origin, pose_second.rotation};
  const int count =
      convex_convex_cached(first, local_first, second, local_second, margin, out, &cache);
  for (int i = 0; i < count; ++i)
    out.points[i].position += origin;
  if (flip) {
    out.normal = -out.normal;
    for (int i = 0; i < count; ++i)
      out.points[i].feature = out.points[i].feature.swapped();
  }
  if (count == 0)
    out = Manifold{};
  return count;
}

}  // namespace tumble
