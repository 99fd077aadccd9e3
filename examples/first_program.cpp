// The first program of docs/api.md: a box dropped on the ground, pushed up for a second.
#include <cstdio>

#include <tumble/tumble.hpp>

int main() {
  auto scene = std::make_shared<tumble::Scene>();
  scene->bodies.push_back(tumble::static_body("ground", tumble::Shape::box({5, 5, 0.5})));
  scene->bodies.push_back(tumble::dynamic_body("box", tumble::Shape::box({0.5, 0.5, 0.5})));
  scene->bodies.back().position = {0, 0, 2};
  tumble::World world(scene);
  const tumble::BodyId box = world.body("box");
  for (int step = 0; step < 120; ++step) {
    if (step < 60)
      world.add_force(box, {0, 0, 0.5 * 9.81 * 1000});  // half the box's weight
    world.step();
  }
  const tumble::BodyState s = world.body_state(box);
  std::printf("box at z = %.3f m after %.2f s, %zu contact(s)\n", s.position.z(), world.time(),
              world.contact_reports().size());
  return s.position.z() > 0.9 && s.position.z() < 1.1 ? 0 : 1;
}
