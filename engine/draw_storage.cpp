#include "engine/draw_storage.hpp"

#include <utility>

#include "engine/checked_draw.hpp"

namespace tumble {

std::shared_ptr<const Model> DrawStorage::draw(const std::shared_ptr<const Scene>& checked,
                                               std::uint64_t seed) {
  Pair& pair = pairs_[std::size_t(next_)];
  // use_count() is exact here: another holder would be the world this storage's owner resets on
  // this thread, or a user's copy made before this call.
  if (pair.model && pair.model.use_count() == 1)
    pair.model->release_scenes();
  else
    pair.model = std::make_shared<Model>();
  if (!pair.scene || pair.scene.use_count() != 1) {
    pair.scene = std::make_shared<Scene>();
    pair.source.reset();
  }
  randomized_from_checked_into(*checked, seed, *pair.scene, pair.source == checked);
  pair.source = checked;
  pair.model->assign(pair.scene, checked);
  next_ = 1 - next_;
  return pair.model;
}

}  // namespace tumble
