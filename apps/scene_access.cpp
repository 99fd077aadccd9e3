#include "apps/scene_access.hpp"

namespace tumble::app {

SceneLoadOptions& scene_load_options() {
  static SceneLoadOptions options;
  return options;
}

}  // namespace tumble::app
