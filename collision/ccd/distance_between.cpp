// distance_between and contact_potential (include/tumble/distance.hpp). The distance is GJK's
// (van den Bergen, "A fast and robust GJK implementation for collision detection of convex
// objects", JGT 1999) and, in penetration, EPA's (van den Bergen, "Proximity queries and
// penetration depth computation on 3D game objects", GDC 2001), run in a frame centred on A for
// precision far from the origin; a plane is answered by the support of the other shape along its
// normal. The gradients follow from the witness points and the normal (the header says why).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Geometry>

#include "collision/ccd/field_distance.hpp"
#include "collision/ccd/projected_descent.hpp"
#include "collision/narrow_phase/gjk_epa/epa.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "tumble/distance.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

// Steps of the short descents that pick the grid seed of a solid deep in a field
// (solid_and_field).
constexpr int kScoutSteps = 20;

bool is_convex(ShapeType t) {
  return t == ShapeType::sphere || t == ShapeType::box || t == ShapeType::capsule ||
         t == ShapeType::cylinder || t == ShapeType::hull;
}

void check(const Shape& s, const Transform& pose, const char* side) {
  if (!is_convex(s.type) && s.type != ShapeType::plane && s.type != ShapeType::sdf)
    throw Error(std::string("distance_between: shape ") + side + " is a " +
                std::string(shape_type_name(s.type)) +
                "; only convex shapes (sphere, box, capsule, cylinder, hull), planes and signed "
                "distance fields");
  if (!pose.translation.allFinite() || !pose.rotation.coeffs().allFinite())
    throw Error(std::string("distance_between: pose ") + side + " is not finite");
}

// A sphere or capsule A against a field B (collision/shapes/sdf_shape.hpp): the distance is
// phi_B at the nearest point of A's core, less A's radius, and its derivatives come from grad phi
// there (the envelope theorem again: the core point is where phi is least along the core). d/d x_A
// = g, d/d turn of A = (c - x_A) x g, d/d x_B = -g, d/d turn of B = -(c - x_B) x g, with g =
// grad phi in the world and c the core point; exact wherever phi is differentiable and its least
// point on the core unique.
// The distance of A from a field B through A's point `core` (world frame), the point of A where
// phi_B is least less `radius`: phi_B there less the radius, along grad phi, with the gradients
// of a point fixed in A (the envelope theorem).
ShapeDistance field_distance_through(const Shape& a, const Vec3& core, Real radius,
                                     const Transform& pose_a, const SdfShape& field, Real time,
                                     const Transform& pose_b) {
  sdf::Sample s = field.sample(pose_b.apply_inverse(core), time);
  s.gradient = pose_b.rotate(s.gradient);
  if (!(std::abs(s.distance) < field.reach()))
    throw Error("distance_between: the " + std::string(shape_type_name(a.type)) +
                "'s nearest point is beyond the field's narrow band (values are distances only "
                "within " +
                std::to_string(field.reach()) +
                " m of its surface); widen the level set's band (docs/sdf.md)");
  ShapeDistance d;
  const Real g2 = s.gradient.squaredNorm();
  d.normal = g2 > 0 ? Vec3(s.gradient / std::sqrt(g2)) : Vec3::UnitZ();
  d.distance = s.distance - radius;
  d.point_a = core - radius * d.normal;
  d.point_b = core - s.distance * d.normal;
  d.gradient_a.head<3>() = s.gradient;
  d.gradient_a.tail<3>() = (core - pose_a.translation).cross(s.gradient);
  d.gradient_b.head<3>() = -s.gradient;
  d.gradient_b.tail<3>() = -(core - pose_b.translation).cross(s.gradient);
  return d;
}

// A sphere or capsule A against a field B: the core point of least phi (a sphere's centre; along
// a capsule's segment, by samples and golden-section search), less the radius.
ShapeDistance round_and_field(const Shape& a, const Transform& pose_a, const SdfShape& field,
                              Real time, const Transform& pose_b) {
  Vec3 core = pose_a.translation;
  if (a.type == ShapeType::capsule) {
    // The least phi along the core segment: 33 samples, then golden-section search around each
    // of the three lowest sampled minima (phi along a segment may have several basins, two of
    // them nearly as deep), the lowest result kept.
    const Vec3 axis = pose_a.rotate(Vec3::UnitZ()) * a.half_length;
    const auto at = [&](Real t) { return Vec3(pose_a.translation + t * axis); };
    const auto phi_of = [&](Real t) { return field.distance(pose_b.apply_inverse(at(t)), time); };
    constexpr int kSamples = 33;
    std::array<Real, kSamples> samples;
    for (int i = 0; i < kSamples; ++i)
      samples[std::size_t(i)] = phi_of(-1 + 2 * Real(i) / (kSamples - 1));
    std::array<int, 3> basins{-1, -1, -1};
    for (int i = 0; i < kSamples; ++i) {
      const Real v = samples[std::size_t(i)];
      if ((i > 0 && samples[std::size_t(i - 1)] < v) ||
          (i + 1 < kSamples && samples[std::size_t(i + 1)] < v))
        continue;  // not a sampled minimum
      // Insert into the three lowest, kept in order.
      for (std::size_t k = 0; k < basins.size(); ++k)
        if (basins[k] < 0 || v < samples[std::size_t(basins[k])]) {
          for (std::size_t m = basins.size() - 1; m > k; --m)
            basins[m] = basins[m - 1];
          basins[k] = i;
          break;
        }
    }
    Real best_t = 0, best_phi = std::numeric_limits<Real>::infinity();
    constexpr Real kGolden = Real(0.6180339887498949);
    for (int basin : basins) {
      if (basin < 0)
        continue;
      Real lo = -1 + 2 * Real(std::max(basin - 1, 0)) / (kSamples - 1);
      Real hi = -1 + 2 * Real(std::min(basin + 1, kSamples - 1)) / (kSamples - 1);
      Real x1 = hi - kGolden * (hi - lo), x2 = lo + kGolden * (hi - lo);
      Real f1 = phi_of(x1), f2 = phi_of(x2);
      for (int step = 0; step < 60 && hi - lo > Real(1e-12); ++step) {
        if (f1 <= f2) {
          hi = x2;
          x2 = x1;
          f2 = f1;
          x1 = hi - kGolden * (hi - lo);
          f1 = phi_of(x1);
        } else {
          lo = x1;
          x1 = x2;
          f1 = f2;
          x2 = lo + kGolden * (hi - lo);
          f2 = phi_of(x2);
        }
      }
      const Real t = (lo + hi) / 2, v = phi_of(t);
      if (v < best_phi) {
        best_phi = v;
        best_t = t;
      }
    }
    core = at(best_t);
  }
  return field_distance_through(a, core, a.radius, pose_a, field, time, pose_b);
}

// A box, cylinder or hull A against a field B: the least phi_B over A's solid, which for an exact
// field is A's distance from B's surface while they are apart and the depth of A's deepest point
// in B when they overlap. Found by projected gradient descent (Rosen's gradient projection,
// "The gradient projection method for nonlinear programming", J. SIAM 8, 1960): a step against
// grad phi, projected back onto A (its closest point to the stepped point), then the least of a
// parabola fitted along the segment to it (phi at both ends and the slope at the start), kept
// when phi falls (the step then doubles if the whole segment was taken) and the step halved
// otherwise; from the three lowest of A's support points along 26 directions, the lowest result
// kept. At the optimum the tangential derivative
// is zero, so an error e in the point is an error of order e^2 in the distance.
ShapeDistance solid_and_field(const Shape& a, const Transform& pose_a, const SdfShape& field,
                              Real time, const Transform& pose_b) {
  const auto phi = [&](const Vec3& world) {
    sdf::Sample s = field.sample(pose_b.apply_inverse(world), time);
    s.gradient = pose_b.rotate(s.gradient);
    return s;
  };
  const ConvexSupport solid = ConvexSupport::of(a, pose_a);
  // The closest point of A: exact clamps for a box and a cylinder (a disc times an interval),
  // GJK for a hull (exact on a polytope).
  const auto project = [&](const Vec3& p) {
    if (a.type == ShapeType::hull) {
      const ConvexSupport point = ConvexSupport::of_points(&p, 1, Transform{});
      const GjkResult r = gjk(solid, point);
      return r.status == GjkStatus::intersecting || !(r.distance > 0) ? p : r.point_a;
    }
    Vec3 q = pose_a.apply_inverse(p);
    if (a.type == ShapeType::box) {
      q = q.cwiseMax(-a.half_extents).cwiseMin(a.half_extents);
    } else {
      q.z() = std::clamp(q.z(), -a.half_length, a.half_length);
      const Real r = std::hypot(q.x(), q.y());
      if (r > a.radius) {
        q.x() *= a.radius / r;
        q.y() *= a.radius / r;
      }
    }
    return pose_a.apply(q);
  };
  const Real size = bounding_radius(a);
  std::array<std::pair<Real, Vec3>, 3> seeds;
  seeds.fill({std::numeric_limits<Real>::infinity(), pose_a.translation});
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k) {
        if (i == 0 && j == 0 && k == 0)
          continue;
        int feature = 0;
        const Vec3 p = solid.core_support(Vec3(Real(i), Real(j), Real(k)), feature);
        const Real v = field.distance(pose_b.apply_inverse(p), time);
        // Kept in order, lowest first; a support point met again (a box corner is the support
        // of several directions) is not a new seed.
        bool seen = false;
        for (const auto& seed : seeds)
          seen = seen || seed.second == p;
        if (seen)
          continue;
        std::pair<Real, Vec3> carried{v, p};
        for (auto& seed : seeds)
          if (carried.first < seed.first)
            std::swap(seed, carried);
      }
  Real best = std::numeric_limits<Real>::infinity();
  Vec3 core = pose_a.translation;
  bool best_capped = false;
  const auto descend = [&](const Vec3& start) {
    bool capped = false;
    const auto [x, here] = projected_descent(start, size, 2000, phi, project, &capped);
    if (here.distance < best) {
      best = here.distance;
      core = x;
      best_capped = capped;
    }
  };
  for (const auto& [start_value, start] : seeds)
    if (std::isfinite(start_value))
      descend(start);
  // Deep in a field whose inside is not convex (a CSG bowl's wall: the larger of a box's planes
  // and a ball's outside), phi has several least points over A, and the descents from A's support
  // points reach the nearest, not the lowest: a cylinder in a bowl's wall ended up to 4.6 cm
  // above the least over 300 poses. Where A penetrates, the lowest of a 3 x 3 x 3 grid over A's
  // bounds (brought onto A) is a seed too, after a short descent from each of the four lowest
  // picks it.
  if (best < 0) {
    std::array<std::pair<Real, Vec3>, 4> inner;
    inner.fill({std::numeric_limits<Real>::infinity(), pose_a.translation});
    const Aabb local = world_aabb(a, Transform{});
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j)
        for (int k = 0; k < 5; ++k) {
          const Vec3 f(Real(i) / 4, Real(j) / 4, Real(k) / 4);
          const Vec3 p =
              project(pose_a.apply(Vec3(local.min + f.cwiseProduct(local.max - local.min))));
          std::pair<Real, Vec3> carried{field.distance(pose_b.apply_inverse(p), time), p};
          for (auto& seed : inner)
            if (carried.first < seed.first)
              std::swap(seed, carried);
        }
    Real lowest = std::numeric_limits<Real>::infinity();
    Vec3 pick = pose_a.translation;
    for (const auto& [value, start] : inner) {
      if (!std::isfinite(value))
        continue;
      const auto [x, here] = projected_descent(start, size, kScoutSteps, phi, project);
      if (here.distance < lowest) {
        lowest = here.distance;
        pick = x;
      }
    }
    if (lowest < best)
      descend(pick);
  }
  ShapeDistance d = field_distance_through(a, core, 0, pose_a, field, time, pose_b);
  d.converged = !best_capped;  // a descent stopped by its step cap may be short of the least
  // The deepest point a minimum of phi itself, not only over A: a kink of the field (its deepest
  // point, the core ridge of a torus) where phi does not fall a step of 1e-10 of A's size along any
  // of 26 directions (a smooth phi falls along one of them). A holds it (inside, or on its
  // boundary where the ridge crosses) as it moves a little, so the distance does not change with
  // either pose. A deepest point inside A is always such a kink.
  if (least_around(phi, core, size, d.distance)) {
    d.gradient_a.setZero();
    d.gradient_b.setZero();
  }
  return d;
}

void fill_gradients(ShapeDistance& d, const Transform& pose_a, const Transform& pose_b) {
  const Vec3& n = d.normal;
  d.gradient_a.head<3>() = n;
  d.gradient_a.tail<3>() = (d.point_a - pose_a.translation).cross(n);
  d.gradient_b.head<3>() = -n;
  d.gradient_b.tail<3>() = -(d.point_b - pose_b.translation).cross(n);
}

// A is the plane: its solid is below z = 0 of its frame.
ShapeDistance plane_and_convex(const Transform& plane_pose, const Shape& b,
                               const Transform& pose_b) {
  const Vec3 up = plane_pose.rotation * Vec3::UnitZ();
  Transform local_b = pose_b;
  local_b.translation -= plane_pose.translation;
  const ConvexSupport sb = ConvexSupport::of(b, local_b);
  int index = 0;
  const Vec3 deepest = sb.core_support(-up, index) - sb.radius * up + plane_pose.translation;
  ShapeDistance d;
  d.distance = (deepest - plane_pose.translation).dot(up);
  d.point_b = deepest;
  d.point_a = deepest - d.distance * up;
  d.normal = -up;
  return d;
}

// A shape's support set along `direction` as the distinct points that the direction and the
// directions turned 1e-7 rad either way about two axes pick, points within a millionth of the
// shape's size counted once: a vertex or a point of a rounded surface or a cylinder's rim gives
// 1; an edge or a cylinder's side line its 2 ends; a face or a cap more. Returns the count.
int support_feature(const ConvexSupport& s, const Vec3& direction, std::array<Vec3, 5>& points) {
  const Vec3 n = direction.normalized();
  const auto support = [&](const Vec3& d) {
    int index = 0;
    return Vec3(s.core_support(d, index) + s.radius * d.normalized());
  };
  const Vec3 u = n.unitOrthogonal();
  const Vec3 v = n.cross(u);
  constexpr Real kTurn = Real(1e-7);
  const Real size = (support(n) - support(-n)).norm() + s.radius;
  int count = 0;
  for (const Vec3& d :
       {n, Vec3(n + kTurn * u), Vec3(n - kTurn * u), Vec3(n + kTurn * v), Vec3(n - kTurn * v)}) {
    const Vec3 p = support(d);
    bool known = false;
    for (int k = 0; k < count; ++k)
      known = known || (points[std::size_t(k)] - p).norm() <= Real(1e-6) * size;
    if (!known)
      points[std::size_t(count++)] = p;
  }
  return count;
}

// `on_flat_features`, when given, is set where a cylinder pair overlaps with neither support
// along the normal a single point (an edge across the cylinder's side line, a face on its cap):
// there EPA's points need not be on the line of contact.
ShapeDistance measure(const Shape& a, const Transform& pose_a, const Shape& b,
                      const Transform& pose_b, bool gradients, bool* on_flat_features = nullptr) {
  ShapeDistance d;
  if (a.type == ShapeType::plane && b.type == ShapeType::plane) {
    throw Error("distance_between: two planes (the distance is that of their normals' angle)");
  } else if (a.type == ShapeType::plane) {
    d = plane_and_convex(pose_a, b, pose_b);
  } else if (b.type == ShapeType::plane) {
    d = plane_and_convex(pose_b, a, pose_a);
    std::swap(d.point_a, d.point_b);
    d.normal = -d.normal;
  } else {
    // In a frame centred on A: the query then works with differences of nearby numbers.
    const Vec3 origin = pose_a.translation;
    Transform local_a = pose_a;
    Transform local_b = pose_b;
    local_a.translation.setZero();
    local_b.translation -= origin;
    const ConvexSupport sa = ConvexSupport::of(a, local_a);
    const ConvexSupport sb = ConvexSupport::of(b, local_b);
    const GjkResult g = gjk(sa, sb);
    if (g.status == GjkStatus::intersecting) {
      const EpaResult e = epa(sa, sb, g);
      d.distance = -e.depth;
      d.normal = e.normal;
      d.point_a = e.point_a + origin;
      d.point_b = e.point_b + origin;
      d.converged = e.status == EpaStatus::converged;
      // EPA's witness points interpolate its closest face's vertices. Against a cylinder they
      // may interpolate rim points (a chord off the rim) or points of the partner's rounded or
      // polygonal surface around the line of contact, and the rotation gradients came out
      // wrong. The depth's derivative is that of the supports along the fixed normal (the
      // envelope theorem), and only a point's offset across the normal enters it: where either
      // shape's support along the normal is one point, that point and, for the other shape, the
      // point on the normal's line through it; where both are segments (an edge across the
      // cylinder's side line), the points where they cross, seen along the normal. Where a
      // support is a face, or the segments are parallel, the caller is told.
      if (a.type == ShapeType::cylinder || b.type == ShapeType::cylinder) {
        std::array<Vec3, 5> on_a, on_b;
        const int count_a = support_feature(sa, -d.normal, on_a);
        const int count_b = support_feature(sb, d.normal, on_b);
        const auto crossing = [&](Vec3& point_a, Vec3& point_b) {
          if (count_a != 2 || count_b != 2)
            return false;
          const Vec3 along_a = on_a[1] - on_a[0], along_b = on_b[1] - on_b[0];
          if (!(along_a.cross(along_b).norm() > Real(1e-6) * along_a.norm() * along_b.norm()))
            return false;  // parallel: no single crossing
          Real s = 0, t = 0;
          detail::closest_parameters_between_segments(on_a[0], on_a[1], on_b[0], on_b[1], s, t);
          point_a = on_a[0] + s * along_a;
          point_b = on_b[0] + t * along_b;
          return true;
        };
        Vec3 cross_a, cross_b;
        if (count_a == 1) {
          d.point_a = on_a[0] + origin;
          d.point_b = d.point_a - d.distance * d.normal;
        } else if (count_b == 1) {
          d.point_b = on_b[0] + origin;
          d.point_a = d.point_b + d.distance * d.normal;
        } else if (crossing(cross_a, cross_b)) {
          d.point_a = cross_a + origin;
          d.point_b = cross_b + origin;
        } else if (on_flat_features != nullptr) {
          *on_flat_features = true;
        }
      }
    } else {
      d.distance = g.distance;
      d.normal = g.normal;
      d.point_a = g.point_a + origin;
      d.point_b = g.point_b + origin;
      d.converged = g.status == GjkStatus::separated;
    }
  }
  if (gradients)
    fill_gradients(d, pose_a, pose_b);
  return d;
}

// A penetrating cylinder pair where neither support along the normal is one point (a box's
// edge across the cylinder's side line, say): EPA's points need not lie on the line of contact
// there, and no single support gives it. The depth itself is smooth and precise (central
// differences agree to 1e-9 from steps of 1e-3 down to 1e-7), so such a pair takes its gradients
// from central differences of the distance: 24 more queries.
void numerical_gradients(ShapeDistance& d, const Shape& a, const Transform& pose_a, const Shape& b,
                         const Transform& pose_b) {
  constexpr Real h = 1e-6;  // m and rad
  const auto moved = [](const Transform& pose, int k, Real step) {
    Transform out = pose;
    if (k < 3)
      out.translation[k] += step;
    else
      out.rotation = (Eigen::AngleAxis<Real>(step, Vec3::Unit(k - 3)) * pose.rotation).normalized();
    return out;
  };
  for (int k = 0; k < 6; ++k) {
    d.gradient_a[k] = (measure(a, moved(pose_a, k, h), b, pose_b, false).distance -
                       measure(a, moved(pose_a, k, -h), b, pose_b, false).distance) /
                      (2 * h);
    d.gradient_b[k] = (measure(a, pose_a, b, moved(pose_b, k, h), false).distance -
                       measure(a, pose_a, b, moved(pose_b, k, -h), false).distance) /
                      (2 * h);
  }
}

}  // namespace

ShapeDistance distance_between(const Shape& a, const Transform& pose_a, const Shape& b,
                               const Transform& pose_b, bool gradients) {
  check(a, pose_a, "a");
  check(b, pose_b, "b");
  if (a.type == ShapeType::sdf && b.type == ShapeType::sdf) {
    ShapeDistance d = field_and_field(*a.sdf, a.field_time, pose_a, *b.sdf, b.field_time, pose_b);
    if (!gradients) {
      d.gradient_a.setZero();
      d.gradient_b.setZero();
    }
    return d;
  }
  if (a.type == ShapeType::sdf || b.type == ShapeType::sdf) {
    const bool field_is_b = b.type == ShapeType::sdf;
    const Shape& other = field_is_b ? a : b;
    ShapeDistance d;
    if (other.type == ShapeType::plane) {
      d = field_is_b ? plane_and_field(pose_a, *b.sdf, b.field_time, pose_b)
                     : plane_and_field(pose_b, *a.sdf, a.field_time, pose_a);
    } else {
      const bool round = other.type == ShapeType::sphere || other.type == ShapeType::capsule;
      const auto measure = round ? round_and_field : solid_and_field;
      d = field_is_b ? measure(a, pose_a, *b.sdf, b.field_time, pose_b)
                     : measure(b, pose_b, *a.sdf, a.field_time, pose_a);
    }
    if (!field_is_b) {
      std::swap(d.point_a, d.point_b);
      std::swap(d.gradient_a, d.gradient_b);
      d.normal = -d.normal;
    }
    if (!gradients) {
      d.gradient_a.setZero();
      d.gradient_b.setZero();
    }
    return d;
  }
  bool on_flat_features = false;
  ShapeDistance d = measure(a, pose_a, b, pose_b, gradients, &on_flat_features);
  if (gradients && on_flat_features)
    numerical_gradients(d, a, pose_a, b, pose_b);
  return d;
}

ContactPotential contact_potential(const ShapeDistance& d, Real stiffness, Real max_gradient) {
  if (!(std::isfinite(stiffness) && stiffness >= 0))
    throw Error("contact_potential: stiffness must be finite and not negative");
  if (!(max_gradient > 0))
    throw Error("contact_potential: max_gradient must be positive");
  ContactPotential p;
  if (!(d.distance < 0))
    return p;
  p.value = stiffness / 2 * d.distance * d.distance;
  const auto clipped = [&](const PoseGradient& g) {
    PoseGradient out = stiffness * d.distance * g;
    for (int k = 0; k < 6; ++k)
      out[k] = std::clamp(out[k], -max_gradient, max_gradient);
    return out;
  };
  p.gradient_a = clipped(d.gradient_a);
  p.gradient_b = clipped(d.gradient_b);
  return p;
}

}  // namespace tumble
