#include "collision/shapes/shape.hpp"

#include <cmath>
#include <numbers>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/triangle_mesh.hpp"

namespace tumble {

std::string_view shape_type_name(ShapeType type) {
  switch (type) {
    case ShapeType::sphere:
      return "sphere";
    case ShapeType::box:
      return "box";
    case ShapeType::capsule:
      return "capsule";
    case ShapeType::plane:
      return "plane";
    case ShapeType::cylinder:
      return "cylinder";
    case ShapeType::hull:
      return "hull";
    case ShapeType::mesh:
      return "mesh";
    case ShapeType::compound:
      return "compound";
  }
  return "unknown";
}

Shape Shape::sphere(Real radius) {
  Shape s;
  s.type = ShapeType::sphere;
  s.radius = radius;
  return s;
}

Shape Shape::box(const Vec3& half_extents) {
  Shape s;
  s.type = ShapeType::box;
  s.half_extents = half_extents;
  return s;
}

Shape Shape::capsule(Real radius, Real half_length) {
  Shape s;
  s.type = ShapeType::capsule;
  s.radius = radius;
  s.half_length = half_length;
  return s;
}

Shape Shape::plane() {
  Shape s;
  s.type = ShapeType::plane;
  return s;
}

Shape Shape::cylinder(Real radius, Real half_length) {
  Shape s;
  s.type = ShapeType::cylinder;
  s.radius = radius;
  s.half_length = half_length;
  return s;
}

Shape Shape::convex_hull(std::shared_ptr<const ConvexHull> hull) {
  Shape s;
  s.type = ShapeType::hull;
  s.hull = std::move(hull);
  return s;
}

Shape Shape::triangle_mesh(std::shared_ptr<const TriangleMesh> mesh) {
  Shape s;
  s.type = ShapeType::mesh;
  s.mesh = std::move(mesh);
  return s;
}

Shape Shape::compound_of(std::shared_ptr<const CompoundShape> compound) {
  Shape s;
  s.type = ShapeType::compound;
  s.compound = std::move(compound);
  return s;
}

namespace {

// Unit vector along `d`, or +z for a zero direction, so support maps never divide by zero.
Vec3 unit_or_z(const Vec3& d) {
  const Real n = d.norm();
  return n > 0 ? Vec3(d / n) : Vec3::UnitZ();
}

Real sign_or_plus(Real x) {
  return x < 0 ? Real(-1) : Real(1);
}

}  // namespace

Vec3 support(const Shape& shape, const Vec3& d) {
  switch (shape.type) {
    case ShapeType::sphere:
      return unit_or_z(d) * shape.radius;
    case ShapeType::box:
      return {sign_or_plus(d.x()) * shape.half_extents.x(),
              sign_or_plus(d.y()) * shape.half_extents.y(),
              sign_or_plus(d.z()) * shape.half_extents.z()};
    case ShapeType::capsule:
      return Vec3(0, 0, sign_or_plus(d.z()) * shape.half_length) + unit_or_z(d) * shape.radius;
    case ShapeType::cylinder: {
      // The rim point in the direction's projection on the cap plane; a direction along the
      // axis has a whole cap as support, and the cap's centre is returned.
      const Real radial = std::sqrt(d.x() * d.x() + d.y() * d.y());
      const Real z = sign_or_plus(d.z()) * shape.half_length;
      if (radial > 0)
        return {d.x() / radial * shape.radius, d.y() / radial * shape.radius, z};
      return {0, 0, z};
    }
    case ShapeType::hull:
      return shape.hull->vertex(shape.hull->support_index(d));
    case ShapeType::mesh:
      return shape.mesh->support(d);
    case ShapeType::compound:
      return shape.compound->support(d);
    case ShapeType::plane:
      break;
  }
  return Vec3::Zero();
}

Aabb world_aabb(const Shape& shape, const Transform& pose) {
  const Vec3& c = pose.translation;
  switch (shape.type) {
    case ShapeType::sphere: {
      const Vec3 r = Vec3::Constant(shape.radius);
      return {c - r, c + r};
    }
    case ShapeType::box: {
      // Extent along each world axis is |R| * h (Arvo, "Transforming Axis-Aligned Bounding
      // Boxes", Graphics Gems 1990).
      const Mat3 r = pose.rotation.toRotationMatrix().cwiseAbs();
      const Vec3 e = r * shape.half_extents;
      return {c - e, c + e};
    }
    case ShapeType::capsule: {
      const Vec3 axis = pose.rotation * Vec3(0, 0, shape.half_length);
      const Vec3 e = axis.cwiseAbs() + Vec3::Constant(shape.radius);
      return {c - e, c + e};
    }
    case ShapeType::cylinder: {
      // Exact box of a disc pair: a cap disc of radius r with unit normal u extends
      // r sqrt(1 - u_k^2) = r sqrt(u_i^2 + u_j^2) along world axis k. The second form: the first
      // cancels when u is near axis k and then loses up to 1e-8 r (the box came out too small).
      const Vec3 u = pose.rotation * Vec3::UnitZ();
      Vec3 e;
      for (int k = 0; k < 3; ++k) {
        const Real i = u[(k + 1) % 3];
        const Real j = u[(k + 2) % 3];
        e[k] = std::abs(u[k]) * shape.half_length + shape.radius * std::sqrt(i * i + j * j);
      }
      return {c - e, c + e};
    }
    case ShapeType::hull: {
      const Mat3 r = pose.rotation.toRotationMatrix();
      Aabb box;
      for (int k = 0; k < 3; ++k) {
        const Vec3 axis_local = r.row(k).transpose();
        box.max[k] =
            c[k] + shape.hull->vertex(shape.hull->support_index(axis_local)).dot(axis_local);
        box.min[k] =
            c[k] + shape.hull->vertex(shape.hull->support_index(-axis_local)).dot(axis_local);
      }
      return box;
    }
    case ShapeType::plane: {
      const Real inf = std::numeric_limits<Real>::infinity();
      Aabb box{Vec3::Constant(-inf), Vec3::Constant(inf)};
      const Vec3 n = pose.rotation * Vec3::UnitZ();
      for (int k = 0; k < 3; ++k) {
        // Solid below the plane: bounded above along +k when the normal is exactly +k.
        const Vec3 axis = Vec3::Unit(k);
        if (n == axis)
          box.max[k] = c[k];
        if (n == -axis)
          box.min[k] = c[k];
      }
      return box;
    }
    case ShapeType::mesh:
      return shape.mesh->world_aabb(pose);
    case ShapeType::compound:
      return shape.compound->world_aabb(pose);
  }
  return {};
}

Real volume(const Shape& shape) {
  constexpr Real pi = std::numbers::pi_v<Real>;
  const Real r = shape.radius;
  switch (shape.type) {
    case ShapeType::sphere:
      return Real(4) / 3 * pi * r * r * r;
    case ShapeType::box:
      return 8 * shape.half_extents.prod();
    case ShapeType::capsule:
      return pi * r * r * (2 * shape.half_length) + Real(4) / 3 * pi * r * r * r;
    case ShapeType::cylinder:
      return pi * r * r * (2 * shape.half_length);
    case ShapeType::hull:
      return shape.hull->volume();
    case ShapeType::plane:
      return std::numeric_limits<Real>::infinity();
    case ShapeType::mesh:
      return shape.mesh->volume();  // 0 for an open mesh
    case ShapeType::compound:
      return shape.compound->volume();
  }
  return 0;
}

Mat3 unit_inertia(const Shape& shape) {
  const Real r = shape.radius;
  switch (shape.type) {
    case ShapeType::sphere:
      return Mat3::Identity() * (Real(2) / 5 * r * r);
    case ShapeType::box: {
      const Vec3 h2 = shape.half_extents.cwiseProduct(shape.half_extents);
      return Vec3(h2.y() + h2.z(), h2.x() + h2.z(), h2.x() + h2.y()).asDiagonal() * (Real(1) / 3);
    }
    case ShapeType::capsule: {
      // Cylinder of height 2a plus two hemispherical caps. A cap of mass m_h has its centroid
      // 3r/8 from its flat face and a transverse inertia of (83/320) m_h r^2 about it; with the
      // parallel-axis shift the two caps give m_s (2r^2/5 + a^2 + 3ar/4) (m_s both caps).
      const Real a = shape.half_length;
      const Real v_cyl = 2 * a;            // proportional to pi r^2 (2a)
      const Real v_sph = Real(4) / 3 * r;  // proportional to pi r^2 (4r/3)
      const Real m_cyl = v_cyl / (v_cyl + v_sph);
      const Real m_sph = v_sph / (v_cyl + v_sph);
      const Real axial = m_cyl * r * r / 2 + m_sph * Real(2) / 5 * r * r;
      const Real transverse = m_cyl * (r * r / 4 + a * a / 3) +
                              m_sph * (Real(2) / 5 * r * r + a * a + Real(3) / 4 * a * r);
      return Vec3(transverse, transverse, axial).asDiagonal();
    }
    case ShapeType::cylinder: {
      const Real h = 2 * shape.half_length;
      const Real transverse = (3 * r * r + h * h) / 12;
      return Vec3(transverse, transverse, r * r / 2).asDiagonal();
    }
    case ShapeType::hull:
      return shape.hull->unit_inertia();
    case ShapeType::plane:
      return Mat3::Zero();
    case ShapeType::mesh:
      return shape.mesh->unit_inertia();  // about the mesh's centroid; zero when open
    case ShapeType::compound:
      return shape.compound->unit_inertia();
  }
  return Mat3::Zero();
}

Real bounding_radius(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::sphere:
      return shape.radius;
    case ShapeType::box:
      return shape.half_extents.norm();
    case ShapeType::capsule:
      return shape.half_length + shape.radius;
    case ShapeType::cylinder:
      return std::sqrt(shape.half_length * shape.half_length + shape.radius * shape.radius);
    case ShapeType::hull:
      return shape.hull->bounding_radius();
    case ShapeType::plane:
      return std::numeric_limits<Real>::infinity();
    case ShapeType::mesh:
      return shape.mesh->bounding_radius();
    case ShapeType::compound:
      return shape.compound->bounding_radius();
  }
  return 0;
}

}  // namespace tumble
