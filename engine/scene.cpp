#include "tumble/scene.hpp"

namespace tumble {

int Scene::find_body(std::string_view name) const {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == name)
      return static_cast<int>(i);
  }
  return -1;
}

int Scene::find_material(std::string_view name) const {
  for (std::size_t i = 0; i < materials.size(); ++i) {
    if (materials[i].name == name)
      return static_cast<int>(i);
  }
  return -1;
}

}  // namespace tumble
