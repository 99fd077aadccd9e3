// fit_shape (include/tumble/shape.hpp): a box, sphere, capsule or convex hull around a detailed
// shape, for training geometry. The detailed shape is reduced to balls (centre, radius) whose
// convex hull is the shape: a polytope's vertices (radius 0), a sphere (one ball), a capsule (its
// two end balls); a cylinder is approximated by points on its rims. Each fitted shape is convex,
// so containing every ball contains their hull, the shape.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "collision/shapes/triangle_mesh.hpp"
#include "tumble/error.hpp"
#include "tumble/shape.hpp"

namespace tumble {
namespace {

struct Ball {
  Vec3 centre;
  Real radius;
};

constexpr int kRimPoints = 32;

void add_balls(const Shape& s, const Transform& pose, std::vector<Ball>& out) {
  const auto add = [&](const Vec3& local, Real radius) {
    out.push_back({pose.apply(local), radius});
  };
  switch (s.type) {
    case ShapeType::sphere:
      add(Vec3::Zero(), s.radius);
      return;
    case ShapeType::capsule:
      add(Vec3(0, 0, s.half_length), s.radius);
      add(Vec3(0, 0, -s.half_length), s.radius);
      return;
    case ShapeType::box:
      for (int c = 0; c < 8; ++c)
        add(Vec3((c & 1 ? 1 : -1) * s.half_extents.x(), (c & 2 ? 1 : -1) * s.half_extents.y(),
                 (c & 4 ? 1 : -1) * s.half_extents.z()),
            0);
      return;
    case ShapeType::cylinder:
      for (int k = 0; k < kRimPoints; ++k) {
        const Real a = 2 * std::numbers::pi_v<Real> * k / kRimPoints;
        const Vec3 rim(s.radius * std::cos(a), s.radius * std::sin(a), 0);
        add(rim + Vec3(0, 0, s.half_length), 0);
        add(rim - Vec3(0, 0, s.half_length), 0);
      }
      return;
    case ShapeType::hull:
      for (const Vec3& v : s.hull->vertices())
        add(v, 0);
      return;
    case ShapeType::mesh:
      for (const Vec3& v : s.mesh->vertices())
        add(v, 0);
      return;
    case ShapeType::compound:
      for (const CompoundPart& part : s.compound->parts())
        add_balls(part.shape, compose(pose, part.pose), out);
      return;
    case ShapeType::sdf:
      // The surface points, each grown by the half cell the surface may bulge between them.
      for (const Vec3& v : s.sdf->surface_points())
        add(v, s.sdf->cell_size() / 2);
      return;
    case ShapeType::plane:
      break;
  }
  throw Error("fit_shape: a plane is unbounded and has no fitted shape");
}

// Points for a hull: a point ball itself, and 26 points on a round one (the directions of a
// cube's faces, edges and corners), so round parts are approximated from inside.
std::vector<Vec3> hull_points(const std::vector<Ball>& balls) {
  std::vector<Vec3> points;
  for (const Ball& b : balls) {
    if (b.radius == 0) {
      points.push_back(b.centre);
      continue;
    }
    for (int x = -1; x <= 1; ++x)
      for (int y = -1; y <= 1; ++y)
        for (int z = -1; z <= 1; ++z)
          if (x != 0 || y != 0 || z != 0)
            points.push_back(b.centre + b.radius * Vec3(x, y, z).normalized());
  }
  return points;
}

}  // namespace

Shape fit_shape(const Shape& detailed, ShapeFit fit) {
  std::vector<Ball> balls;
  add_balls(detailed, Transform{}, balls);
  Vec3 extent = Vec3::Zero();  // the half extents of the box about the origin
  for (const Ball& b : balls)
    extent = extent.cwiseMax(b.centre.cwiseAbs() + Vec3::Constant(b.radius));
  switch (fit) {
    case ShapeFit::box:
      return Shape::box(extent);
    case ShapeFit::sphere: {
      Real radius = 0;
      for (const Ball& b : balls)
        radius = std::max(radius, b.centre.norm() + b.radius);
      return Shape::sphere(radius);
    }
    case ShapeFit::capsule: {
      int axis = 0;
      extent.maxCoeff(&axis);
      // Radius: the farthest reach from the axis. Half length: the least that holds every ball
      // whose centre lies beyond it, |a| - hl <= sqrt((R - r)^2 - rho^2).
      Real radius = 0;
      for (const Ball& b : balls) {
        Vec3 off = b.centre;
        off[axis] = 0;
        radius = std::max(radius, off.norm() + b.radius);
      }
      Real half_length = 0;
      for (const Ball& b : balls) {
        Vec3 off = b.centre;
        off[axis] = 0;
        const Real reach = std::sqrt(
            std::max(Real(0), (radius - b.radius) * (radius - b.radius) - off.squaredNorm()));
        half_length = std::max(half_length, std::abs(b.centre[axis]) - reach);
      }
      const Shape capsule = Shape::capsule(radius, half_length);
      if (axis == 2)
        return capsule;
      // The capsule's core is along its local z: turn it onto the axis, in a one-part compound
      // (symmetric about the origin, so nothing moves).
      CompoundPart part{capsule, Transform{}};
      part.pose.rotation = Quat::FromTwoVectors(Vec3::UnitZ(), Vec3::Unit(axis));
      return compound_in_frame({part});
    }
    case ShapeFit::hull:
      return hull_in_frame(hull_points(balls));
  }
  throw Error("fit_shape: unknown fit");
}

}  // namespace tumble
