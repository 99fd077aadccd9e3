// Convex primitive against one triangle. Sphere: closest point on the triangle (Ericson 5.1.5).
// Capsule: closest points between the core segment and the triangle (end points against the
// face, the segment against the three edges, Ericson 5.1.9), with both ends reported when the
// capsule lies on the face. Box: separating-axis test over the 13 axes of Akenine-Moller, "Fast
// 3D Triangle-Box Overlap Testing" (JGT 2001), used as a contact generator: the least separated
// axis (preferring the triangle's face, then the box's faces, with the hysteresis of
// clearly_more_separated) picks the reference feature, and the incident polygon is clipped
// against its side planes (Sutherland-Hodgman, Ericson 8.3.4).
#include "collision/narrow_phase/pairs/convex_triangle.hpp"

#include <cmath>

#include "collision/narrow_phase/pairs/pairs.hpp"

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

// Exact closest points of the box [-h, h] and a triangle that does not touch it: for two
// disjoint convex polytopes the minimum is reached vertex against face (either way round) or
// edge against edge, so 8 + 3 + 12 x 3 candidates cover it. Ties keep the first found.
struct ClosestFeatures {
  Real distance_squared = std::numeric_limits<Real>::infinity();
  Vec3 on_box;
  Vec3 on_triangle;
  std::uint16_t box_feature = 0;
  TriangleRegion region = TriangleRegion::face;
};

ClosestFeatures closest_box_triangle(const Vec3& h, const std::array<Vec3, 3>& u) {
  ClosestFeatures best;
  const auto offer = [&](const Vec3& on_box, const Vec3& on_triangle, std::uint16_t feature,
                         TriangleRegion region) {
    const Real d2 = (on_box - on_triangle).squaredNorm();
    if (d2 < best.distance_squared)
      best = {d2, on_box, on_triangle, feature, region};
  };
  const auto corner_of = [&](int bits) {
    return Vec3((bits & 1) ? h.x() : -h.x(), (bits & 2) ? h.y() : -h.y(),
                (bits & 4) ? h.z() : -h.z());
  };
  for (int bits = 0; bits < 8; ++bits) {
    // The closest point first: it sets `region`, and the order in which a call's arguments are
    // evaluated is unspecified (GCC read `region` before the call set it, clang after).
    TriangleRegion region = TriangleRegion::face;
    const Vec3 corner = corner_of(bits);
    const Vec3 on_triangle = closest_point_on_triangle(corner, u, region);
    offer(corner, on_triangle, feature::box_vertex(bits), region);
  }
  for (int k = 0; k < 3; ++k) {
    const Vec3 clamped = u[k].cwiseMax(-h).cwiseMin(h);
    offer(clamped, u[k], box_feature_of_outside_point(u[k], h), corner_region(k));
  }
  for (int axis = 0; axis < 3; ++axis) {
    for (int bits = 0; bits < 8; ++bits) {
      if (bits & (1 << axis))
        continue;  // each edge once, from its negative end
      const Vec3 e0 = corner_of(bits);
      const Vec3 e1 = corner_of(bits | (1 << axis));
      for (int j = 0; j < 3; ++j) {
        Real s = 0;
        Real t = 0;
        closest_parameters_between_segments(e0, e1, u[j], u[(j + 1) % 3], s, t);
        const TriangleRegion region =
            t <= 0 ? corner_region(j) : (t >= 1 ? corner_region((j + 1) % 3) : edge_region(j));
        offer(e0 + (e1 - e0) * s, u[j] + (u[(j + 1) % 3] - u[j]) * t, feature::box_edge(axis, bits),
              region);
      }
    }
  }
  return best;
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
  const unsigned k = unsigned(r - 4) % 3u;  // 0..2 (the modulo also tells the compiler so)
  if (tri.corner_active[k])
    return RegionUse::keep;
  if (tri.edge[k] == EdgeKind::concave || tri.edge[(k + 2) % 3u] == EdgeKind::concave)
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
  // In front of the triangle's plane by more than the margin: every depth below would be less
  // than -margin (the distance to the triangle is at least the height over its plane).
  if (-tri.normal.dot(tri.corner[0]) - r > margin)
    return 0;
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
  // Wholly in front of the plane by more than the margin: every depth below would be less than
  // -margin (a core point's distance to the triangle is at least its height over the plane).
  if (std::min(height[0], height[1]) - r > margin)
    return 0;
  const Real scale = r + capsule.half_length + triangle_size(tri);

  // Closest points between the core segment and the triangle: the ends against the face, the
  // segment against each edge; the first minimum wins, so the choice is deterministic.
  Real best = std::numeric_limits<Real>::infinity();
  Vec3 on_segment = end[0];
  Vec3 on_triangle = tri.corner[0];
  Real segment_t = 0;
  TriangleRegion region = TriangleRegion::face;
  for (int i = 0; i < 2; ++i) {
    TriangleRegion rg = TriangleRegion::face;
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
  const bool centre_behind = tri.normal.dot(tri.corner[0]) > 0;
  if (!pierces && distance > Real(1e-12) * scale && region != TriangleRegion::face) {
    const RegionUse use = region_use(tri, region);
    if (use == RegionUse::drop)
      return 0;
    if (use == RegionUse::keep) {
      const Vec3 normal = (on_segment - on_triangle) / distance;
      if (normal.dot(n) < 0 && centre_behind)
        return 0;  // behind the triangle
      contact.normal = normal;
      contact.add(on_segment - normal * r, r - distance, feature::capsule_feature_at(segment_t),
                  region, margin);
      return contact.count;
    }
  }
  if (pierces || distance <= Real(1e-12) * scale) {
    // The core touches the triangle: the minimum translation is along a face normal of the
    // Minkowski sum of segment and triangle (the triangle's normal, front side only, or the
    // cross product of the core with an edge), chosen by least penetration with the face
    // preferred; edges that are not real features (internal edges) are not candidates.
    const Vec3 core = end[1] - end[0];
    Vec3 best_axis = n;
    Real best_separation = std::min(height[0], height[1]) - r;
    int best_edge = -1;
    for (int k = 0; k < 3; ++k) {
      if (region_use(tri, edge_region(k)) != RegionUse::keep)
        continue;
      const Vec3 edge = tri.corner[(k + 1) % 3] - tri.corner[k];
      Vec3 l = core.cross(edge);
      const Real length = l.norm();
      if (length <= Real(1e-6) * core.norm() * edge.norm())
        continue;
      l /= length;
      const Real lo = std::min({l.dot(tri.corner[0]), l.dot(tri.corner[1]), l.dot(tri.corner[2])});
      const Real hi = std::max({l.dot(tri.corner[0]), l.dot(tri.corner[1]), l.dot(tri.corner[2])});
      // l is across the core, which runs through the origin: the capsule spans [-r, r] on it.
      const Real positive = -r - hi;
      const Real negative = lo - r;
      const Real s = std::max(positive, negative);
      if (clearly_more_separated(s, best_separation, scale)) {
        best_separation = s;
        best_axis = positive >= negative ? l : Vec3(-l);
        best_edge = k;
      }
    }
    if (best_edge >= 0) {
      contact.normal = best_axis;
      contact.add(on_segment - best_axis * r, -best_separation, feature::kCapsuleSide,
                  edge_region(best_edge), margin);
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
  // A core that pierces the face, with the face the least separated axis: the segment and the
  // triangle are polytopes, the face's overlap (the lower end's depth) is the minimum
  // translation, and the lower end must be reported even where it lies beyond the face's edges,
  // or the contact is shallower than the overlap and pushing out by it leaves the capsule
  // through the triangle (a capsule 0.3 m deep got 0.27).
  const int lower = height[0] < height[1] ? 0 : 1;
  if (pierces && !projects_inside(end[lower], tri))
    contact.add(end[lower] - n * r, r - height[lower], feature::kCapsuleSide, TriangleRegion::face,
                margin);
  if (contact.count == 0) {
    // The deepest point of the segment over the face.
    contact.add(on_segment - n * r, r - n.dot(on_segment - tri.corner[0]), feature::kCapsuleSide,
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

  // Apart and on the face path: the box's closest point, which the clipped face must reach.
  bool apart_on_face = false;
  Vec3 closest_on_box = Vec3::Zero();
  std::uint16_t closest_feature = 0;
  if (best.separation > 0) {
    // Apart: the separating-axis value is only a lower bound of the distance, so the contact
    // comes from the exact closest features. A face-region contact (or one from an internal
    // edge) takes the face path below, whose clipped points then carry the exact distance.
    const ClosestFeatures closest = closest_box_triangle(h, u);
    const Real distance = std::sqrt(closest.distance_squared);
    const RegionUse use = region_use(tri, closest.region);
    if (use == RegionUse::drop)
      return 0;
    if (closest.region == TriangleRegion::face || use == RegionUse::use_face || !(distance > 0)) {
      best = {n, -box_radius(n) - n.dot(u[0]), 0, -1, -1};
      apart_on_face = closest.region == TriangleRegion::face;
      closest_on_box = closest.on_box;
      closest_feature = closest.box_feature;
    } else {
      const Vec3 normal = (closest.on_box - closest.on_triangle) / distance;
      if (normal.dot(n) < 0 && n.dot(u[0]) > 0)
        return 0;  // the box's centre is behind the triangle
      contact.normal = normal;
      contact.add(closest.on_box, -distance, closest.box_feature, closest.region, margin);
      return contact.count;
    }
  } else if (best.kind != 0) {
    // The triangle's feature nearest the box along the axis decides whether an axis other than
    // the face normal may be used (internal edges).
    const Vec3& l = best.direction;
    if (l.dot(n) < 0 && n.dot(u[0]) > 0)
      return 0;  // the box's centre is behind the triangle and the axis points further back
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
    Real deepest = -std::numeric_limits<Real>::infinity();
    for (int i = 0; i < polygon.count; ++i) {
      const PolygonVertex& v = polygon.v[i];
      if (contact.count == TriangleContact::kMaxPoints - 1)
        break;
      const Real depth = -n.dot(v.p - u[0]);
      deepest = std::max(deepest, depth);
      contact.add(v.p, depth, v.convex_feature, v.region, margin);
    }
    // Penetrating, the clipped face may miss the box's deepest corner (it hangs outside the
    // triangle's prism while the triangle cuts the box): add it, so the manifold's depth is the
    // separating-axis depth and pushing the box out by it separates the shapes.
    if (apart_on_face && deepest < -n.dot(closest_on_box - u[0]) - Real(1e-9) * scale) {
      // Apart: the closest corner of the box lies over the triangle but off the incident face.
      contact.add(closest_on_box, -n.dot(closest_on_box - u[0]), closest_feature,
                  TriangleRegion::face, margin);
    } else if (best.separation <= 0 && deepest < -best.separation - Real(1e-9) * scale) {
      int bits = 0;
      Vec3 p;
      for (int m = 0; m < 3; ++m) {
        const bool positive = n[m] < 0;
        bits |= positive ? 1 << m : 0;
        p[m] = positive ? h[m] : -h[m];
      }
      contact.add(p, -n.dot(p - u[0]), feature::box_vertex(bits), TriangleRegion::face, margin);
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
    Real deepest = -std::numeric_limits<Real>::infinity();
    for (int i = 0; i < polygon.count; ++i) {
      const PolygonVertex& v = polygon.v[i];
      if (contact.count == TriangleContact::kMaxPoints - 1)
        break;
      const Real depth = h[k] + sigma * v.p[k];
      deepest = std::max(deepest, depth);
      contact.add(v.p - best.direction * depth, depth, v.convex_feature, v.region, margin);
    }
    // As above: the triangle's deepest corner, when clipping lost it.
    if (deepest < -best.separation - Real(1e-9) * scale) {
      int c = 0;
      for (int m = 1; m < 3; ++m)
        if (sigma * u[m][k] > sigma * u[c][k])
          c = m;
      // Its foot on the reference face, kept on the face (the corner may lie beside the box).
      const Real depth = h[k] + sigma * u[c][k];
      const Vec3 foot = (u[c] - best.direction * depth).cwiseMax(-h).cwiseMin(h);
      contact.add(foot, depth, face, corner_region(c), margin);
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
  // The triangle's support along l: edge j when both its ends are extreme, else the corner
  // that is (the axis came from edge j's direction, but the third corner may reach further).
  const std::array<Real, 3> along{l.dot(u[0]), l.dot(u[1]), l.dot(u[2])};
  const Real top = std::max({along[0], along[1], along[2]});
  const Real tolerance = Real(1e-9) * scale;
  if (along[j] >= top - tolerance && along[(j + 1) % 3] >= top - tolerance) {
    Real s = 0;
    Real t = 0;
    closest_parameters_between_segments(e0, e1, u[j], u[(j + 1) % 3], s, t);
    const Vec3 on_box = e0 + (e1 - e0) * s;
    const Vec3 on_triangle = u[j] + (u[(j + 1) % 3] - u[j]) * t;
    contact.add(on_box, -l.dot(on_box - on_triangle), feature::box_edge(i, bits), edge_region(j),
                margin);
    return contact.count;
  }
  int c = 0;
  for (int m = 1; m < 3; ++m)
    if (along[m] > along[c])
      c = m;
  // The corner's closest point on the box edge, moved onto the plane through that edge.
  const Real s = closest_parameter_on_segment(u[c], e0, e1);
  const Vec3 on_box = e0 + (e1 - e0) * s;
  contact.add(on_box, -l.dot(on_box - u[c]), feature::box_edge(i, bits), corner_region(c), margin);
  return contact.count;
}

}  // namespace tumble::detail
