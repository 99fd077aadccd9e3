#include "apps/bullet_bridge.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "collision/shapes/compound_shape.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/shape.hpp"
#include "collision/shapes/triangle_mesh.hpp"

#ifdef TUMBLE_HAVE_BULLET
#include <btBulletDynamicsCommon.h>
#endif

namespace tumble::app {

const char* bullet_solver_name(BulletSolver solver) {
  switch (solver) {
    case BulletSolver::sequential_impulse:
      return "bullet_si";
    case BulletSolver::sequential_impulse_no_split:
      return "bullet_si_nosplit";
  }
  return "bullet_si";
}

BulletSettings benchmark_bullet_settings(const Scene& scene) {
  BulletSettings s;
  s.dt = scene.world.dt;
  s.substeps = 1;
  s.iterations = 10;
  s.restitution_threshold = scene.world.restitution_threshold;
  return s;
}

BulletSettings matching_bullet_settings(const Scene& scene) {
  BulletSettings s;
  s.dt = scene.world.dt;
  s.substeps = std::max(1, scene.world.substeps);
  s.iterations = std::max(1, scene.world.iterations + scene.world.relax_iterations);
  s.restitution_threshold = scene.world.restitution_threshold;
  // Bouncing needs Bullet to apply restitution only once bodies touch, and never to fold
  // position error into velocity (both add or remove energy at every impact); stacks with few
  // iterations need Bullet's default folding to stand. So scenes with restitution get the
  // former, the others Bullet's defaults (docs/oracle.md, "Bounce").
  const bool bouncy = std::any_of(scene.materials.begin(), scene.materials.end(),
                                  [](const Material& m) { return m.restitution > 0; });
  if (bouncy) {
    s.contact_breaking_threshold = Real(0.0001);
    s.split_impulse_penetration_threshold = Real(1e30);
  }
  return s;
}

namespace {

// The settings that cannot match whatever the bridge does; the Bullet side is independent of
// how it was built, so these are listed for every scene.
[[maybe_unused]] void list_fixed_mismatches(const Scene& scene, const BulletSettings& s,
                                            std::vector<std::string>& out) {
  const WorldSettings& w = scene.world;
  out.push_back("position correction: tumble uses soft contacts (contact_hertz " +
                (w.contact_hertz ? std::to_string(*w.contact_hertz) + " Hz"
                                 : std::string("auto: 1/8 of the substep rate, 1/4 on static")) +
                ", damping ratio " + std::to_string(w.contact_damping_ratio) + ", slop " +
                std::to_string(w.penetration_slop) + " m, max push " +
                std::to_string(w.max_push_velocity) +
                " m/s); Bullet uses split impulse with erp2 0.8 and no slop");
  out.push_back("contact margin: tumble creates contacts " + std::to_string(w.contact_margin) +
                " m before touching plus the step's reach (speculative); Bullet keeps manifold "
                "points whose gap is below gContactBreakingThreshold (" +
                std::to_string(s.contact_breaking_threshold) +
                ") times the shape's bounding radius and has no speculative contacts");
  out.push_back("solver passes: tumble runs " + std::to_string(w.iterations) + " soft + " +
                std::to_string(w.relax_iterations) +
                " relax passes per substep; Bullet runs m_numIterations = " +
                std::to_string(s.iterations) + " per internal step");
  if (s.substeps > 1 || w.substeps > 1) {
    out.push_back("collision frequency: tumble collides once per step and solves " +
                  std::to_string(w.substeps) + " substeps; Bullet collides and solves on each of " +
                  std::to_string(s.substeps) + " internal steps");
  }
  out.push_back(
      "rotation: tumble integrates Euler's equations by the implicit midpoint rule and the "
      "orientation by a Cayley rotation; Bullet by one Newton step of implicit Euler "
      "(BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY) and the exponential map");
  out.push_back(
      "box margin: Bullet boxes have setMargin(0) (their size is exact; Bullet's GJK "
      "for box-capsule pairs works without the usual 0.04 m rounding)");
  out.push_back(
      "contact manifolds: tumble reduces to at most 4 points from its own clipping; Bullet keeps "
      "up to 4 persistent points refreshed every step");
  if (w.solver == SolverType::penalty)
    out.push_back("solver: tumble's penalty solver has no Bullet counterpart");
  if (w.ccd == CcdMode::on ||
      std::any_of(scene.bodies.begin(), scene.bodies.end(),
                  [](const BodyDesc& b) { return b.fast && !b.is_static; })) {
    out.push_back("continuous collision: the scene asks for it; Bullet's CCD is left off");
  }
  const Real h = s.dt / s.substeps;
  for (const BodyDesc& b : scene.bodies) {
    // Bullet clamps the rotation of one internal step to a quarter turn.
    if (!b.is_static && b.angular_velocity.norm() * h > Real(0.25) * std::numbers::pi_v<Real>) {
      out.push_back("body '" + b.name +
                    "': spins faster than Bullet's limit of a quarter turn "
                    "per internal step; Bullet clamps it");
    }
    const Mat3& I = b.inertia;
    const Real off = std::abs(I(0, 1)) + std::abs(I(0, 2)) + std::abs(I(1, 2));
    if (!b.is_static && off > Real(1e-12) * I.diagonal().cwiseAbs().maxCoeff()) {
      out.push_back("body '" + b.name +
                    "': inertia is not diagonal in the body frame; Bullet gets its diagonal only");
    }
  }
}

}  // namespace

#ifdef TUMBLE_HAVE_BULLET

bool bullet_available() {
  return true;
}

namespace {

btVector3 bt(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}
Vec3 from_bt(const btVector3& v) {
  return {v.x(), v.y(), v.z()};
}

// tumble's combine rules (engine/world.cpp): friction by the geometric mean, restitution by the
// maximum. Bullet's defaults multiply both.
btScalar combined_friction(const btCollisionObject* a, const btCollisionObject* b) {
  return std::sqrt(a->getFriction() * b->getFriction());
}
btScalar combined_restitution(const btCollisionObject* a, const btCollisionObject* b) {
  return std::max(a->getRestitution(), b->getRestitution());
}

}  // namespace

namespace {

// Owner of the Bullet shapes of one world. Triangle data of mesh shapes is declared before
// `shapes` so that it outlives the btBvhTriangleMeshShapes that point into it; `shapes` holds
// compound children too (btCompoundShape does not own them).
struct BulletShapes {
  std::vector<std::unique_ptr<btTriangleMesh>> triangle_meshes;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
};

}  // namespace

struct BulletWorld::Impl {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broad_phase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broad_phase, &solver, &configuration};
  BulletShapes shapes;  // declared before the bodies, so it outlives them
  std::vector<std::unique_ptr<btRigidBody>> bodies;  // one per scene body, null if left out
  std::vector<BodyMass> masses;
  Vec3 gravity = Vec3::Zero();
  int substeps = 1;
  Real h = 0;

  ~Impl() {
    for (auto& b : bodies) {
      if (b)
        world.removeRigidBody(b.get());
    }
  }
};

namespace {

btTransform bt(const Transform& t) {
  const Quat& q = t.rotation;
  return btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), bt(t.translation));
}

// Bullet's counterpart of a tumble shape in the body frame, owned by `m`; null for a shape type the
// bridge does not know. Convex shapes get margin 0 so that Bullet's shape is exactly ours:
// btBoxShape and btCylinderShape keep their outer size when the margin changes; a btConvexHullShape
// with margin 0 is its points' hull.
btCollisionShape* make_bullet_shape(const Shape& shape, BulletShapes& m) {
  std::unique_ptr<btCollisionShape> out;
  switch (shape.type) {
    case ShapeType::sphere:
      out = std::make_unique<btSphereShape>(shape.radius);
      break;
    case ShapeType::box:
      out = std::make_unique<btBoxShape>(bt(shape.half_extents));
      out->setMargin(0);
      break;
    case ShapeType::capsule:
      out = std::make_unique<btCapsuleShapeZ>(shape.radius, 2 * shape.half_length);
      break;
    case ShapeType::plane:
      out = std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0);
      break;
    case ShapeType::cylinder:
      out = std::make_unique<btCylinderShapeZ>(
          btVector3(shape.radius, shape.radius, shape.half_length));
      out->setMargin(0);
      break;
    case ShapeType::hull: {
      auto hull = std::make_unique<btConvexHullShape>();
      for (const Vec3& v : shape.hull->vertices())
        hull->addPoint(bt(v), false);
      hull->recalcLocalAabb();
      hull->setMargin(0);
      out = std::move(hull);
      break;
    }
    case ShapeType::compound: {
      auto compound = std::make_unique<btCompoundShape>();
      for (const CompoundPart& part : shape.compound->parts()) {
        btCollisionShape* child = make_bullet_shape(part.shape, m);
        if (child == nullptr)
          return nullptr;
        compound->addChildShape(bt(part.pose), child);
      }
      out = std::move(compound);
      break;
    }
    case ShapeType::mesh: {
      auto triangles = std::make_unique<btTriangleMesh>(true, false);  // 32-bit indices
      const TriangleMesh& mesh = *shape.mesh;
      for (int t = 0; t < mesh.triangle_count(); ++t)
        triangles->addTriangle(bt(mesh.corner(t, 0)), bt(mesh.corner(t, 1)), bt(mesh.corner(t, 2)));
      out = std::make_unique<btBvhTriangleMeshShape>(triangles.get(), true);
      m.triangle_meshes.push_back(std::move(triangles));
      break;
    }
    case ShapeType::sdf:
      break;  // Bullet has no signed distance field shape: the body is reported and left out
  }
  if (!out)
    return nullptr;
  m.shapes.push_back(std::move(out));
  return m.shapes.back().get();
}

}  // namespace

BulletWorld::BulletWorld(const Scene& scene, const BulletSettings& settings)
    : impl_(std::make_unique<Impl>()), dt_(settings.dt) {
  gCalculateCombinedFrictionCallback = &combined_friction;
  gCalculateCombinedRestitutionCallback = &combined_restitution;
  // A process-wide Bullet global, read when manifolds are created; every BulletWorld sets it.
  gContactBreakingThreshold = settings.contact_breaking_threshold;
  Impl& m = *impl_;
  m.gravity = scene.world.gravity;
  m.substeps = std::max(1, settings.substeps);
  m.h = settings.dt / m.substeps;
  m.world.setGravity(bt(scene.world.gravity));
  btContactSolverInfo& info = m.world.getSolverInfo();
  info.m_numIterations = settings.iterations;
  info.m_restitutionVelocityThreshold = settings.restitution_threshold;
  info.m_splitImpulse = settings.solver == BulletSolver::sequential_impulse ? 1 : 0;
  info.m_splitImpulsePenetrationThreshold = settings.split_impulse_penetration_threshold;
  list_fixed_mismatches(scene, settings, mismatches_);

  for (const BodyDesc& d : scene.bodies) {
    m.masses.push_back(BodyMass::make(d.mass, d.inertia, d.is_static));
    btCollisionShape* shape = make_bullet_shape(d.shape, m.shapes);
    if (shape == nullptr) {
      // Shapes added to tumble later need a case in make_bullet_shape; until then the body is
      // left out.
      mismatches_.push_back("body '" + d.name + "': shape type '" +
                            std::string(shape_type_name(d.shape.type)) +
                            "' has no Bullet counterpart in the bridge; left out of Bullet");
      m.bodies.push_back(nullptr);
      continue;
    }
    const Real mass = d.is_static ? Real(0) : d.mass;
    const btVector3 inertia = d.is_static
                                  ? btVector3(0, 0, 0)
                                  : btVector3(d.inertia(0, 0), d.inertia(1, 1), d.inertia(2, 2));
    btRigidBody::btRigidBodyConstructionInfo ci(mass, nullptr, shape, inertia);
    const Quat& q = d.orientation;
    ci.m_startWorldTransform =
        btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), bt(d.position));
    const Material& mat = scene.materials[d.material];
    ci.m_friction = mat.friction;
    ci.m_restitution = mat.restitution;
    ci.m_linearDamping = 0;
    ci.m_angularDamping = 0;
    auto body = std::make_unique<btRigidBody>(ci);
    if (!d.is_static) {
      body->setLinearVelocity(bt(d.velocity));
      body->setAngularVelocity(bt(d.angular_velocity));
      body->setFlags(BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY);
    }
    if (!settings.sleeping)
      body->setActivationState(DISABLE_DEACTIVATION);
    m.world.addRigidBody(body.get());
    m.bodies.push_back(std::move(body));
  }
}

BulletWorld::~BulletWorld() = default;

void BulletWorld::step() {
  for (int s = 0; s < impl_->substeps; ++s) {
    // maxSubSteps = 0: exactly one internal step of h, no accumulator, no interpolation.
    impl_->world.stepSimulation(impl_->h, 0);
  }
  steps_ += 1;
  time_ = static_cast<Real>(steps_) * dt_;
}

BodyState BulletWorld::body(int i) const {
  BodyState s;
  const btRigidBody* b = impl_->bodies[i].get();
  if (b == nullptr)
    return s;
  const btTransform& t = b->getWorldTransform();
  s.position = from_bt(t.getOrigin());
  btQuaternion q;
  t.getBasis().getRotation(q);
  s.orientation = Quat(q.w(), q.x(), q.y(), q.z());
  if (s.orientation.w() < 0)
    s.orientation.coeffs() = -s.orientation.coeffs();
  s.velocity = from_bt(b->getLinearVelocity());
  s.angular_velocity = from_bt(b->getAngularVelocity());
  return s;
}

Real BulletWorld::kinetic_energy() const {
  Real e = 0;
  for (std::size_t i = 0; i < impl_->bodies.size(); ++i) {
    if (impl_->bodies[i])
      e += tumble::kinetic_energy(body(static_cast<int>(i)), impl_->masses[i]);
  }
  return e;
}

Real BulletWorld::potential_energy() const {
  Real e = 0;
  for (std::size_t i = 0; i < impl_->bodies.size(); ++i) {
    if (!impl_->bodies[i] || impl_->masses[i].inverse_mass == 0)
      continue;
    e -= impl_->gravity.dot(body(static_cast<int>(i)).position) / impl_->masses[i].inverse_mass;
  }
  return e;
}

int BulletWorld::contact_points() const {
  int n = 0;
  btDispatcher& d = impl_->dispatcher;
  for (int k = 0; k < d.getNumManifolds(); ++k) {
    const btPersistentManifold* pm = d.getManifoldByIndexInternal(k);
    n += pm->getNumContacts();
  }
  return n;
}

#else  // no Bullet in this build

bool bullet_available() {
  return false;
}

struct BulletWorld::Impl {};

BulletWorld::BulletWorld(const Scene&, const BulletSettings&) {
  throw std::runtime_error(
      "this build has no Bullet (configure with -DTUMBLE_WITH_BULLET=ON and the bullet-float64 "
      "package); the Bullet side of compare, report and bench is unavailable");
}
BulletWorld::~BulletWorld() = default;
void BulletWorld::step() {}
BodyState BulletWorld::body(int) const {
  return {};
}
Real BulletWorld::kinetic_energy() const {
  return 0;
}
Real BulletWorld::potential_energy() const {
  return 0;
}
int BulletWorld::contact_points() const {
  return 0;
}

#endif

}  // namespace tumble::app
