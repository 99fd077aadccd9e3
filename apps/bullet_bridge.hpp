// The Bullet oracle bridge: builds a tumble Scene in Bullet 3.24 (the float64 build, so that both
// engines compute in double) and steps it side by side with tumble. This file and its .cpp are
// the only code outside tests/benchmarks and tests/oracle that touches Bullet, and this header
// does not include Bullet: without TUMBLE_WITH_BULLET the same interface exists and
// bullet_available() is false (the constructor then throws a clear error).
//
// What is matched, and how (docs/oracle.md has the full table):
//   shapes     sphere btSphereShape, box btBoxShape, capsule btCapsuleShapeZ (core along z, as
//              ours), plane btStaticPlaneShape((0,0,1), 0) in the body frame, cylinder
//              btCylinderShapeZ((r, r, half_length)), hull btConvexHullShape of its vertices,
//              compound btCompoundShape of the parts, static mesh btBvhTriangleMeshShape.
//   margins    spheres and capsules: the radius is Bullet's margin (no choice). Boxes:
//              setMargin(0), so Bullet's box is exactly ours; box-box goes through Bullet's exact
//              btBoxBoxCollisionAlgorithm and box-plane through the support map, which need no
//              margin; listed as a mismatch because Bullet's GJK for box-capsule prefers one.
//              Cylinders and hulls: setMargin(0) too (both keep their outer size).
//   mass       the scene's mass and the diagonal of its body-frame inertia (a non-diagonal
//              inertia cannot be given to Bullet and is listed).
//   materials  friction by the geometric mean and restitution by the maximum, tumble's rule,
//              through gCalculateCombinedFrictionCallback / ...RestitutionCallback.
//   stepping   `substeps` calls of stepSimulation(dt / substeps, 0): exactly one internal step of
//              dt / substeps each (no accumulator, no interpolation). Bullet collides on every
//              substep, tumble once per step (listed).
//   solver     m_numIterations = iterations + relax_iterations (tumble's passes per substep),
//              m_restitutionVelocityThreshold = restitution_threshold, split impulse on.
//   rotation   BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY (one Newton step of implicit Euler on
//              Euler's equations) against tumble's implicit midpoint rule.
//   sleeping   off in both unless BulletSettings::sleeping: every Bullet body then has
//              DISABLE_DEACTIVATION; with it, Bullet's default deactivation.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "dynamics/rigid_body.hpp"
#include "tumble/scene.hpp"

namespace tumble::app {

// True when this build links Bullet (TUMBLE_WITH_BULLET).
bool bullet_available();

// The Bullet solver variants a sweep can ask for; data, so adding one is one line.
enum class BulletSolver { sequential_impulse, sequential_impulse_no_split };
const char* bullet_solver_name(BulletSolver solver);

struct BulletSettings {
  Real dt = Real(1) / 60;  // s, one step
  int substeps = 1;        // internal Bullet steps per step
  int iterations = 10;     // m_numIterations
  BulletSolver solver = BulletSolver::sequential_impulse;
  Real restitution_threshold = Real(0.2);  // m/s
  // gContactBreakingThreshold: Bullet keeps manifold points whose gap is below this factor
  // times the shape's bounding radius (plus margin). Bullet's default is 0.02. Bullet applies
  // restitution on points that have not touched yet, against the gap, so a bouncing body loses
  // energy on the way in unless the factor is small (docs/oracle.md, "Bounce").
  Real contact_breaking_threshold = Real(0.02);
  // With split impulse, Bullet still folds the position error of penetrations shallower than
  // this (its default -0.04 m) into the velocity, which adds energy to every bounce. A huge value
  // splits every penetration, so position correction never adds kinetic energy (tumble's relax
  // pass does the same). [m]
  Real split_impulse_penetration_threshold = Real(-0.04);
  // Bullet's default deactivation (bodies below 0.8 m/s and 1 rad/s for 2 s sleep) instead of
  // DISABLE_DEACTIVATION on every body.
  bool sleeping = false;
};

// The settings that match the scene's tumble settings as closely as Bullet allows: the scene's
// dt and substeps, iterations + relax_iterations passes, restitution threshold; for scenes with
// restitution also every penetration split and a contact breaking threshold factor of 0.0001
// (the restitution of a body caught by a point before it touches is otherwise lost, and folded
// position error adds energy; docs/oracle.md).
BulletSettings matching_bullet_settings(const Scene& scene);

// Bullet as its own benchmark demos run it: one internal step per step, 10 iterations, split
// impulse. Matching tumble's substeps would make Bullet collide four times per step and so
// flatter tumble; the accuracy each buys is in the reports (docs/reports/).
BulletSettings benchmark_bullet_settings(const Scene& scene);

class BulletWorld {
 public:
  // Throws std::runtime_error when the build has no Bullet.
  BulletWorld(const Scene& scene, const BulletSettings& settings);
  ~BulletWorld();
  BulletWorld(const BulletWorld&) = delete;
  BulletWorld& operator=(const BulletWorld&) = delete;

  // One step of settings.dt.
  void step();

  // Pose and velocities of scene body i (the scene's order), tumble's conventions.
  BodyState body(int i) const;
  Real time() const { return time_; }
  // Totals over the dynamic bodies [J], defined as Simulation's.
  Real kinetic_energy() const;
  Real potential_energy() const;
  // Points in Bullet's persistent manifolds after the last step (those within the contact
  // breaking threshold included).
  int contact_points() const;
  // Every setting that could not be matched, one readable line each.
  const std::vector<std::string>& mismatches() const { return mismatches_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<std::string> mismatches_;
  Real time_ = 0;
  std::int64_t steps_ = 0;
  Real dt_ = 0;
};

}  // namespace tumble::app
