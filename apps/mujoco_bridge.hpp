// The MuJoCo 2.2.2 peer of the batch benchmark (`tumble bench-batch`): a scene of free bodies on
// static ground written as MJCF, and N mjData of it stepped like N tumble worlds. This file and its
// .cpp are the only code that touches MuJoCo; this header does not include it, so without
// TUMBLE_WITH_MUJOCO the same interface exists and mujoco_available() is false.
//
// What is matched: the time step and gravity; boxes, spheres and capsules (MuJoCo's capsule and
// ours both have their core along local z) with the scene's mass and diagonal inertia under a
// free joint; static planes, boxes, spheres and capsules as world geoms; each geom's sliding
// friction the mixed friction of its material with itself (MuJoCo combines a pair by the larger,
// tumble by the geometric mean: equal for a scene of one material). What is MuJoCo's own: its
// soft constraints (default solref and solimp), its Newton solver at default tolerances, its
// Euler integrator, its contacts (box-plane up to 4 points, box-box by its own routine).
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "tumble/scene.hpp"

namespace tumble::app {

// True when this build links MuJoCo (TUMBLE_WITH_MUJOCO).
bool mujoco_available();
// "2.2.2" or "absent".
std::string mujoco_version();

// The scene as MJCF (no MuJoCo needed). Throws std::invalid_argument naming the body for what
// the peer cannot express: hulls, meshes, cylinders, compounds, kinematic bodies, a plane that is
// not static.
std::string mjcf_of(const Scene& scene);

class MujocoBatch {
 public:
  // `worlds` mjData of the scene's model. Throws std::runtime_error without MuJoCo or when
  // MuJoCo refuses the model (its message included).
  MujocoBatch(const Scene& scene, int worlds);
  ~MujocoBatch();
  MujocoBatch(const MujocoBatch&) = delete;
  MujocoBatch& operator=(const MujocoBatch&) = delete;

  int size() const;
  // One mj_step of world w; worlds may be stepped from different threads at once.
  void step(int w);
  void reset(int w);
  // Contacts of world w after its last step.
  int contacts(int w) const;
  // The height of dynamic body i (the scene's dynamic bodies in order) of world w [m].
  Real height(int w, int dynamic_body) const;
  // Bytes of one world's mjData (its buffer and its stack).
  std::size_t bytes_per_world() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tumble::app
