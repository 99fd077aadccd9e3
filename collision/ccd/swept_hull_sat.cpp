// Time-extended SAT for boxes and convex hulls (collision/ccd/swept_hull_sat.hpp).
//
// Sources, and what is ours:
//   - The time extension of the separating-axis test for translating boxes is
//     collision/ccd/swept_box_sat.cpp. With rotation each axis becomes a root problem of
//     trigonometric functions (swept_box_sat.hpp); we do not solve those roots.
//   - The axes of two polytopes are the face normals of the Minkowski difference: the face
//     normals of both and the cross products of the edge pairs whose arcs on the Gauss map cross
//     (Gregorius, "The Separating Axis Test between Convex Polyhedra", GDC 2013). For such a
//     pair the two edges are the supporting features along the axis, so its gap needs no
//     support search; pairs whose arcs do not cross are not faces and are skipped. Dropping an
//     axis can only make the test report contact earlier, never miss one, so near-parallel
//     edge pairs (whose axis is the face normals' anyway) are skipped too.
//   - With rotation: our own extension, built from interval (Lipschitz) bounds of the gap along a
//     fixed axis, the bound conservative advancement uses (Mirtich 2000; Zhang et al. 2007),
//     but per axis and tighter. A body turns about a fixed world axis u at rate |w| for
//     both motion kinds, so a point at distance r from the line through the centre of mass along
//     u moves, relative to the centre, across u only: along a fixed unit axis n its projection
//     changes at most at |w| r |n x u|. The centre moves at a constant velocity (linear kind)
//     or on a helix about u (screw kind: constant speed along u plus a speed across u whose
//     direction turns), so along n the centre's speed is n.v exactly, or lies within
//     (n.u)(u.v) +- |n x u| (speed across u). So the gap g along n at time s0 is still positive
//     for s in [s0, s0 + g / rate(n)) with rate(n) the bound of the closing speed along n; every
//     axis rules out such a window, the search jumps to the end of the longest one and evaluates
//     the axes again. Without rotation the rate is exact, the first jump lands on the exact time
//     of contact and the method is the translating test again.
#include "collision/ccd/swept_hull_sat.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

#include "collision/shapes/convex_hull.hpp"

namespace tumble {
namespace {

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();
// Edge pairs whose cross product is shorter than this times the product of their lengths are
// parallel: the sine of the angle between them.
constexpr Real kParallelSine = Real(1e-9);

// A convex polytope as the SAT sees it: vertices, outward face planes, edges with their faces.
struct PolytopeView {
  std::span<const Vec3> vertices;
  std::span<const HullFace> faces;
  std::span<const HullEdge> edges;
  const ConvexHull* hull = nullptr;  // big hulls climb the vertex graph for supports
  bool is_box = false;               // a box: two boxes use the closed-form axes
  Vec3 half_extents = Vec3::Zero();

  // max over vertices of direction . vertex (local frame).
  Real support(const Vec3& direction) const {
    if (hull != nullptr && int(vertices.size()) > kHullScanLimit)
      return vertices[std::size_t(hull->support_index(direction))].dot(direction);
    Real best = vertices[0].dot(direction);
    for (std::size_t i = 1; i < vertices.size(); ++i)
      best = std::max(best, vertices[i].dot(direction));
    return best;
  }
};

PolytopeView hull_view(const ConvexHull& hull) {
  return {hull.vertices(), hull.faces(), hull.edges(), &hull, false, Vec3::Zero()};
}

// A box as a polytope, on the stack: vertex k has the sign of axis i in bit i of k, face
// 2 i + 1 is the face at +h_i and 2 i the one at -h_i.
class BoxPolytope {
 public:
  explicit BoxPolytope(const Vec3& h) {
    for (int k = 0; k < 8; ++k)
      vertices_[std::size_t(k)] =
          Vec3(k & 1 ? h.x() : -h.x(), k & 2 ? h.y() : -h.y(), k & 4 ? h.z() : -h.z());
    for (int i = 0; i < 3; ++i) {
      for (int side = 0; side < 2; ++side) {
        HullFace& f = faces_[std::size_t(2 * i + side)];
        f.normal = Vec3::Unit(i) * (side == 1 ? 1 : -1);
        f.offset = h[i];
      }
    }
    int e = 0;
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3;
      const int k = (i + 2) % 3;
      for (int sj = 0; sj < 2; ++sj) {
        for (int sk = 0; sk < 2; ++sk) {
          HullEdge& edge = edges_[std::size_t(e++)];
          edge.vertex[0] = (sj << j) | (sk << k);
          edge.vertex[1] = edge.vertex[0] | (1 << i);
          edge.face[0] = 2 * j + sj;
          edge.face[1] = 2 * k + sk;
        }
      }
    }
  }
  PolytopeView view() const {
    return {vertices_,
            faces_,
            edges_,
            nullptr,
            true,
            faces_[1].offset * Vec3::UnitX() + faces_[3].offset * Vec3::UnitY() +
                faces_[5].offset * Vec3::UnitZ()};
  }

 private:
  std::array<Vec3, 8> vertices_{};
  std::array<HullFace, 6> faces_{};
  std::array<HullEdge, 12> edges_{};
};

// Box or hull storage behind a view (the box needs its arrays kept alive).
class Polytope {
 public:
  explicit Polytope(const Shape& shape)
      : box_(shape.type == ShapeType::box ? shape.half_extents : Vec3::Zero()) {
    view_ = shape.type == ShapeType::hull ? hull_view(*shape.hull) : box_.view();
  }
  Polytope(const Polytope&) = delete;  // the view points into box_
  Polytope& operator=(const Polytope&) = delete;
  const PolytopeView& view() const { return view_; }

 private:
  BoxPolytope box_;
  PolytopeView view_;
};

// B's pose in A's frame: x_A = rotation x_B + offset (offset: B's centre seen from A's).
struct RelativePose {
  Mat3 rotation;
  Vec3 offset;
};

RelativePose relative_pose(const Transform& a, const Transform& b) {
  return {(a.rotation.conjugate() * b.rotation).toRotationMatrix(),
          a.rotate_inverse(b.translation - a.translation)};
}

// Which candidate axis a gap was measured on, so that the advancement can measure that one axis
// again at a later time.
struct AxisFeature {
  enum class Kind : std::uint8_t { face_a, face_b, edge_pair, box_axis };
  Kind kind = Kind::face_a;
  int i = 0;  // face of A or B, edge of A, or box axis (0 to 14)
  int j = 0;  // edge of B, or the side of a box axis (0: +l, 1: -l)
};

// Box axis k (A's frame): 2 i is A's face axis i, 2 i + 1 B's, 6 + 3 i + j A's edge i across
// B's edge j.
Vec3 box_axis_direction(int k, const Mat3& r) {
  if (k < 6)
    return k % 2 == 0 ? Vec3(Vec3::Unit(k / 2)) : Vec3(r.col(k / 2));
  return Vec3::Unit((k - 6) / 3).cross(r.col((k - 6) % 3));
}

// The gap along box axis k (side 0: l, 1: -l); false for parallel edges (the face axes cover
// that direction).
bool box_axis_gap(const Vec3& ha, const Vec3& hb, const RelativePose& pose, int k, int side,
                  Vec3& n, Real& gap) {
  const Mat3& r = pose.rotation;
  Vec3 l = box_axis_direction(k, r);
  const Real length = l.norm();
  if (!(length > kParallelSine))
    return false;
  l /= length;
  const Real reach = ha.x() * std::abs(l.x()) + ha.y() * std::abs(l.y()) +
                     ha.z() * std::abs(l.z()) + hb.x() * std::abs(l.dot(r.col(0))) +
                     hb.y() * std::abs(l.dot(r.col(1))) + hb.z() * std::abs(l.dot(r.col(2)));
  const Real centre = -l.dot(pose.offset);  // B's centre to A's, along l
  n = side == 0 ? l : Vec3(-l);
  gap = (side == 0 ? centre : -centre) - reach;
  return true;
}

// Two boxes: the 15 axes of the box-box test (Gottschalk, Lin and Manocha, "OBBTree", SIGGRAPH
// 1996), each with its projected radii in closed form and visited in both directions: the same
// axes as the general code below (a box's opposite faces share one axis; the far side's gap is
// negative now but opens when the boxes pass each other, an exit of the translating test).
template <class Visit>
bool for_each_box_axis(const Vec3& ha, const Vec3& hb, const RelativePose& pose, Visit&& visit) {
  for (int k = 0; k < 15; ++k) {
    for (int side = 0; side < 2; ++side) {
      Vec3 n;
      Real gap = 0;
      if (box_axis_gap(ha, hb, pose, k, side, n, gap) &&
          !visit(n, gap, AxisFeature{AxisFeature::Kind::box_axis, k, side}))
        return false;
    }
  }
  return true;
}

Real face_a_gap(const PolytopeView& b, const RelativePose& pose, const HullFace& f) {
  return f.normal.dot(pose.offset) - f.offset - b.support(pose.rotation.transpose() * -f.normal);
}

Real face_b_gap(const PolytopeView& a, const RelativePose& pose, const HullFace& f, Vec3& n) {
  n = pose.rotation * f.normal;
  return -a.support(-n) - f.offset - n.dot(pose.offset);
}

// The axis of edge ea of A across edge eb of B once their arcs are known to cross: false for
// parallel edges.
bool edge_pair_gap(const PolytopeView& a, const HullEdge& ea, const PolytopeView& b,
                   const HullEdge& eb, const RelativePose& pose, Vec3& n, Real& gap) {
  const Vec3& a0 = a.vertices[std::size_t(ea.vertex[0])];
  const Vec3 direction_a = a.vertices[std::size_t(ea.vertex[1])] - a0;
  const Vec3& b0 = b.vertices[std::size_t(eb.vertex[0])];
  const Vec3 direction_b = pose.rotation * (b.vertices[std::size_t(eb.vertex[1])] - b0);
  n = direction_a.cross(direction_b);
  const Real length = n.norm();
  if (!(length > kParallelSine * direction_a.norm() * direction_b.norm()))
    return false;
  n /= length;
  // A's edge supports A along -n: -n points out of A there (A's centre is its origin).
  if (n.dot(a0) > 0)
    n = -n;
  gap = n.dot(a0 - (pose.rotation * b0 + pose.offset));
  return true;
}

// The Gauss-map test (Gregorius 2013): the arc of A's edge between its face normals (na0, na1)
// and the arc of -B's edge between its negated face normals (c, d) cross when c and d lie on
// both sides of the plane of (na0, na1), na0 and na1 on both sides of the plane of (c, d), and
// both arcs lie in the same hemisphere. cba = c . (na1 x na0), dba = d . (na1 x na0).
bool arcs_cross(const Vec3& na0, const Vec3& na1, const Vec3& c, const Vec3& d, Real cba,
                Real dba) {
  if (!(cba * dba < 0))
    return false;
  const Vec3 dxc = d.cross(c);
  const Real adc = na0.dot(dxc);
  const Real bdc = na1.dot(dxc);
  return adc * bdc < 0 && cba * bdc > 0;
}

// B's face normals on the Gauss map of -B are kept in a stack buffer up to this many faces;
// bigger hulls turn them again where needed (no heap allocation either way).
constexpr std::size_t kBufferedFaces = 256;

// Calls visit(axis, gap, feature) for every candidate axis (unit, A's frame, pointing from B to
// A) with the gap along it: min over A of axis . x minus max over B of axis . x (> 0: apart
// along it). Stops as soon as visit returns false, and then returns false.
template <class Visit>
bool for_each_axis(const PolytopeView& a, const PolytopeView& b, const RelativePose& pose,
                   Visit&& visit) {
  using Kind = AxisFeature::Kind;
  if (a.is_box && b.is_box)
    return for_each_box_axis(a.half_extents, b.half_extents, pose, visit);
  const Mat3& r = pose.rotation;
  // A's faces: the axis is minus the face normal; A's side along it is the face plane itself.
  for (std::size_t i = 0; i < a.faces.size(); ++i) {
    if (!visit(Vec3(-a.faces[i].normal), face_a_gap(b, pose, a.faces[i]),
               AxisFeature{Kind::face_a, int(i), 0}))
      return false;
  }
  // B's faces: the axis is the face normal turned into A's frame.
  for (std::size_t i = 0; i < b.faces.size(); ++i) {
    Vec3 n;
    const Real gap = face_b_gap(a, pose, b.faces[i], n);
    if (!visit(n, gap, AxisFeature{Kind::face_b, int(i), 0}))
      return false;
  }
  // Edge pairs that form a face of the Minkowski difference. The first half of the Gauss-map
  // test rejects most pairs; for one edge of A it needs only the side of each face normal of B,
  // computed once per face.
  const std::size_t faces_b = b.faces.size();
  const bool buffered = faces_b <= kBufferedFaces;
  std::array<Vec3, kBufferedFaces> gauss_b;
  std::array<Real, kBufferedFaces> side_b;
  if (buffered) {
    for (std::size_t f = 0; f < faces_b; ++f)
      gauss_b[f] = -(r * b.faces[f].normal);
  }
  auto gauss = [&](int f) {
    return buffered ? gauss_b[std::size_t(f)] : Vec3(-(r * b.faces[std::size_t(f)].normal));
  };
  for (std::size_t ia = 0; ia < a.edges.size(); ++ia) {
    const HullEdge& ea = a.edges[ia];
    const Vec3& na0 = a.faces[std::size_t(ea.face[0])].normal;
    const Vec3& na1 = a.faces[std::size_t(ea.face[1])].normal;
    const Vec3 bxa = na1.cross(na0);
    if (buffered) {
      for (std::size_t f = 0; f < faces_b; ++f)
        side_b[f] = gauss_b[f].dot(bxa);
    }
    for (std::size_t ib = 0; ib < b.edges.size(); ++ib) {
      const HullEdge& eb = b.edges[ib];
      const Real cba = buffered ? side_b[std::size_t(eb.face[0])] : gauss(eb.face[0]).dot(bxa);
      const Real dba = buffered ? side_b[std::size_t(eb.face[1])] : gauss(eb.face[1]).dot(bxa);
      if (!(cba * dba < 0) || !arcs_cross(na0, na1, gauss(eb.face[0]), gauss(eb.face[1]), cba, dba))
        continue;
      Vec3 n;
      Real gap = 0;
      if (edge_pair_gap(a, ea, b, eb, pose, n, gap) &&
          !visit(n, gap, AxisFeature{Kind::edge_pair, int(ia), int(ib)}))
        return false;
    }
  }
  return true;
}

// The gap along one feature's axis at a new pose; false when the feature no longer gives an
// axis (an edge pair whose arcs stopped crossing, or parallel edges).
bool feature_gap(const PolytopeView& a, const PolytopeView& b, const RelativePose& pose,
                 const AxisFeature& feature, Vec3& n, Real& gap) {
  switch (feature.kind) {
    case AxisFeature::Kind::box_axis:
      return box_axis_gap(a.half_extents, b.half_extents, pose, feature.i, feature.j, n, gap);
    case AxisFeature::Kind::face_a: {
      const HullFace& f = a.faces[std::size_t(feature.i)];
      n = -f.normal;
      gap = face_a_gap(b, pose, f);
      return true;
    }
    case AxisFeature::Kind::face_b:
      gap = face_b_gap(a, pose, b.faces[std::size_t(feature.i)], n);
      return true;
    case AxisFeature::Kind::edge_pair: {
      const HullEdge& ea = a.edges[std::size_t(feature.i)];
      const HullEdge& eb = b.edges[std::size_t(feature.j)];
      const Vec3& na0 = a.faces[std::size_t(ea.face[0])].normal;
      const Vec3& na1 = a.faces[std::size_t(ea.face[1])].normal;
      const Vec3 c = -(pose.rotation * b.faces[std::size_t(eb.face[0])].normal);
      const Vec3 d = -(pose.rotation * b.faces[std::size_t(eb.face[1])].normal);
      const Vec3 bxa = na1.cross(na0);
      return arcs_cross(na0, na1, c, d, c.dot(bxa), d.dot(bxa)) &&
             edge_pair_gap(a, ea, b, eb, pose, n, gap);
    }
  }
  return false;
}

bool finite(const Transform& t) {
  return t.translation.allFinite() && t.rotation.coeffs().allFinite();
}

ToiResult invalid(Real time) {
  ToiResult out;
  out.status = ToiStatus::invalid_input;
  out.time_of_impact = time;
  return out;
}

ToiResult separated(int iterations) {
  ToiResult out;
  out.status = ToiStatus::separated;
  out.time_of_impact = 1;
  out.iterations = iterations;
  return out;
}

// The exact translating test: every axis keeps its direction and its gap moves linearly.
ToiResult translating_sat(const PolytopeView& a, const Transform& pose_a, const Vec3& translation_a,
                          const PolytopeView& b, const Transform& pose_b, const Vec3& translation_b,
                          Real target) {
  if (!finite(pose_a) || !finite(pose_b) || !translation_a.allFinite() ||
      !translation_b.allFinite() || !std::isfinite(target))
    return invalid(0);
  const RelativePose pose = relative_pose(pose_a, pose_b);
  // Along axis n (A's frame) the gap grows by n . v per unit of s.
  const Vec3 v = pose_a.rotate_inverse(translation_a - translation_b);
  Real enter = -kInfinity;  // all axes tested so far overlap (to the target) for s in
  Real exit = kInfinity;    // [enter, exit]
  Vec3 enter_axis = Vec3::UnitZ();
  Real largest_gap = -kInfinity;  // at s = 0, for the normal of an initial overlap
  Vec3 largest_axis = Vec3::UnitZ();
  auto visit = [&](const Vec3& n, Real gap, const AxisFeature&) {
    const Real g = gap - target;
    if (g > largest_gap) {
      largest_gap = g;
      largest_axis = n;
    }
    const Real rate = n.dot(v);
    if (rate < 0) {
      const Real s = g / -rate;
      if (s > enter) {
        enter = s;
        enter_axis = n;
      }
    } else if (rate > 0) {
      exit = std::min(exit, -g / rate);
    } else if (g > 0) {
      enter = kInfinity;  // apart along n for ever
    }
    return enter <= exit && enter <= 1 && exit >= 0;
  };
  if (!for_each_axis(a, b, pose, visit))
    return separated(1);
  ToiResult out;
  out.iterations = 1;
  if (enter <= 0) {
    out.status = ToiStatus::overlapping;
    out.time_of_impact = 0;
    out.normal = pose_a.rotate(largest_axis);
    out.distance = largest_gap + target;
    return out;
  }
  out.status = ToiStatus::hit;
  out.time_of_impact = enter;
  out.normal = pose_a.rotate(enter_axis);
  out.distance = target;
  return out;
}

// Bounds of how fast the points of one body move along a fixed axis (world frame, constant over
// the motion): along unit n every point's speed lies within n . velocity +- |n x axis| sweep.
struct MotionBound {
  Vec3 velocity = Vec3::Zero();  // linear kind: the centre's velocity; screw: its part along u
  Vec3 axis = Vec3::Zero();      // u, the unit rotation axis (zero when the body does not turn)
  Real sweep = 0;                // speed across u: the screw centre's plus |w| times the radius
  Vec3 omega = Vec3::Zero();     // angular velocity (world) [rad per unit s]
  bool linear = true;            // the linear kind (or no rotation): the centre does not turn
};

MotionBound motion_bound(const RigidMotion& motion, const PolytopeView& shape) {
  MotionBound out;
  const Vec3& w = motion.angular_velocity();
  const Real turn = w.norm();
  const Vec3 displacement = motion.end().translation - motion.start().translation;
  if (!(turn > 0)) {
    out.velocity = displacement;  // either kind without rotation is a translation
    return out;
  }
  out.axis = w / turn;
  out.omega = w;
  out.linear = motion.kind() == MotionKind::linear;
  // Largest distance of a vertex from the rotation axis through the centre: it does not change
  // while the body turns about that axis.
  const Vec3 u_local = motion.start().rotate_inverse(out.axis);
  Real radius = 0;
  for (const Vec3& v : shape.vertices)
    radius = std::max(radius, u_local.cross(v).norm());
  out.sweep = turn * radius;
  if (motion.kind() == MotionKind::linear) {
    out.velocity = displacement;
    return out;
  }
  // Helix: the speed along u is constant (u . displacement over the whole motion); the rest of
  // the constant speed goes across u. The small relative term covers the rounding of the
  // difference of squares.
  const Real along = out.axis.dot(displacement);
  const Real speed = motion.centre_speed();
  out.velocity = out.axis * along;
  out.sweep +=
      std::sqrt(std::max(Real(0), speed * speed - along * along) + Real(1e-15) * speed * speed);
  return out;
}

Real across(const Vec3& n, const Vec3& u) {
  const Real along = n.dot(u);
  return std::sqrt(std::max(Real(0), Real(1) - along * along));
}

// A longer window along one fixed axis n (A's frame) when both bodies move with the linear kind:
// every vertex's projection moves at a rate known exactly at s (centre velocity plus w x r) and
// that rate drifts by at most |w| |n x u| sweep per unit s (the turning of w x r), so
//   gap(s + h) >= F(h) = min_a (alpha_a + h beta_a) - max_b (alpha_b + h beta_b) - K h^2 / 2.
// F is concave, so F > 0 at 0 and at h means F > 0 on [0, h]: any h where F is verified positive
// is a safe window. Secant steps from below find one close to the root of F; near contact this
// converges much faster than the first-order bound, whose rate is the worst vertex's.
struct SpinFrame {  // the motion of both bodies in A's frame at s
  Vec3 velocity_a, omega_a, velocity_b, omega_b;
  Real acceleration_a = 0, acceleration_b = 0;  // |w|^2 radius across u (times |n x u| below)
  Vec3 axis_a, axis_b;
};

Real second_order_window(const PolytopeView& a, const PolytopeView& b, const RelativePose& pose,
                         const SpinFrame& m, const Vec3& n, Real target, Real limit) {
  const Vec3 na_spin = n.cross(m.omega_a);  // n . (w x r) = r . (n x w)
  const Vec3 nb = pose.rotation.transpose() * n;
  const Vec3 nb_spin = pose.rotation.transpose() * n.cross(m.omega_b);
  const Real base_b = n.dot(pose.offset);
  const Real rate_a = n.dot(m.velocity_a);
  const Real rate_b = n.dot(m.velocity_b);
  const Real k = across(n, m.axis_a) * m.acceleration_a + across(n, m.axis_b) * m.acceleration_b;
  auto lower_gap = [&](Real h) {
    Real min_a = kInfinity;
    for (const Vec3& v : a.vertices)
      min_a = std::min(min_a, n.dot(v) + h * (rate_a + na_spin.dot(v)));
    Real max_b = -kInfinity;
    for (const Vec3& v : b.vertices)
      max_b = std::max(max_b, nb.dot(v) + h * (rate_b + nb_spin.dot(v)));
    return min_a - max_b - base_b - target - Real(0.5) * k * h * h;
  };
  Real lo = 0;
  Real f_lo = lower_gap(0);
  if (!(f_lo > 0))
    return 0;
  Real hi = limit;
  Real f_hi = lower_gap(hi);
  if (f_hi > 0)
    return limit;  // apart along n up to the end of the motion
  for (int step = 0; step < 6; ++step) {
    const Real h = lo + f_lo * (hi - lo) / (f_lo - f_hi);
    if (!(h > lo && h < hi))
      break;
    const Real f = lower_gap(h);
    if (f > 0) {
      lo = h;
      f_lo = f;
    } else {
      hi = h;
      f_hi = f;
      f_lo *= Real(0.5);  // Illinois: keeps the secant from creeping up on one side
    }
  }
  return lo;
}

// Every this many evaluations of the advancement measures all axes; the others measure only the
// axis that ruled out the last window (cheaper by the number of axes; near contact it is the
// contact axis anyway).
constexpr int kFullEvaluationEvery = 4;

// Advancement over time windows for turning bodies (see the header comment of this file).
ToiResult advancing_sat(const PolytopeView& a, const RigidMotion& motion_a, const PolytopeView& b,
                        const RigidMotion& motion_b, const ToiSettings& settings) {
  const MotionBound bound_a = motion_bound(motion_a, a);
  const MotionBound bound_b = motion_bound(motion_b, b);
  if (!bound_a.velocity.allFinite() || !bound_b.velocity.allFinite() ||
      !std::isfinite(bound_a.sweep) || !std::isfinite(bound_b.sweep))
    return invalid(0);
  const Real target = settings.target_distance;
  const Real stop = target + (settings.tolerance > 0 ? settings.tolerance : Real(1e-6));
  const bool second_order = bound_a.linear && bound_b.linear;
  ToiResult out;
  AxisFeature cached;  // the axis that ruled out the last window of a full evaluation
  bool have_cached = false;
  Real s = 0;
  for (int it = 0; it < settings.max_iterations; ++it) {
    out.iterations = it + 1;
    const Transform pose_a = motion_a.at(s);
    const Transform pose_b = motion_b.at(s);
    const RelativePose pose = relative_pose(pose_a, pose_b);
    // The bounds in A's frame at s.
    const Vec3 velocity = pose_a.rotate_inverse(bound_a.velocity - bound_b.velocity);
    const Vec3 axis_a = pose_a.rotate_inverse(bound_a.axis);
    const Vec3 axis_b = pose_a.rotate_inverse(bound_b.axis);
    // Lower bound of d(gap)/ds along a fixed axis n.
    auto rate_bound = [&](const Vec3& n) {
      return n.dot(velocity) - across(n, axis_a) * bound_a.sweep -
             across(n, axis_b) * bound_b.sweep;
    };
    SpinFrame spin;
    if (second_order) {
      spin.velocity_a = pose_a.rotate_inverse(bound_a.velocity);
      spin.velocity_b = pose_a.rotate_inverse(bound_b.velocity);
      spin.omega_a = pose_a.rotate_inverse(bound_a.omega);
      spin.omega_b = pose_a.rotate_inverse(bound_b.omega);
      spin.acceleration_a = bound_a.omega.norm() * bound_a.sweep;
      spin.acceleration_b = bound_b.omega.norm() * bound_b.sweep;
      spin.axis_a = axis_a;
      spin.axis_b = axis_b;
    }
    // The window of one axis: the first-order one, or the second-order one when longer.
    auto window_of = [&](const Vec3& n, Real g, Real rate) {
      const Real first = rate < 0 ? g / -rate : kInfinity;
      if (!second_order || first >= 1 - s)
        return first;
      return std::max(first, second_order_window(a, b, pose, spin, n, target, 1 - s));
    };
    // Between full evaluations only the cached axis is measured again: while its gap stays
    // above the stop it rules out a window by itself (no contact can be declared from it).
    if (have_cached && it % kFullEvaluationEvery != 0) {
      Vec3 n;
      Real gap = 0;
      if (feature_gap(a, b, pose, cached, n, gap) && gap > stop) {
        const Real window = window_of(n, gap - target, rate_bound(n));
        if (s + window >= 1)
          return separated(out.iterations);
        s += window;
        continue;
      }
    }
    Real largest_gap = -kInfinity;
    Vec3 largest_axis = Vec3::UnitZ();
    Real window = 0;  // the longest window [s, s + window) that some axis keeps apart
    bool apart = false;
    have_cached = false;
    auto visit = [&](const Vec3& n, Real gap, const AxisFeature& feature) {
      const Real g = gap - target;
      if (g > largest_gap) {
        largest_gap = g;
        largest_axis = n;
      }
      if (!(g > 0))
        return true;  // rules out no window
      const Real rate = rate_bound(n);
      if (rate >= 0) {
        apart = true;  // apart along n and never closing
        return false;
      }
      if (g / -rate > window) {
        window = g / -rate;
        cached = feature;
        have_cached = true;
      }
      apart = s + window >= 1;
      return !apart;
    };
    for_each_axis(a, b, pose, visit);
    if (!apart && second_order && have_cached && window > 0) {
      // The second-order window of the axis that ruled out the longest first-order one.
      Vec3 n;
      Real gap = 0;
      if (feature_gap(a, b, pose, cached, n, gap)) {
        window = std::max(window, window_of(n, gap - target, rate_bound(n)));
        apart = s + window >= 1;
      }
    }
    if (apart)
      return separated(out.iterations);
    if (!std::isfinite(largest_gap))
      return invalid(s);
    out.distance = largest_gap + target;
    out.normal = pose_a.rotate(largest_axis);
    if (largest_gap + target <= stop) {
      out.status = s == 0 ? ToiStatus::overlapping : ToiStatus::hit;
      out.time_of_impact = s;
      return out;
    }
    s += window;
  }
  out.status = ToiStatus::max_iterations;
  out.time_of_impact = s;
  return out;
}

bool is_polytope(const Shape& s) {
  return (s.type == ShapeType::box) || (s.type == ShapeType::hull && s.hull != nullptr);
}

}  // namespace

ToiResult swept_hull_sat(const ConvexHull& a, const Transform& pose_a, const Vec3& translation_a,
                         const ConvexHull& b, const Transform& pose_b, const Vec3& translation_b,
                         Real target_distance) {
  return translating_sat(hull_view(a), pose_a, translation_a, hull_view(b), pose_b, translation_b,
                         target_distance);
}

bool time_extended_sat_applies(const Shape& a, const Shape& b) {
  return is_polytope(a) && is_polytope(b);
}

ToiResult time_extended_sat(const Shape& a, const RigidMotion& motion_a, const Shape& b,
                            const RigidMotion& motion_b, const ToiSettings& settings) {
  if (!time_extended_sat_applies(a, b))
    return invalid(0);
  if (!finite(motion_a.start()) || !finite(motion_a.end()) || !finite(motion_b.start()) ||
      !finite(motion_b.end()) || !motion_a.angular_velocity().allFinite() ||
      !motion_b.angular_velocity().allFinite() || !std::isfinite(settings.target_distance))
    return invalid(0);
  const Polytope pa(a);
  const Polytope pb(b);
  if (motion_a.angular_velocity().isZero(0) && motion_b.angular_velocity().isZero(0)) {
    return translating_sat(
        pa.view(), motion_a.start(), motion_a.end().translation - motion_a.start().translation,
        pb.view(), motion_b.start(), motion_b.end().translation - motion_b.start().translation,
        settings.target_distance);
  }
  return advancing_sat(pa.view(), motion_a, pb.view(), motion_b, settings);
}

DistanceBound polytope_separation(const Shape& a, const Transform& pose_a, const Shape& b,
                                  const Transform& pose_b) {
  DistanceBound out;
  if (!time_extended_sat_applies(a, b)) {
    out.distance = -kInfinity;
    out.separating_normal = false;
    return out;
  }
  const Polytope pa(a);
  const Polytope pb(b);
  Real largest = -kInfinity;
  Vec3 axis = Vec3::UnitZ();
  for_each_axis(pa.view(), pb.view(), relative_pose(pose_a, pose_b),
                [&](const Vec3& n, Real gap, const AxisFeature&) {
                  if (gap > largest) {
                    largest = gap;
                    axis = n;
                  }
                  return true;
                });
  out.distance = largest;
  out.normal = pose_a.rotate(axis);
  return out;
}

}  // namespace tumble
