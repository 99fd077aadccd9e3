// A kinematic paddle sweeps boxes along the ground into a goal region (x > 4 m). The paddle is
// moved by targets, one per step; the boxes only feel it through contacts. Exits 0 when every
// box ends in the goal.
#include <cstdio>

#include <tumble/tumble.hpp>

int main() {
  using tumble::Vec3;
  auto scene = std::make_shared<tumble::Scene>();
  scene->bodies.push_back(tumble::static_body("ground", tumble::Shape::box({10, 10, 0.5})));
  tumble::BodyDesc paddle = tumble::kinematic_body("paddle", tumble::Shape::box({0.1, 2, 0.3}));
  paddle.position = {-3, 0, 0.85};
  scene->bodies.push_back(paddle);
  for (int k = 0; k < 3; ++k) {
    tumble::BodyDesc box =
        tumble::dynamic_body("box" + std::to_string(k), tumble::Shape::box({0.25, 0.25, 0.25}));
    box.position = {-1.5 + 0.6 * k, -1.0 + 1.0 * k, 0.75};
    scene->bodies.push_back(box);
  }
  tumble::World world(scene);
  const tumble::BodyId p = world.body("paddle");
  const double speed = 1.5;  // m/s
  const double dt = scene->world.dt;
  for (int step = 0; step < 360; ++step) {
    const Vec3 at = world.body_state(p).position;
    if (at.x() < 4.2)
      world.set_kinematic_target(p, at + Vec3(speed * dt, 0, 0), tumble::Quat::Identity());
    else
      world.set_velocity(p, Vec3::Zero(), Vec3::Zero());  // stop at the goal line
    world.step();
  }
  int in_goal = 0;
  for (int k = 0; k < 3; ++k) {
    const Vec3 x = world.body_state(world.body("box" + std::to_string(k))).position;
    std::printf("box%d at (%.2f, %.2f, %.2f)\n", k, x.x(), x.y(), x.z());
    in_goal += x.x() > 4.0 ? 1 : 0;
  }
  std::printf("%d of 3 boxes in the goal\n", in_goal);
  return in_goal == 3 ? 0 : 1;
}
