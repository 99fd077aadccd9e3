#include "tests/collision/oracle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "collision/shapes/convex_hull.hpp"

namespace tumble::testing {

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

Real uniform(Rng& rng, Real low, Real high) {
  return std::uniform_real_distribution<Real>(low, high)(rng);
}

Vec3 random_unit_vector(Rng& rng) {
  std::normal_distribution<Real> normal(0, 1);
  for (;;) {
    // One draw per statement: a call's arguments are evaluated in an order the compiler picks
    // (GCC right to left, clang left to right), and the cases must not depend on the compiler.
    const Real x = normal(rng), y = normal(rng), z = normal(rng);
    const Vec3 v(x, y, z);
    if (v.norm() > Real(1e-6))
      return v.normalized();
  }
}

Quat random_rotation(Rng& rng) {
  // A normalised 4D Gaussian is uniform on the unit quaternions (Shoemake, Graphics Gems III).
  std::normal_distribution<Real> normal(0, 1);
  for (;;) {
    const Real w = normal(rng), x = normal(rng), y = normal(rng), z = normal(rng);
    Quat q(w, x, y, z);
    if (q.norm() > Real(1e-6))
      return q.normalized();
  }
}

Vec3 random_vector_in_box(Rng& rng, Real half_width) {
  return {uniform(rng, -half_width, half_width), uniform(rng, -half_width, half_width),
          uniform(rng, -half_width, half_width)};
}

Shape random_shape(Rng& rng, ShapeType type) {
  switch (type) {
    case ShapeType::sphere:
      return Shape::sphere(uniform(rng, 0.2, 1.2));
    case ShapeType::box:
      return Shape::box(
          {uniform(rng, 0.15, 1.2), uniform(rng, 0.15, 1.2), uniform(rng, 0.15, 1.2)});
    case ShapeType::capsule: {
      const Real radius = uniform(rng, 0.1, 0.8);
      return Shape::capsule(radius, uniform(rng, 0.05, 1.2));
    }
    case ShapeType::plane:
      return Shape::plane();
    case ShapeType::cylinder: {
      const Real radius = uniform(rng, 0.15, 1.0);
      return Shape::cylinder(radius, uniform(rng, 0.1, 1.0));
    }
    case ShapeType::hull: {
      // 4 to 43 points, half of the time on a sphere (many faces), otherwise in a box (a few
      // big faces with merged coplanar facets are rarer but happen with 8 corners below).
      const int count = 4 + int(uniform(rng, 0, 40));
      const Vec3 size{uniform(rng, 0.2, 1.0), uniform(rng, 0.2, 1.0), uniform(rng, 0.2, 1.0)};
      std::vector<Vec3> points;
      const int style = int(uniform(rng, 0, 3));
      for (int i = 0; i < count; ++i) {
        if (style == 0)
          points.push_back(random_unit_vector(rng).cwiseProduct(size));
        else
          points.push_back(random_vector_in_box(rng, 1).cwiseProduct(size));
      }
      if (style == 2) {
        // A box's corners plus the interior points: merged square faces.
        for (int v = 0; v < 8; ++v)
          points.push_back(Vec3(v & 1 ? 1 : -1, v & 2 ? 1 : -1, v & 4 ? 1 : -1).cwiseProduct(size));
      }
      return Shape::convex_hull(
          std::make_shared<const ConvexHull>(ConvexHull::from_points(points)));
    }
    case ShapeType::mesh:
    case ShapeType::compound:
    case ShapeType::sdf:
      break;
  }
  return {};
}

namespace {

// Distance from p to triangle (a, b, c): the projection when it falls inside (tested with
// edge-side signs), else the nearest edge.
Real point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const Real n2 = n.squaredNorm();
  if (n2 > 0) {
    const Vec3 q = p - n * (n.dot(p - a) / n2);
    const bool inside = (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
                        (a - c).cross(q - c).dot(n) >= 0;
    if (inside)
      return (p - q).norm();
  }
  return std::min({point_segment_distance(p, a, b), point_segment_distance(p, b, c),
                   point_segment_distance(p, c, a)});
}

}  // namespace

Real hull_local_signed_distance(const ConvexHull& hull, const Vec3& p) {
  Real largest = -kInfinity;
  for (const HullFace& f : hull.faces())
    largest = std::max(largest, f.normal.dot(p) - f.offset);
  if (largest <= 0)
    return largest;
  Real best = kInfinity;
  for (const HullFace& f : hull.faces()) {
    const auto at = [&](int k) {
      return hull.vertex(hull.face_vertices()[std::size_t(f.first_index + k)]);
    };
    for (int k = 1; k + 1 < f.count; ++k)
      best = std::min(best, point_triangle_distance(p, at(0), at(k), at(k + 1)));
  }
  return best;
}

Real local_signed_distance(const Shape& shape, const Vec3& p) {
  switch (shape.type) {
    case ShapeType::sphere:
      return p.norm() - shape.radius;
    case ShapeType::box: {
      Real outside_squared = 0;
      Real largest = -kInfinity;
      for (int k = 0; k < 3; ++k) {
        const Real q = std::abs(p[k]) - shape.half_extents[k];
        if (q > 0)
          outside_squared += q * q;
        largest = std::max(largest, q);
      }
      return outside_squared > 0 ? std::sqrt(outside_squared) : largest;
    }
    case ShapeType::capsule: {
      const Real z = std::clamp(p.z(), -shape.half_length, shape.half_length);
      return (p - Vec3(0, 0, z)).norm() - shape.radius;
    }
    case ShapeType::plane:
      return p.z();
    case ShapeType::cylinder: {
      // Exact SDF of a finite cylinder (Quilez): d = (|p_xy| - r, |z| - h).
      const Real dr = std::hypot(p.x(), p.y()) - shape.radius;
      const Real dz = std::abs(p.z()) - shape.half_length;
      const Real outside = std::hypot(std::max(dr, Real(0)), std::max(dz, Real(0)));
      return outside + std::min(std::max(dr, dz), Real(0));
    }
    case ShapeType::hull:
      return hull_local_signed_distance(*shape.hull, p);
    case ShapeType::mesh:
    case ShapeType::compound:
    case ShapeType::sdf:
      break;
  }
  return 0;
}

Real signed_distance_to_shape(const Shape& shape, const Transform& pose, const Vec3& world_point) {
  return local_signed_distance(shape, pose.apply_inverse(world_point));
}

Vec3 random_surface_point(Rng& rng, const Shape& shape) {
  switch (shape.type) {
    case ShapeType::sphere:
      return random_unit_vector(rng) * shape.radius;
    case ShapeType::box: {
      const Vec3& h = shape.half_extents;
      const Vec3 areas(h.y() * h.z(), h.x() * h.z(), h.x() * h.y());
      Real pick = uniform(rng, 0, areas.sum());
      int axis = 0;
      while (axis < 2 && pick > areas[axis])
        pick -= areas[axis++];
      Vec3 p = random_vector_in_box(rng, 1).cwiseProduct(h);
      p[axis] = uniform(rng, 0, 1) < 0.5 ? -h[axis] : h[axis];
      return p;
    }
    case ShapeType::capsule: {
      const Real r = shape.radius;
      const Real a = shape.half_length;
      const Real side_area = 2 * std::numbers::pi * r * 2 * a;
      const Real caps_area = 4 * std::numbers::pi * r * r;
      if (uniform(rng, 0, side_area + caps_area) < side_area) {
        const Real angle = uniform(rng, 0, 2 * std::numbers::pi);
        return {r * std::cos(angle), r * std::sin(angle), uniform(rng, -a, a)};
      }
      const Vec3 u = random_unit_vector(rng);
      return Vec3(0, 0, u.z() >= 0 ? a : -a) + u * r;
    }
    case ShapeType::plane:
      return {uniform(rng, -10, 10), uniform(rng, -10, 10), 0};
    case ShapeType::cylinder: {
      const Real r = shape.radius;
      const Real h = shape.half_length;
      const Real side_area = 2 * std::numbers::pi * r * 2 * h;
      const Real caps_area = 2 * std::numbers::pi * r * r;
      const Real angle = uniform(rng, 0, 2 * std::numbers::pi);
      if (uniform(rng, 0, side_area + caps_area) < side_area)
        return {r * std::cos(angle), r * std::sin(angle), uniform(rng, -h, h)};
      const Real rho = r * std::sqrt(uniform(rng, 0, 1));
      return {rho * std::cos(angle), rho * std::sin(angle), uniform(rng, 0, 1) < 0.5 ? -h : h};
    }
    case ShapeType::hull: {
      // A random face, a random point of a random fan triangle (not area-uniform; enough for
      // surface tests).
      const ConvexHull& hull = *shape.hull;
      const HullFace& f =
          hull.faces()[std::size_t(uniform(rng, 0, Real(hull.faces().size()) - 1e-9))];
      const auto at = [&](int k) {
        return hull.vertex(hull.face_vertices()[std::size_t(f.first_index + k)]);
      };
      const int k = 1 + int(uniform(rng, 0, Real(f.count - 2) - 1e-9));
      Real u = uniform(rng, 0, 1);
      Real v = uniform(rng, 0, 1);
      if (u + v > 1) {
        u = 1 - u;
        v = 1 - v;
      }
      return at(0) + u * (at(k) - at(0)) + v * (at(k + 1) - at(0));
    }
    case ShapeType::mesh:
    case ShapeType::compound:
    case ShapeType::sdf:
      break;
  }
  return Vec3::Zero();
}

Real support_value(const Shape& shape, const Transform& pose, const Vec3& direction) {
  if (shape.type == ShapeType::plane) {
    const Vec3 normal = pose.rotate(Vec3::UnitZ());
    const Real length = direction.norm();
    if (direction.dot(normal) >= (1 - Real(1e-12)) * length) {
      return direction.dot(pose.translation);
    }
    return kInfinity;
  }
  const Vec3 local = pose.rotate_inverse(direction);
  return direction.dot(pose.apply(support(shape, local)));
}

Real separation_along(const Shape& a, const Transform& pose_a, const Shape& b,
                      const Transform& pose_b, const Vec3& n) {
  return -support_value(a, pose_a, -n) - support_value(b, pose_b, n);
}

Real point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const Real length_squared = d.squaredNorm();
  if (length_squared == 0)
    return (p - a).norm();
  const Real t = std::clamp((p - a).dot(d) / length_squared, Real(0), Real(1));
  return (p - (a + d * t)).norm();
}

Real segment_segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  // Boundary of the parameter square: each side is a point against the other segment.
  Real best = std::min({point_segment_distance(p0, q0, q1), point_segment_distance(p1, q0, q1),
                        point_segment_distance(q0, p0, p1), point_segment_distance(q1, p0, p1)});
  // Interior: the stationary point of the quadratic, when it exists and lies in the square.
  const Vec3 d1 = p1 - p0;
  const Vec3 d2 = q1 - q0;
  const Vec3 r = p0 - q0;
  const Real a = d1.dot(d1);
  const Real b = d1.dot(d2);
  const Real e = d2.dot(d2);
  const Real determinant = a * e - b * b;
  if (determinant > Real(1e-14) * a * e && determinant > 0) {
    const Real s = (b * d2.dot(r) - e * d1.dot(r)) / determinant;
    const Real t = (a * d2.dot(r) - b * d1.dot(r)) / determinant;
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) {
      best = std::min(best, (p0 + d1 * s - (q0 + d2 * t)).norm());
    }
  }
  return best;
}

Real hull_signed_distance_of_origin(const std::vector<Vec3>& points) {
  const int n = int(points.size());
  Real scale = 0;
  for (const Vec3& p : points)
    scale = std::max(scale, p.norm());
  scale = std::max(scale, Real(1e-300));
  const Real plane_tolerance = Real(1e-10) * scale;

  Real outside = kInfinity;
  for (int i = 0; i < n; ++i) {
    outside = std::min(outside, points[i].norm());
    for (int j = i + 1; j < n; ++j) {
      outside = std::min(outside, point_segment_distance(Vec3::Zero(), points[i], points[j]));
    }
  }

  bool found_facet = false;
  bool flat = false;
  bool inside = true;
  Real nearest_facet = kInfinity;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      for (int k = j + 1; k < n; ++k) {
        Vec3 normal = (points[j] - points[i]).cross(points[k] - points[i]);
        const Real length = normal.norm();
        if (!(length > Real(1e-12) * scale * scale))
          continue;
        normal /= length;
        const Real offset = normal.dot(points[i]);
        bool all_below = true;
        bool all_above = true;
        for (int m = 0; m < n && (all_below || all_above); ++m) {
          const Real height = normal.dot(points[m]) - offset;
          if (height > plane_tolerance)
            all_below = false;
          if (height < -plane_tolerance)
            all_above = false;
        }
        // All points on the plane: the set is flat and has no inside; its distance is the
        // distance to the polygon, which the triangles and segments below give.
        if (all_below && all_above)
          flat = true;
        for (const int orientation : {1, -1}) {
          if (orientation == 1 ? !all_below : !all_above)
            continue;
          const Vec3 outward = normal * Real(orientation);
          const Real outward_offset = offset * Real(orientation);  // origin height: -offset
          found_facet = true;
          if (outward_offset < -plane_tolerance)
            inside = false;
          nearest_facet = std::min(nearest_facet, outward_offset);
          // Distance through the facet's interior: the origin's projection inside the triangle.
          const Vec3 projection = outward * outward_offset;
          const Vec3* corner[3] = {&points[i], &points[j], &points[k]};
          bool within = true;
          for (int e = 0; e < 3 && within; ++e) {
            const Vec3& from = *corner[e];
            const Vec3& to = *corner[(e + 1) % 3];
            within =
                (to - from).cross(projection - from).dot(normal) >= -Real(1e-12) * scale * scale;
          }
          // The winding of (i, j, k) agrees with `normal`, whichever orientation is outward.
          if (within)
            outside = std::min(outside, std::abs(outward_offset));
        }
      }
    }
  }
  if (found_facet && inside && !flat)
    return -std::max(nearest_facet, Real(0));
  return outside;
}

namespace {

void core_of(const Shape& shape, const Transform& pose, std::vector<Vec3>& core, Real& radius) {
  core.clear();
  switch (shape.type) {
    case ShapeType::sphere:
      core.push_back(pose.translation);
      radius = shape.radius;
      return;
    case ShapeType::capsule:
      core.push_back(pose.apply(Vec3(0, 0, -shape.half_length)));
      core.push_back(pose.apply(Vec3(0, 0, shape.half_length)));
      radius = shape.radius;
      return;
    case ShapeType::box:
      for (int v = 0; v < 8; ++v) {
        Vec3 corner;
        for (int k = 0; k < 3; ++k) {
          corner[k] = (v >> k) & 1 ? shape.half_extents[k] : -shape.half_extents[k];
        }
        core.push_back(pose.apply(corner));
      }
      radius = 0;
      return;
    case ShapeType::hull:
      for (const Vec3& v : shape.hull->vertices())
        core.push_back(pose.apply(v));
      radius = 0;
      return;
    case ShapeType::plane:
    case ShapeType::cylinder:  // no finite core: tests use its exact SDF or Bullet instead
    case ShapeType::mesh:
    case ShapeType::compound:
      break;
    default:  // cylinder, hull, mesh, compound: not part of this oracle
      break;
  }
}

}  // namespace

Real brute_force_signed_distance(const Shape& a, const Transform& pose_a, const Shape& b,
                                 const Transform& pose_b) {
  if (b.type == ShapeType::plane) {
    return separation_along(a, pose_a, b, pose_b, pose_b.rotate(Vec3::UnitZ()));
  }
  if (a.type == ShapeType::plane) {
    return separation_along(a, pose_a, b, pose_b, -pose_a.rotate(Vec3::UnitZ()));
  }
  std::vector<Vec3> core_a;
  std::vector<Vec3> core_b;
  Real radius_a = 0;
  Real radius_b = 0;
  core_of(a, pose_a, core_a, radius_a);
  core_of(b, pose_b, core_b, radius_b);
  std::vector<Vec3> difference;
  for (const Vec3& p : core_a) {
    for (const Vec3& q : core_b)
      difference.push_back(p - q);
  }
  if (difference.size() <= 48)
    return hull_signed_distance_of_origin(difference) - radius_a - radius_b;
  // Too many points for the O(n^4) enumeration: Qhull builds the Minkowski difference's hull
  // and the origin's distance to it is enumerated over its faces (hull_local_signed_distance,
  // which shares nothing with GJK/EPA).
  const ConvexHull hull = ConvexHull::from_points(difference);
  return hull_local_signed_distance(hull, -hull.centre_of_mass_offset()) - radius_a - radius_b;
}

int deepest_point(const Manifold& m) {
  int best = -1;
  for (int i = 0; i < m.count; ++i) {
    if (best < 0 || m.points[i].depth > m.points[best].depth)
      best = i;
  }
  return best;
}

}  // namespace tumble::testing
