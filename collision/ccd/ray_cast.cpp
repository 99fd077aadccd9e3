#include "collision/ccd/ray_cast.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/triangle_mesh.hpp"

namespace tumble {
namespace {

// First entering root of |o + t d|^2 = r^2 with t in [0, 1]; the ray starts outside.
bool sphere_hit(const Vec3& o, const Vec3& d, Real r, Real& t) {
  const Real a = d.squaredNorm();
  const Real b = o.dot(d);
  const Real c = o.squaredNorm() - r * r;
  if (a == 0 || b >= 0)
    return false;  // still or moving away from the centre
  const Real disc = b * b - a * c;
  if (disc < 0)
    return false;
  // Entering root -(b + sqrt(disc)) / a written as c / q to avoid cancellation (b < 0).
  const Real q = -b + std::sqrt(disc);
  t = c / q;
  return t >= 0 && t <= 1;
}

ShapeRayHit local_ray(const Shape& shape, const Vec3& o, const Vec3& d) {
  ShapeRayHit out;
  switch (shape.type) {
    case ShapeType::sphere: {
      Real t = 0;
      if (sphere_hit(o, d, shape.radius, t)) {
        out = {true, t, (o + t * d) / shape.radius};
      }
      return out;
    }
    case ShapeType::plane: {
      if (d.z() < 0) {
        const Real t = -o.z() / d.z();
        if (t <= 1)
          out = {true, t, Vec3::UnitZ()};
      }
      return out;
    }
    case ShapeType::box: {
      Real enter = 0;
      Real exit = 1;
      int enter_axis = -1;
      Real enter_sign = 1;
      for (int k = 0; k < 3; ++k) {
        const Real h = shape.half_extents[k];
        if (d[k] == 0) {
          if (std::abs(o[k]) > h)
            return out;
          continue;
        }
        Real t0 = (-h - o[k]) / d[k];
        Real t1 = (h - o[k]) / d[k];
        Real sign = -1;  // entering through the -h face when moving in +k
        if (t0 > t1) {
          std::swap(t0, t1);
          sign = 1;
        }
        if (t0 > enter) {
          enter = t0;
          enter_axis = k;
          enter_sign = sign;
        }
        exit = std::min(exit, t1);
        if (enter > exit)
          return out;
      }
      if (enter_axis < 0)
        return out;  // starts inside: handled by the caller
      out.hit = true;
      out.fraction = enter;
      out.normal = Vec3::Zero();
      out.normal[enter_axis] = enter_sign;
      return out;
    }
    case ShapeType::capsule: {
      const Real r = shape.radius;
      const Real hl = shape.half_length;
      Real best = std::numeric_limits<Real>::infinity();
      Vec3 normal = Vec3::UnitZ();
      // Side: |o_xy + t d_xy| = r, entering root, with z inside the core's span.
      const Vec3 oxy(o.x(), o.y(), 0);
      const Vec3 dxy(d.x(), d.y(), 0);
      Real t = 0;
      if (sphere_hit(oxy, dxy, r, t)) {
        const Real z = o.z() + t * d.z();
        if (z >= -hl && z <= hl) {
          best = t;
          normal = (oxy + t * dxy) / r;
        }
      }
      for (Real end : {-hl, hl}) {
        const Vec3 centre(0, 0, end);
        if (sphere_hit(o - centre, d, r, t) && t < best) {
          best = t;
          normal = (o + t * d - centre) / r;
        }
      }
      if (best <= 1)
        out = {true, best, normal};
      return out;
    }
    case ShapeType::cylinder: {
      const Real r = shape.radius;
      const Real hl = shape.half_length;
      Real best = std::numeric_limits<Real>::infinity();
      Vec3 normal = Vec3::UnitZ();
      const Vec3 oxy(o.x(), o.y(), 0);
      const Vec3 dxy(d.x(), d.y(), 0);
      Real t = 0;
      if (sphere_hit(oxy, dxy, r, t)) {
        const Real z = o.z() + t * d.z();
        if (z >= -hl && z <= hl) {
          best = t;
          normal = (oxy + t * dxy) / r;
        }
      }
      // Caps: entering through z = +hl moving down, or z = -hl moving up.
      for (const Real side : {Real(-1), Real(1)}) {
        if (d.z() * side >= 0)
          continue;
        const Real tc = (side * hl - o.z()) / d.z();
        const Vec3 p = o + tc * d;
        if (tc >= 0 && tc < best && p.x() * p.x() + p.y() * p.y() <= r * r) {
          best = tc;
          normal = Vec3(0, 0, side);
        }
      }
      if (best <= 1)
        out = {true, best, normal};
      return out;
    }
    case ShapeType::hull: {
      // Cyrus-Beck: the segment clipped by every face's half-space.
      Real enter = 0;
      Real exit = 1;
      Vec3 normal = Vec3::UnitZ();
      bool entered = false;
      for (const HullFace& f : shape.hull->faces()) {
        const Real dn = f.normal.dot(d);
        const Real gap = f.offset - f.normal.dot(o);  // >= 0 inside this face's half-space
        if (dn == 0) {
          if (gap < 0)
            return out;
          continue;
        }
        const Real t = gap / dn;
        if (dn < 0) {
          if (t > enter) {
            enter = t;
            normal = f.normal;
            entered = true;
          }
        } else {
          exit = std::min(exit, t);
        }
        if (enter > exit)
          return out;
      }
      if (entered)
        out = {true, enter, normal};
      return out;
    }
    case ShapeType::mesh: {
      // Triangles are one-sided: hit from the front only (Moller and Trumbore, "Fast, Minimum
      // Storage Ray/Triangle Intersection", JGT 1997), on the triangles whose boxes the
      // segment's box meets.
      const TriangleMesh& mesh = *shape.mesh;
      Aabb box;
      box.grow(o);
      box.grow(o + d);
      Real best = std::numeric_limits<Real>::infinity();
      Vec3 normal = Vec3::UnitZ();
      mesh.for_each_overlapping(box, [&](int tri) {
        const Vec3& n = mesh.normal(tri);
        if (n.dot(d) >= 0)
          return;
        const Vec3 a = mesh.corner(tri, 0);
        const Vec3 e1 = mesh.corner(tri, 1) - a;
        const Vec3 e2 = mesh.corner(tri, 2) - a;
        const Vec3 p = d.cross(e2);
        const Real det = e1.dot(p);
        if (det == 0)
          return;
        const Vec3 s = o - a;
        const Real u = s.dot(p) / det;
        if (u < 0 || u > 1)
          return;
        const Vec3 q = s.cross(e1);
        const Real v = d.dot(q) / det;
        if (v < 0 || u + v > 1)
          return;
        const Real t = e2.dot(q) / det;
        if (t >= 0 && t < best) {
          best = t;
          normal = n;
        }
      });
      if (best <= 1)
        out = {true, best, normal};
      return out;
    }
    case ShapeType::compound: {
      for (const CompoundPart& part : shape.compound->parts()) {
        ShapeRayHit h =
            local_ray(part.shape, part.pose.apply_inverse(o), part.pose.rotate_inverse(d));
        if (h.hit && (!out.hit || h.fraction < out.fraction)) {
          h.normal = part.pose.rotate(h.normal);
          out = h;
        }
      }
      return out;
    }
  }
  return out;
}

// Distance from a point to a triangle mesh's surface (Ericson 5.1.5 per triangle; a scan, this
// is a query for tests and tools, not the step).
Real mesh_distance(const TriangleMesh& mesh, const Vec3& p) {
  Real best = std::numeric_limits<Real>::infinity();
  for (int tri = 0; tri < mesh.triangle_count(); ++tri) {
    const Vec3 a = mesh.corner(tri, 0);
    const Vec3 b = mesh.corner(tri, 1);
    const Vec3 c = mesh.corner(tri, 2);
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
    Vec3 q;
    if (d1 <= 0 && d2 <= 0) {
      q = a;
    } else {
      const Vec3 bp = p - b;
      const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
      const Vec3 cp = p - c;
      const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
      const Real vc = d1 * d4 - d3 * d2;
      const Real vb = d5 * d2 - d1 * d6;
      const Real va = d3 * d6 - d5 * d4;
      if (d3 >= 0 && d4 <= d3)
        q = b;
      else if (vc <= 0 && d1 >= 0 && d3 <= 0)
        q = a + ab * (d1 / (d1 - d3));
      else if (d6 >= 0 && d5 <= d6)
        q = c;
      else if (vb <= 0 && d2 >= 0 && d6 <= 0)
        q = a + ac * (d2 / (d2 - d6));
      else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        q = b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
      else
        q = a + ab * (vb / (va + vb + vc)) + ac * (vc / (va + vb + vc));
    }
    best = std::min(best, (p - q).norm());
  }
  return best;
}

Real local_signed_distance(const Shape& shape, const Vec3& p) {
  switch (shape.type) {
    case ShapeType::sphere:
      return p.norm() - shape.radius;
    case ShapeType::plane:
      return p.z();
    case ShapeType::box: {
      const Vec3 q = p.cwiseAbs() - shape.half_extents;
      return q.cwiseMax(Real(0)).norm() + std::min(q.maxCoeff(), Real(0));
    }
    case ShapeType::capsule: {
      const Real z = std::clamp(p.z(), -shape.half_length, shape.half_length);
      return (p - Vec3(0, 0, z)).norm() - shape.radius;
    }
    case ShapeType::cylinder: {
      // Exact for a finite cylinder: d = (|p_xy| - r, |z| - h).
      const Real dr = std::hypot(p.x(), p.y()) - shape.radius;
      const Real dz = std::abs(p.z()) - shape.half_length;
      return std::hypot(std::max(dr, Real(0)), std::max(dz, Real(0))) +
             std::min(std::max(dr, dz), Real(0));
    }
    case ShapeType::hull: {
      // Inside: the nearest face plane; outside: GJK against the point (exact).
      Real inside = -std::numeric_limits<Real>::infinity();
      for (const HullFace& f : shape.hull->faces())
        inside = std::max(inside, f.normal.dot(p) - f.offset);
      if (inside <= 0)
        return inside;
      const ConvexSupport point = ConvexSupport::of_points(&p, 1, Transform{});
      const GjkResult g = gjk(ConvexSupport::of(shape, Transform{}), point);
      return std::max(g.distance, inside);
    }
    case ShapeType::mesh:
      return mesh_distance(*shape.mesh, p);  // a surface: distance, never negative
    case ShapeType::compound: {
      // The union's distance outside; inside, the deepest part's (a bound on the union's).
      Real best = std::numeric_limits<Real>::infinity();
      for (const CompoundPart& part : shape.compound->parts())
        best = std::min(best, local_signed_distance(part.shape, part.pose.apply_inverse(p)));
      return best;
    }
  }
  return 0;
}

}  // namespace

Real signed_distance(const Shape& shape, const Transform& pose, const Vec3& point) {
  return local_signed_distance(shape, pose.apply_inverse(point));
}

ShapeRayHit ray_cast(const Shape& shape, const Transform& pose, const Vec3& origin,
                     const Vec3& delta) {
  ShapeRayHit out;
  if (!origin.allFinite() || !delta.allFinite())
    return out;
  if (signed_distance(shape, pose, origin) <= 0) {
    out.hit = true;
    out.fraction = 0;
    const Real length = delta.norm();
    out.normal = length > 0 ? Vec3(-delta / length) : Vec3::UnitZ();
    return out;
  }
  const Vec3 o = pose.apply_inverse(origin);
  const Vec3 d = pose.rotate_inverse(delta);
  out = local_ray(shape, o, d);
  if (out.hit)
    out.normal = pose.rotate(out.normal);
  return out;
}

}  // namespace tumble
