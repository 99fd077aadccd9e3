// randomized() (include/tumble/randomization.hpp): the draws of a scene's `randomize` block
// applied to a copy of the scene. Each quantity has its own stream (engine/random_stream.hpp)
// keyed by the seed, the quantity and the material or body index, so a draw depends on nothing
// but those three.
#include "tumble/randomization.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/shape.hpp"
#include "engine/checked_draw.hpp"
#include "engine/random_stream.hpp"
#include "engine/scene_check.hpp"
#include "tumble/model.hpp"
#include "tumble/scene.hpp"

namespace tumble {
namespace {

// The stream of each quantity (the `kind` of RandomStream). Fixed values: changing one changes
// every world drawn with it.
enum class Draw : std::uint64_t {
  gravity = 1,
  friction = 2,
  restitution = 3,
  mass_scale = 4,
  size = 5,
  position = 6,
  orientation = 7,
  train_size = 8,
};

RandomStream stream(std::uint64_t seed, Draw kind, std::size_t index) {
  return RandomStream(seed, static_cast<std::uint64_t>(kind), index);
}

Vec3 normal3(RandomStream& s) {
  const Real x = s.normal();
  const Real y = s.normal();
  const Real z = s.normal();
  return {x, y, z};
}

// 1 + n, n ~ Normal(0, sigma) cut at 3 sigma; sigma <= 0.2 (engine/scene_check.cpp) keeps the
// factor at 0.4 or more.
Real size_factor(RandomStream& s, Real sigma) {
  return 1 + std::clamp(sigma * s.normal(), -3 * sigma, 3 * sigma);
}

// The shape with each dimension scaled by its own draw. `offset` receives how far a rebuilt
// compound's centre of mass moved in its frame (the body moves by it so the parts stay put);
// a training shape stays in its body's frame (`in_frame`) and moves nothing.
Shape scaled(const Shape& shape, RandomStream& s, Real sigma, Vec3& offset, bool in_frame) {
  Shape out = shape;
  switch (shape.type) {
    case ShapeType::sphere:
      out.radius *= size_factor(s, sigma);
      return out;
    case ShapeType::box:
      for (int k = 0; k < 3; ++k)
        out.half_extents[k] *= size_factor(s, sigma);
      return out;
    case ShapeType::capsule:
    case ShapeType::cylinder:
      out.radius *= size_factor(s, sigma);
      out.half_length *= size_factor(s, sigma);
      return out;
    case ShapeType::hull: {
      // A linear map takes the centroid to the centroid, so the hull stays centred on its
      // centre of mass.
      Vec3 factor;
      for (int k = 0; k < 3; ++k)
        factor[k] = size_factor(s, sigma);
      std::vector<Vec3> points(shape.hull->vertices().begin(), shape.hull->vertices().end());
      for (Vec3& p : points)
        p = p.cwiseProduct(factor);
      return in_frame ? hull_in_frame(points) : hull_from_points(points, &offset);
    }
    case ShapeType::compound: {
      std::vector<CompoundPart> parts = shape.compound->parts();
      for (CompoundPart& part : parts) {
        Vec3 unused = Vec3::Zero();
        part.shape = scaled(part.shape, s, sigma, unused, in_frame);
      }
      return in_frame ? compound_in_frame(std::move(parts))
                      : compound_from_parts(std::move(parts), &offset);
    }
    case ShapeType::plane:
    case ShapeType::mesh:
    case ShapeType::sdf:
      // A field is not rebuilt per draw (its mass properties and surface points take tens of
      // milliseconds): size noise leaves it as it is (docs/scene-format.md).
      return out;
  }
  return out;
}

}  // namespace

Scene randomized(const Scene& scene, std::uint64_t seed) {
  check_scene(scene);
  return randomized_from_checked(scene, seed);
}

Scene randomized_from_checked(const Scene& scene, std::uint64_t seed) {
  Scene out;
  randomized_from_checked_into(scene, seed, out);
  return out;
}

void randomized_from_checked_into(const Scene& scene, std::uint64_t seed, Scene& out,
                                  bool out_drawn_from_checked) {
  const Randomization& r = scene.randomize;
  if (!out_drawn_from_checked) {
    out = scene;
    out.randomize = Randomization{};
  } else {
    // Every field the draws below write, back to the scene's value; the rest of `out` is the
    // scene's already. (A field drawn below must be listed here: DrawStorage's tests,
    // tests/api/draw_storage_test.cpp, compare draws written over earlier ones with fresh ones.)
    out.world.gravity = scene.world.gravity;
    out.materials = scene.materials;
    for (std::size_t i = 0; i < out.bodies.size(); ++i) {
      const BodyDesc& from = scene.bodies[i];
      if (from.is_static)
        continue;
      BodyDesc& b = out.bodies[i];
      b.shape = from.shape;
      b.train_shape = from.train_shape;
      b.mass = from.mass;
      b.inertia = from.inertia;
      b.position = from.position;
      b.orientation = from.orientation;
    }
  }

  if (r.gravity_low && r.gravity_high) {
    RandomStream s = stream(seed, Draw::gravity, 0);
    for (int k = 0; k < 3; ++k)
      out.world.gravity[k] = s.uniform((*r.gravity_low)[k], (*r.gravity_high)[k]);
  }
  if ((r.friction || r.restitution) && out.materials.empty())
    out.materials.push_back(Material{"default"});
  for (std::size_t m = 0; m < out.materials.size(); ++m) {
    if (r.friction) {
      RandomStream s = stream(seed, Draw::friction, m);
      out.materials[m].friction = s.uniform(r.friction->low, r.friction->high);
    }
    if (r.restitution) {
      RandomStream s = stream(seed, Draw::restitution, m);
      out.materials[m].restitution = s.uniform(r.restitution->low, r.restitution->high);
    }
  }

  for (std::size_t i = 0; i < out.bodies.size(); ++i) {
    BodyDesc& b = out.bodies[i];
    if (b.is_static)
      continue;
    const bool dynamic = !b.kinematic;
    if (r.size_noise > 0) {
      RandomStream s = stream(seed, Draw::size, i);
      Vec3 offset = Vec3::Zero();
      Shape shape = scaled(b.shape, s, r.size_noise, offset, false);
      if (b.train_shape) {
        // The training shape draws its own noise (its stream), in its frame.
        RandomStream t = stream(seed, Draw::train_size, i);
        Vec3 unused = Vec3::Zero();
        b.train_shape = scaled(*b.train_shape, t, r.size_noise, unused, true);
      }
      if (dynamic) {
        // Same density; the inertia changes by the difference of the two shapes' uniform-density
        // inertias, which keeps any inertia the scene gave beyond the shape's own.
        const Real density = b.mass / volume(b.shape);
        const Real mass = density * volume(shape);
        b.inertia += mass * unit_inertia(shape) - b.mass * unit_inertia(b.shape);
        b.mass = mass;
      }
      b.position += b.orientation * offset;
      b.shape = std::move(shape);
    }
    if (!dynamic)
      continue;
    if (r.mass_scale) {
      RandomStream s = stream(seed, Draw::mass_scale, i);
      const Real factor = s.uniform(r.mass_scale->low, r.mass_scale->high);
      b.mass *= factor;
      b.inertia *= factor;
    }
    if (r.position_noise > 0) {
      RandomStream s = stream(seed, Draw::position, i);
      b.position += r.position_noise * normal3(s);
    }
    if (r.orientation_noise > 0) {
      RandomStream s = stream(seed, Draw::orientation, i);
      const Vec3 turn = r.orientation_noise * normal3(s);
      const Real angle = turn.norm();
      if (angle > 0)
        b.orientation =
            (Quat(Eigen::AngleAxis<Real>(angle, turn / angle)) * b.orientation).normalized();
    }
  }
  // A draw can still leave the ranges (a position noise at the edge of the world): say so here
  // rather than in the step.
  check_drawn_scene(out);
}

}  // namespace tumble
