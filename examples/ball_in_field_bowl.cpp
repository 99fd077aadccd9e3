// A program of docs/api.md: a ball rolling in a bowl that is a signed distance field (a box less
// a sphere, docs/sdf.md), the field built in C++ from its YAML form, and the ball's distance to
// the bowl with its gradient (tumble/distance.hpp).
#include <cmath>
#include <cstdio>

#include <tumble/tumble.hpp>

int main() {
  // The bowl: a 2 m x 2 m x 1 m block with a sphere of radius 0.9 taken out above its middle,
  // so that its inside is the sphere's lower cap, lowest at z = -0.3.
  tumble::Vec3 centre_of_mass;
  const tumble::Shape bowl = tumble::load_shape_text(
      "{type: sdf, sdf: {difference: [{box: {half_extents: [1, 1, 0.5]}},"
      "                               {sphere: {radius: 0.9}, position: [0, 0, 0.6]}]}}",
      "bowl", &centre_of_mass);
  auto scene = std::make_shared<tumble::Scene>();
  // A field is re-centred on its centre of mass: the body stands there, so that the bowl's own
  // frame is the world's.
  scene->bodies.push_back(tumble::static_body("bowl", bowl));
  scene->bodies.back().position = centre_of_mass;
  const tumble::Shape ball_shape = tumble::Shape::sphere(0.1);
  scene->bodies.push_back(tumble::dynamic_body("ball", ball_shape));
  scene->bodies.back().position = {0.4, 0, 0};  // up the bowl's side, a little above it
  tumble::World world(scene);
  const tumble::BodyId ball = world.body("ball");
  const tumble::BodyId bowl_id = world.body("bowl");

  double lowest = 1e9, farthest = 0;
  for (int step = 0; step < 300; ++step) {
    world.step();
    const tumble::Vec3 p = world.body_state(ball).position;
    lowest = std::min(lowest, p.z());
    farthest = std::max(farthest, std::hypot(p.x(), p.y()));
  }
  const tumble::BodyState s = world.body_state(ball);
  const tumble::BodyState b = world.body_state(bowl_id);
  const tumble::ShapeDistance d = tumble::distance_between(ball_shape, {s.position, s.orientation},
                                                           bowl, {b.position, b.orientation});
  std::printf(
      "ball at (%.3f, %.3f, %.3f) m after %.2f s; lowest z %.3f m, at most %.3f m from the "
      "axis; distance to the bowl %.4f m, d/dz %.3f\n",
      s.position.x(), s.position.y(), s.position.z(), world.time(), lowest, farthest, d.distance,
      d.gradient_a[2]);
  // The ball rolls in the cap: never more than a few millimetres below its lowest point
  // (-0.3 + 0.1; the soft contact gives a little at 60 Hz on a curved surface), never out over the
  // rim, touching the bowl, and rising moves it away from the bowl's bottom.
  const bool in_bowl =
      lowest > -0.2 - 0.005 && farthest < 0.6 && std::abs(d.distance) < 3e-3 && d.gradient_a[2] > 0;
  return in_bowl ? 0 : 1;
}
