// No tunneling, at any speed (docs/ccd.md, "No tunneling"):
//   - a sphere of 1 cm diameter at 1000 m/s toward a static wall 1 cm thick, over 1000 random
//     directions and offsets (the crossing falls anywhere inside a step): its centre never
//     reaches the wall's far half;
//   - a thin rod (1 m long, 1 cm thick) spinning at up to 300 rad/s beside a static plate 1 cm
//     thick: no corner of the rod ever gets past the plate;
//   - the same for a 1 cm cylinder, a 1 cm hull and a 1 cm compound (two boxes) at 1000 m/s,
//     in random orientations spinning at up to 50 rad/s: its centre never crosses the wall;
//   - the shipped high-speed scene (scenes/high_speed.yaml): no body leaves the closed box.
// Each also runs with `ccd: off` and prints how many bodies tunnel then, to show the cases are
// hard ones; only the swept runs are asserted.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <utility>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "engine/simulation.hpp"
#include "tests/physics/body_builders.hpp"
#include "tests/physics/scene_fixture.hpp"
#include "tests/property_scale.hpp"

namespace tumble::test {
namespace {

BodyDesc fast_body(const Shape& shape, const Vec3& position, const Vec3& velocity) {
  return dynamic_body("mover", shape, position, velocity, 0.01);
}

BodyDesc static_box(const std::string& name, const Vec3& half, const Vec3& position) {
  return static_body(name, Shape::box(half), position);
}

Scene empty_scene(CcdMode ccd) {
  Scene s;
  s.source = "ccd_tunneling_test";
  s.world.gravity = Vec3::Zero();
  s.world.ccd = ccd;
  s.materials.push_back(Material{"default", 0.5, 0.0});
  return s;
}

Vec3 unit_towards_plus_x(std::mt19937_64& rng) {
  std::normal_distribution<Real> n(0, 1);
  for (;;) {
    Vec3 v(n(rng), n(rng), n(rng));
    v.normalize();
    if (v.x() > 0.3)
      return v;
  }
}

// The wall is the box |x| <= 5 mm, |y|, |z| <= 2 m. The bullet starts on the -x side aimed so
// that its straight path crosses x = 0 within 1.5 m of the wall's centre.
int bullets_through_wall(CcdMode ccd, int cases, std::uint64_t seed,
                         const Shape& bullet = Shape::sphere(0.005),
                         const Shape& wall = Shape::box(Vec3(0.005, 2, 2))) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<Real> unit(0, 1);
  int escaped = 0;
  for (int i = 0; i < cases; ++i) {
    const Vec3 dir = unit_towards_plus_x(rng);
    const Real distance = 0.05 + 30 * unit(rng);  // metres of flight to the wall plane
    const Vec3 hit(0, 3 * unit(rng) - 1.5, 3 * unit(rng) - 1.5);
    const Vec3 start = hit - dir * (distance / dir.x());
    Scene s = empty_scene(ccd);
    BodyDesc mover = fast_body(bullet, start, 1000 * dir);
    if (bullet.type != ShapeType::sphere) {
      // Any orientation, tumbling (a field ball too: its field turns with it).
      std::normal_distribution<Real> n(0, 1);
      mover.orientation = Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
      mover.angular_velocity = Vec3(n(rng), n(rng), n(rng)).normalized() * (50 * unit(rng));
    }
    s.bodies.push_back(mover);
    s.bodies.push_back(static_body("wall", wall, Vec3::Zero()));
    Simulation world(std::make_shared<const Scene>(std::move(s)));
    const int steps =
        3 + static_cast<int>(std::ceil(distance / dir.x() / 1000 / world.scene().world.dt));
    // Through: the centre's path in a step (a straight segment between the step's ends)
    // crosses the wall's mid-plane inside the wall. A bullet deflected around the wall's edge
    // reaches x > 0 legitimately.
    bool through = false;
    for (int k = 0; k < steps && !through; ++k) {
      const Vec3 before = world.state().bodies[0].position;
      world.step();
      const Vec3 after = world.state().bodies[0].position;
      if (before.x() <= 0 && after.x() > 0) {
        const Vec3 crossing = before + (after - before) * (-before.x() / (after.x() - before.x()));
        through = std::abs(crossing.y()) <= 2 && std::abs(crossing.z()) <= 2;
      }
    }
    escaped += through ? 1 : 0;
    if (through && ccd != CcdMode::off)
      ADD_FAILURE() << "bullet " << i << " passed the wall";
  }
  return escaped;
}

TEST(NoTunneling, CentimetreSphereAt1000MetresPerSecondNeverCrossesACentimetreWall) {
  const int cases = scaled(1000);
  const int swept = bullets_through_wall(CcdMode::automatic, cases, 61);
  const int unswept = bullets_through_wall(CcdMode::off, std::min(cases, 200), 61);
  std::printf("sphere at 1000 m/s vs 1 cm wall: %d of %d through with ccd, %d of %d without\n",
              swept, cases, unswept, std::min(cases, 200));
  EXPECT_EQ(swept, 0);
}

// A sphere's spin, and a capsule's turn about its own axis, move no part of the space the body
// fills: a 1 cm ball spinning at 1000 rad/s (its surface moves 8 cm a step, 33 times the sweep
// threshold) while it drifts at 0.1 m/s is never swept, nor is a capsule spinning so about its
// axis, while the capsule turning end over end at that rate is, and the ball flying at 1000 m/s
// with the same spin is swept and stops at the wall.
TEST(NoTunneling, ASpinThatMovesNoPartOfTheBodysSpaceIsNotSwept) {
  const auto run = [](const Shape& shape, const Vec3& velocity, const Vec3& spin, int steps) {
    Scene s = empty_scene(CcdMode::automatic);
    BodyDesc body = fast_body(shape, Vec3(-0.5, 0, 0), velocity);
    body.angular_velocity = spin;
    s.bodies.push_back(body);
    s.bodies.push_back(static_box("wall", Vec3(0.005, 2, 2), Vec3::Zero()));
    Simulation world(std::make_shared<const Scene>(std::move(s)));
    std::int64_t swept = 0;
    for (int k = 0; k < steps; ++k) {
      world.step();
      swept += world.last_step_statistics().swept_bodies;
    }
    return std::pair{swept, world.state().bodies[0].position.x()};
  };
  const Shape ball = Shape::sphere(0.005);
  const Shape capsule = Shape::capsule(0.005, 0.01);
  const Vec3 drift(0.1, 0, 0);
  const auto [ball_swept, ball_x] = run(ball, drift, Vec3(0, 1000, 0), 60);
  EXPECT_EQ(ball_swept, 0);
  EXPECT_GT(ball_x, -0.5);  // it moved
  EXPECT_EQ(run(capsule, drift, Vec3(0, 0, 1000), 60).first, 0);
  EXPECT_GT(run(capsule, drift, Vec3(0, 1000, 0), 1).first, 0);
  const auto [flying_swept, flying_x] = run(ball, Vec3(1000, 0, 0), Vec3(0, 1000, 0), 3);
  EXPECT_GT(flying_swept, 0);
  EXPECT_LT(flying_x, 0);  // stopped on the near side of the wall's mid-plane
}

// Signed distance fields are swept like any other shape (their distance to the other shape by
// the narrow phase, collision/ccd/shape_distance.cpp): a field ball of 1 cm at 1000 m/s,
// tumbling, into the 1 cm wall, a 1 cm ball into a wall that is itself a field (an analytic box),
// and a field ball into the field wall. A field's manifold normal is no separating axis, so
// conservative advancement bounds the approach by the whole relative speed (with the normal's
// speed, the field ball went through in 126 of 300 tries); an oblique approach then takes many
// small advances, which is why there are fewer cases here than for the other shapes.
TEST(NoTunneling, FieldBulletsAndAFieldWallAt1000MetresPerSecond) {
  // Two flights each under the sanitizers, where the field's samples cost 30 times more (the
  // sanitizer run checks the memory of the path, the release run the count).
  const int cases = property_scale() < 1 ? 2 : 40;
  const Shape field_ball = sdf_shape(SdfNode::sphere(0.005));
  const Shape box_wall = Shape::box(Vec3(0.005, 2, 2));
  const Shape field_wall = sdf_shape(SdfNode::box(Vec3(0.005, 2, 2)));
  const std::pair<const char*, std::pair<Shape, Shape>> runs[] = {
      {"field ball vs box wall", {field_ball, box_wall}},
      {"ball vs field wall", {Shape::sphere(0.005), field_wall}},
      {"field ball vs field wall", {field_ball, field_wall}}};
  for (const auto& [name, shapes] : runs) {
    const int swept =
        bullets_through_wall(CcdMode::automatic, cases, 67, shapes.first, shapes.second);
    const int unswept = bullets_through_wall(CcdMode::off, cases, 67, shapes.first, shapes.second);
    std::printf("%s at 1000 m/s: %d of %d through with ccd, %d without\n", name, swept, cases,
                unswept);
    EXPECT_EQ(swept, 0) << name;
  }
}

// Centimetre bullets of the shapes swept by GJK-based conservative advancement: a cylinder, a
// hull (an irregular octahedron) and a compound of two boxes (a dumbbell).
Shape centimetre_bullet(ShapeType type) {
  if (type == ShapeType::cylinder)
    return Shape::cylinder(0.005, 0.005);
  if (type == ShapeType::hull) {
    const std::vector<Vec3> points = {{0.006, 0, 0},      {-0.005, 0.001, 0}, {0, 0.005, 0},
                                      {0.001, -0.006, 0}, {0, 0, 0.005},      {0.001, 0, -0.006}};
    return Shape::convex_hull(std::make_shared<const ConvexHull>(ConvexHull::from_points(points)));
  }
  const Shape box = Shape::box(Vec3(0.003, 0.003, 0.003));
  return Shape::compound_of(std::make_shared<const CompoundShape>(
      CompoundShape::build({{box, {Vec3(0.004, 0, 0), Quat::Identity()}},
                            {box, {Vec3(-0.004, 0, 0), Quat::Identity()}}})));
}

TEST(NoTunneling, CentimetreCylinderHullAndCompoundAt1000MetresPerSecondNeverCrossAWall) {
  const int cases = scaled(300);
  for (const ShapeType type : {ShapeType::cylinder, ShapeType::hull, ShapeType::compound}) {
    const Shape bullet = centimetre_bullet(type);
    const int swept = bullets_through_wall(CcdMode::automatic, cases, 63, bullet);
    const int unswept = bullets_through_wall(CcdMode::off, std::min(cases, 100), 63, bullet);
    std::printf("%s at 1000 m/s vs 1 cm wall: %d of %d through with ccd, %d of %d without\n",
                std::string(shape_type_name(type)).c_str(), swept, cases, unswept,
                std::min(cases, 100));
    EXPECT_EQ(swept, 0) << shape_type_name(type);
  }
}

// The rod (box 1 m x 1 cm x 1 cm) turns about an axis near z with its centre at rest; the plate
// x = c +- 5 mm lies within its reach (c < 0.5 m).
int rods_through_plate(CcdMode ccd, int cases, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<Real> unit(0, 1);
  int escaped = 0;
  const Vec3 half(0.5, 0.005, 0.005);
  for (int i = 0; i < cases; ++i) {
    const Real plate_x = 0.1 + 0.35 * unit(rng);
    // Start clear of the plate: the rod lies near the y axis, its ends at most plate_x - 2 cm
    // along x, and turns about (nearly) z into the plate.
    const Real max_tilt = std::asin((plate_x - 0.02) / 0.5);
    const Real tilt = max_tilt * (2 * unit(rng) - 1);
    const Quat q(Eigen::AngleAxis<Real>(M_PI / 2 + tilt, Vec3::UnitZ()));
    const Vec3 spin = Vec3(0.2 * (unit(rng) - 0.5), 0, 1).normalized() * (50 + 250 * unit(rng));
    Scene s = empty_scene(ccd);
    BodyDesc rod = fast_body(Shape::box(half), Vec3(0, 0, 0), Vec3::Zero());
    rod.orientation = q;
    rod.angular_velocity = spin;
    s.bodies.push_back(rod);
    s.bodies.push_back(static_box("plate", Vec3(0.005, 2, 2), Vec3(plate_x, 0, 0)));
    Simulation world(std::make_shared<const Scene>(std::move(s)));
    bool through = false;
    for (int k = 0; k < 30 && !through; ++k) {
      world.step();
      const BodyState& b = world.state().bodies[0];
      for (int c = 0; c < 8; ++c) {
        const Vec3 corner((c & 1 ? 1 : -1) * half.x(), (c & 2 ? 1 : -1) * half.y(),
                          (c & 4 ? 1 : -1) * half.z());
        if ((b.orientation * corner + b.position).x() > plate_x + 0.005)
          through = true;
      }
    }
    escaped += through ? 1 : 0;
    if (through && ccd != CcdMode::off)
      ADD_FAILURE() << "rod " << i << " passed the plate";
  }
  return escaped;
}

TEST(NoTunneling, FastSpinningThinRodNeverCrossesAThinPlate) {
  const int cases = scaled(1000);
  const int swept = rods_through_plate(CcdMode::automatic, cases, 62);
  const int unswept = rods_through_plate(CcdMode::off, std::min(cases, 200), 62);
  std::printf(
      "rod spinning up to 300 rad/s vs 1 cm plate: %d of %d through with ccd, %d of %d "
      "without\n",
      swept, cases, unswept, std::min(cases, 200));
  EXPECT_EQ(swept, 0);
}

}  // namespace
}  // namespace tumble::test
