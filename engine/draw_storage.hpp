// Storage for a world's randomized draws (docs/rl.md, "Seeds"). Each reset of a randomized world
// draws a new scene and compiles its model; building both afresh costs a scene copy, a dozen
// allocations and as many frees, a fifth of the reset in a large batch. A world's draws have the
// same shape every time, so two scene-and-model pairs suffice: the one the world runs, and a spare
// that the next draw is written over, each vector and string keeping its storage, and only the
// drawn fields written when the pair last held a draw of the same scene.
//
// A pair is written over only when this storage alone holds it: a model or scene still held
// elsewhere (a user who kept a world's model) is left alone, and the draw takes new storage.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "engine/model.hpp"
#include "tumble/scene.hpp"

namespace tumble {

class DrawStorage {
 public:
  // The model of randomized(*checked, seed), for a scene that passed check_scene. Throws as
  // randomized() does if the draw fails its check; the model returned before stays as it was.
  std::shared_ptr<const Model> draw(const std::shared_ptr<const Scene>& checked,
                                    std::uint64_t seed);

 private:
  struct Pair {
    std::shared_ptr<Scene> scene;
    std::shared_ptr<Model> model;
    // The scene `scene` holds a draw of (passed or failed), or null: a redraw of the same scene
    // writes only the drawn fields.
    std::shared_ptr<const Scene> source;
  };
  std::array<Pair, 2> pairs_;
  int next_ = 0;  // the pair the next draw is written into
};

}  // namespace tumble
