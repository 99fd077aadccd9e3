// Convex primitive against one triangle. Sphere: closest point on the triangle (Ericson 5.1.5).
// Capsule: closest points between the core segment and the triangle (end points against the
// face, the segment against the three edges, Ericson 5.1.9), with both ends reported when the
// capsule lies on the face. Box: separating-axis test over the 13 axes of Akenine-Moller, "Fast
// 3D Triangle-Box Overlap Testing" (JGT 2001), used as a contact generator: the least separated
// axis (preferring the triangle's face, then the box's faces, with the hysteresis of
// clearly_more_separated) picks the reference feature, and the incident polygon is clipped
// against its side planes (Sutherland-Hodgman, Ericson 8.3.4).
#include "collision/pairs/convex_triangle.hpp"

#include <cmath>

#include "collision/pairs/pairs.hpp"

namespace tumble::detail {
namespace {

TriangleRegion edge_region(int k) {
  return TriangleRegion(1 + k);
}
TriangleRegion corner_region(int k) {
  return TriangleRegion(4 + k);
}

Real triangle_size(const TriangleView& tri) {
  return std::max({(tri.corner[1] - tri.corner[0]).norm(), (tri.corner[2] - tri.corner[1]).norm(),
                   (tri.corner[0] - tri.corner[2]).norm()});
}

// Whether the projection of `p` along the normal falls inside the triangle (edges included).
bool projects_inside(const Vec3& p, const TriangleView& tri) {
  for (int k = 0; k < 3; ++k) {
    const Vec3 inward = tri.normal.cross(tri.corner[(k + 1) % 3] - tri.corner[k]);
    if (inward.dot(p - tri.corner[k]) < 0)
      return false;
  }
  return true;
}

// A polygon vertex during clipping: its point, the convex feature and the triangle region.
struct PolygonVertex {
  Vec3 p;
  std::uint16_t convex_feature;
  TriangleRegion region;
};
struct Polygon {
  std::array<PolygonVertex, 12> v;
  int count = 0;
  void push(const PolygonVertex& x) {
    if (count < int(v.size()))
      v[count++] = x;
  }
};

// Keeps the part of `in` where distance(p) >= 0. A crossing takes `crossing_feature` and
// `crossing_region` from the caller, who knows which plane it is.
template <class Distance, class Label>
Polygon clip(const Polygon& in, Distance distance, Label label) {
  Polygon out;
  for (int i = 0; i < in.count; ++i) {
    const PolygonVertex& p = in.v[i];
    const PolygonVertex& q = in.v[(i + 1) % in.count];
    const Real dp = distance(p.p);
    const Real dq = distance(q.p);
    if (dp >= 0)
      out.push(p);
    if ((dp >= 0) != (dq >= 0)) {
      const Real t = dp / (dp - dq);
      PolygonVertex x = label(p, q);
      x.p = p.p + (q.p - p.p) * t;
      out.push(x);
    }
  }
  return out;
}

}  // namespace

RegionUse region_use(const TriangleView& tri, TriangleRegion region) {
  const int r = int(region);
  if (r == 0)
    return RegionUse::keep;
  if (r <= 3) {
    switch (tri.edge[r - 1]) {
      case EdgeKind::boundary:
      case EdgeKind::convex:
        return RegionUse::keep;
      case EdgeKind::flat:
        return RegionUse::use_face;
      case EdgeKind::concave:
        return RegionUse::drop;
    }
  }
  const int k = r - 4;
  if (tri.corner_active[k])
    return RegionUse::keep;
  if (tri.edge[k] == EdgeKind::concave || tri.edge[(k + 2) % 3] == EdgeKind::concave)
    return RegionUse::drop;
  return RegionUse::use_face;
}

Vec3 closest_point_on_triangle(const Vec3& p, const std::array<Vec3, 3>& tri,
                               TriangleRegion& region) {
  const Vec3& a = tri[0];
  const Vec3& b = tri[1];
  const Vec3& c = tri[2];
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const Real d1 = ab.dot(ap);
  const Real d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) {
    region = TriangleRegion::corner0;
    return a;
  }
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp);
  const Real d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) {
    region = TriangleRegion::corner1;
    return b;
  }
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    region = TriangleRegion::edge0;
    return a + ab * (d1 / (d1 - d3));
  }
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp);
  const Real d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) {
    region = TriangleRegion::corner2;
    return c;
  }
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    region = TriangleRegion::edge2;
    return a + ac * (d2 / (d2 - d6));
  }
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    region = TriangleRegion::edge1;
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  region = TriangleRegion::face;
  const Real denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

int sphere_triangle(const Shape& sphere, const TriangleView& tri, Real margin,
                    TriangleContact& contact) {
  const Real r = sphere.radius;
  TriangleRegion region;
  const Vec3 closest = closest_point_on_triangle(Vec3::Zero(), tri.corner, region);
  const RegionUse use = region_use(tri, region);
  if (use == RegionUse::drop)
    return 0;
  if (use == RegionUse::keep && region != TriangleRegion::face) {
    const Vec3 offset = -closest;  // from the triangle to the centre
    const Real distance = offset.norm();
    if (distance > Real(1e-12) * (r + triangle_size(tri))) {
      const Vec3 normal = offset / distance;
      if (normal.dot(tri.normal) < 0)
        return 0;  // behind the triangle
      contact.normal = normal;
      contact.add(-normal * r, r - distance, feature::kSphere, region, margin);
      return contact.count;
    }
  }
  // Face: the centre's height over the triangle's plane.
  const Real height = -tri.normal.dot(tri.corner[0]);
  if (height < -r)
    return 0;  // entirely behind
  contact.normal = tri.normal;
  contact.add(-tri.normal * r, r - height, feature::kSphere, TriangleRegion::face, margin);
  return contact.count;
}

int capsule_triangle(const Shape& capsule, const TriangleView& tri, Real margin,
                     TriangleContact& contact) {
  const Real r = capsule.radius;
  const std::array<Vec3, 2> end{Vec3(0, 0, -capsule.half_length), Vec3(0, 0, capsule.half_length)};
  const Vec3& n = tri.normal;
  const std::array<Real, 2> height{n.dot(end[0] - tri.corner[0]), n.dot(end[1] - tri.corner[0])};
  if (height[0] < -r && height[1] < -r)
    return 0;  // entirely behind
  const Real scale = r + capsule.half_length + triangle_size(tri);

  // Closest points between the core segment and the triangle: the ends against the face, the
  // segment against each edge; the first minimum wins, so the choice is deterministic.
  Real best = std::numeric_limits<Real>::infinity();
  Vec3 on_segment = end[0];
  Vec3 on_triangle = tri.corner[0];
  Real segment_t = 0;
  TriangleRegion region = TriangleRegion::face;
  for (int i = 0; i < 2; ++i) {
    TriangleRegion rg;
    const Vec3 q = closest_point_on_triangle(end[i], tri.corner, rg);
    const Real d2 = (end[i] - q).squaredNorm();
    if (d2 < best) {
      best = d2;
      on_segment = end[i];
      on_triangle = q;
      segment_t = Real(i);
      region = rg;
    }
  }
  for (int k = 0; k < 3; ++k) {
    Real s = 0;
    Real t = 0;
    closest_parameters_between_segments(end[0], end[1], tri.corner[k], tri.corner[(k + 1) % 3], s,
                                        t);
    const Vec3 ps = end[0] + (end[1] - end[0]) * s;
    const Vec3 pt = tri.corner[k] + (tri.corner[(k + 1) % 3] - tri.corner[k]) * t;
    const Real d2 = (ps - pt).squaredNorm();
    if (d2 < best) {
      best = d2;
      on_segment = ps;
      on_triangle = pt;
      segment_t = s;
      region = t <= 0 ? corner_region(k) : (t >= 1 ? corner_region((k + 1) % 3) : edge_region(k));
    }
  }
  // The core pierces the face: the ends lie on both sides and the crossing is inside.
  bool pierces = false;
  if ((height[0] > 0) != (height[1] > 0) && height[0] != height[1]) {
    const Real t = height[0] / (height[0] - height[1]);
    pierces = projects_inside(end[0] + (end[1] - end[0]) * t, tri);
  }
  const Real distance = std::sqrt(best);
  if (!pierces && distance > Real(1e-12) * scale && region != TriangleRegion::face) {
    const RegionUse use = region_use(tri, region);
    if (use == RegionUse::drop)
      return 0;
    if (use == RegionUse::keep) {
      const Vec3 normal = (on_segment - on_triangle) / distance;
      if (normal.dot(n) < 0)
        return 0;  // behind the triangle
      contact.normal = normal;
      contact.add(on_segment - normal * r, r - distance, feature::capsule_feature_at(segment_t),
                  region, margin);
      return contact.count;
    }
  }
  // Face contact: both ends where they lie over the face, else the closest point.
  contact.normal = n;
  for (int i = 0; i < 2; ++i) {
    if (projects_inside(end[i], tri))
      contact.add(end[i] - n * r, r - height[i],
                  i == 0 ? feature::kCapsuleEnd0 : feature::kCapsuleEnd1, TriangleRegion::face,
                  margin);
  }
  if (contact.count == 0) {
    // The deepest point of the segment over the face: the lower end's side of the crossing.
    const Vec3 lowest = pierces ? (height[0] < height[1] ? end[0] : end[1]) : on_segment;
    contact.add(lowest - n * r, r - n.dot(lowest - tri.corner[0]), feature::kCapsuleSide,
                TriangleRegion::face, margin);
  }
  return contact.count;
}

int box_triangle(const Shape& box, const TriangleView& tri, Real margin, TriangleContact& contact) {
  const Vec3& h = box.half_extents;
  const std::array<Vec3, 3>& u = tri.corner;
  const Vec3& n = tri.normal;
  const Real scale = h.norm() + triangle_size(tri);
  const auto box_radius = [&](const Vec3& l) {
    return std::abs(l.x()) * h.x() + std::abs(l.y()) * h.y() + std::abs(l.z()) * h.z();
  };

  // The axis with the least penetration; `kind` 0 = triangle face, 1 = box face, 2 = edges.
  struct Axis {
    Vec3 direction;  // from the triangle to the box
    Real separation;
    int kind;
    int box_axis;
    int triangle_edge;
  };
  Axis best{n, -box_radius(n) - n.dot(u[0]), 0, -1, -1};
  if (best.separation > margin)
    return 0;
  // Tries `l` in both orientations; false when it separates the shapes by more than the margin.
  const auto consider = [&](const Vec3& l, int kind, int box_axis, int triangle_edge) {
    const Real a = l.dot(u[0]);
    const Real b = l.dot(u[1]);
    const Real c = l.dot(u[2]);
    const Real lo = std::min({a, b, c});
    const Real hi = std::max({a, b, c});
    const Real rb = box_radius(l);
    const Real positive = -rb - hi;  // box on the +l side
    const Real negative = lo - rb;   // box on the -l side
    const Real s = std::max(positive, negative);
    if (s > margin)
      return false;
    if (clearly_more_separated(s, best.separation, scale))
      best = {positive >= negative ? l : Vec3(-l), s, kind, box_axis, triangle_edge};
    return true;
  };
  for (int k = 0; k < 3; ++k)
    if (!consider(Vec3::Unit(k), 1, k, -1))
      return 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Vec3 edge = u[(j + 1) % 3] - u[j];
      const Vec3 l = Vec3::Unit(i).cross(edge);
      const Real length = l.norm();
      if (length <= Real(1e-6) * edge.norm())
        continue;  // parallel: the face axes cover it
      if (!consider(l / length, 2, i, j))
        return 0;
    }
  }

  if (best.kind != 0) {
    // The triangle's feature nearest the box along the axis decides whether an axis other than
    // the face normal may be used (internal edges).
    const Vec3& l = best.direction;
    if (l.dot(n) < 0)
      return 0;  // behind the triangle
    const std::array<Real, 3> along{l.dot(u[0]), l.dot(u[1]), l.dot(u[2])};
    const Real top = std::max({along[0], along[1], along[2]});
    const Real tolerance = Real(1e-9) * scale;
    int at_top = 0;
    int first = -1;
    int last = -1;
    for (int k = 0; k < 3; ++k) {
      if (along[k] >= top - tolerance) {
        ++at_top;
        if (first < 0)
          first = k;
        last = k;
      }
    }
    TriangleRegion region = TriangleRegion::face;
    if (at_top == 1)
      region = corner_region(first);
    else if (at_top == 2)
      region = edge_region(last - first == 1 ? first : 2);  // corners (0,2) make edge 2
    const RegionUse use = region_use(tri, region);
    if (use == RegionUse::drop)
      return 0;
    if (use == RegionUse::use_face)
      best = {n, -box_radius(n) - n.dot(u[0]), 0, -1, -1};
  }

  contact.normal = best.direction;
  if (best.kind == 0) {
    // Reference: the triangle. Incident: the box face most against the normal.
    int k = 0;
    for (int m = 1; m < 3; ++m)
      if (std::abs(n[m]) > std::abs(n[k]))
        k = m;
    const int sign_bit = n[k] < 0 ? 1 : 0;  // the face whose outward normal opposes n
    const int j1 = (k + 1) % 3;
    const int j2 = (k + 2) % 3;
    Polygon polygon;
    const int signs[4][2] = {{1, 1}, {0, 1}, {0, 0}, {1, 0}};
    for (const auto& s : signs) {
      const int bits = (sign_bit << k) | (s[0] << j1) | (s[1] << j2);
      Vec3 p;
      for (int m = 0; m < 3; ++m)
        p[m] = (bits >> m) & 1 ? h[m] : -h[m];
      polygon.push({p, feature::box_vertex(bits), TriangleRegion::face});
    }
    for (int e = 0; e < 3 && polygon.count > 0; ++e) {
      const Vec3 inward = n.cross(u[(e + 1) % 3] - u[e]);
      polygon = clip(
          polygon, [&](const Vec3& p) { return inward.dot(p - u[e]); },
          [&](const PolygonVertex& p, const PolygonVertex& q) {
            // A box edge crossing the triangle's side e: name it by the box edge's corners.
            const int differ = p.convex_feature ^ q.convex_feature;
            const bool corners = p.convex_feature < 8 && q.convex_feature < 8 &&
                                 (differ == 1 || differ == 2 || differ == 4);
            const std::uint16_t f =
                corners
                    ? feature::box_edge(differ == 1 ? 0 : (differ == 2 ? 1 : 2), p.convex_feature)
                    : p.convex_feature;
            return PolygonVertex{Vec3::Zero(), f, edge_region(e)};
          });
    }
    for (int i = 0; i < polygon.count; ++i) {
      const PolygonVertex& v = polygon.v[i];
      if (contact.count == TriangleContact::kMaxPoints)
        break;
      contact.add(v.p, -n.dot(v.p - u[0]), v.convex_feature, v.region, margin);
    }
    return contact.count;
  }
  if (best.kind == 1) {
    // Reference: the box face facing the triangle; incident: the triangle.
    const int k = best.box_axis;
    const Real sigma = best.direction[k];  // +1 or -1
    const std::uint16_t face = feature::box_face(k, sigma < 0);
    Polygon polygon;
    for (int c = 0; c < 3; ++c)
      polygon.push({u[c], face, corner_region(c)});
    for (int m = 1; m < 3 && polygon.count > 0; ++m) {
      const int j = (k + m) % 3;
      for (const Real side : {Real(1), Real(-1)}) {
        polygon = clip(
            polygon, [&](const Vec3& p) { return h[j] - side * p[j]; },
            [&](const PolygonVertex& p, const PolygonVertex& q) {
              const int rp = int(p.region) - 4;
              const int rq = int(q.region) - 4;
              TriangleRegion r = p.region;
              if (rp >= 0 && rq >= 0)
                r = edge_region((rq == (rp + 1) % 3) ? rp : rq);
              return PolygonVertex{Vec3::Zero(), face, r};
            });
      }
    }
    for (int i = 0; i < polygon.count; ++i) {
      const PolygonVertex& v = polygon.v[i];
      if (contact.count == TriangleContact::kMaxPoints)
        break;
      const Real depth = h[k] + sigma * v.p[k];
      contact.add(v.p - best.direction * depth, depth, v.convex_feature, v.region, margin);
    }
    return contact.count;
  }
  // Edge against edge: the box edge along box_axis nearest the triangle, and the triangle edge.
  const Vec3& l = best.direction;
  const int i = best.box_axis;
  int bits = 0;
  Vec3 e0;
  for (int m = 0; m < 3; ++m) {
    const bool positive = m != i && l[m] < 0;  // the box's support towards -l
    if (positive)
      bits |= 1 << m;
    e0[m] = positive ? h[m] : -h[m];
  }
  Vec3 e1 = e0;
  e0[i] = -h[i];
  e1[i] = h[i];
  const int j = best.triangle_edge;
  Real s = 0;
  Real t = 0;
  closest_parameters_between_segments(e0, e1, u[j], u[(j + 1) % 3], s, t);
  const Vec3 on_box = e0 + (e1 - e0) * s;
  const Vec3 on_triangle = u[j] + (u[(j + 1) % 3] - u[j]) * t;
  contact.add(on_box, -l.dot(on_box - on_triangle), feature::box_edge(i, bits), edge_region(j),
              margin);
  return contact.count;
}

}  // namespace tumble::detail
