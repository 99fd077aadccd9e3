// Narrow-phase benchmark: tumble and Bullet (float64 build) in the same binary, on the same
// precomputed random poses, five comparisons:
//   1. box-box manifold: tumble collide(), and the batched collide_box_pairs() over all the poses
//      at once (also its AVX2 and baseline versions on the deep poses), vs
//      btBoxBoxDetector::getClosestPoints, on deep random poses and on resting ones;
//   2. GJK on separated boxes and 3. on separated 43-vertex hulls: tumble gjk() vs
//      btGjkPairDetector (btVoronoiSimplexSolver, margins 0);
//   4. GJK+EPA on penetrating 43-vertex hulls: tumble gjk()+epa() vs btGjkPairDetector with
//      btGjkEpaPenetrationDepthSolver;
//   5. sphere-sphere over an array of 10,000 pairs: tumble collide() in a loop, and tumble's
//      batched path collide_sphere_pairs() (structure-of-arrays), vs Bullet's
//      per-pair path (btSphereSphereCollisionAlgorithm::processCollision through
//      btCollisionObjectWrapper and btManifoldResult, the algorithm created once per pair as the
//      dispatcher caches it).
// Each benchmark reports items per second; the ratios go to docs/narrow-phase-benchmark.md.
#include <benchmark/benchmark.h>
#include <btBulletCollisionCommon.h>

#include <BulletCollision/CollisionDispatch/btBoxBoxDetector.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btSphereSphereCollisionAlgorithm.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btPointCollector.h>
#include <BulletCollision/NarrowPhaseCollision/btPolyhedralContactClipping.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "collision/narrow_phase/box_batch.hpp"
#include "collision/narrow_phase/gjk_epa/epa.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/narrow_phase/pairs/pairs.hpp"
#include "collision/narrow_phase/sphere_batch.hpp"
#include "collision/shapes/convex_hull.hpp"

namespace {

using namespace tumble;
using Rng = std::mt19937_64;

constexpr int kPoses = 1024;

Vec3 unit_vector(Rng& rng) {
  std::normal_distribution<Real> n(0, 1);
  return Vec3(n(rng), n(rng), n(rng)).normalized();
}

Quat rotation(Rng& rng) {
  std::normal_distribution<Real> n(0, 1);
  return Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
}

btTransform to_bullet(const Transform& t) {
  return btTransform(btQuaternion(t.rotation.x(), t.rotation.y(), t.rotation.z(), t.rotation.w()),
                     btVector3(t.translation.x(), t.translation.y(), t.translation.z()));
}

struct PosePair {
  Transform a;
  Transform b;
};

// B's centre at `distance` times the sum of bounding radii from A's, random orientations.
std::vector<PosePair> poses(Real low, Real high, Real reach, std::uint64_t seed) {
  Rng rng(seed);
  std::uniform_real_distribution<Real> u(low, high);
  std::vector<PosePair> out;
  for (int i = 0; i < kPoses; ++i) {
    const Transform a{Vec3::Zero(), rotation(rng)};
    out.push_back({a, {unit_vector(rng) * u(rng) * reach, rotation(rng)}});
  }
  return out;
}

// 43 points on an ellipsoid: the hull of comparisons 3 and 4 above.
std::shared_ptr<const ConvexHull> hull43() {
  Rng rng(43);
  std::vector<Vec3> points;
  for (int i = 0; i < 43; ++i)
    points.push_back(unit_vector(rng).cwiseProduct(Vec3(0.6, 0.5, 0.4)));
  return std::make_shared<const ConvexHull>(ConvexHull::from_points(points));
}

std::unique_ptr<btConvexHullShape> bullet_hull(const ConvexHull& hull) {
  auto shape = std::make_unique<btConvexHullShape>();
  for (const Vec3& v : hull.vertices())
    shape->addPoint(btVector3(v.x(), v.y(), v.z()), false);
  shape->recalcLocalAabb();
  shape->setMargin(0);
  return shape;
}

// A Result that keeps nothing: the detectors' cost without a manifold's bookkeeping.
struct CountingResult : btDiscreteCollisionDetectorInterface::Result {
  int points = 0;
  void setShapeIdentifiersA(int, int) override {}
  void setShapeIdentifiersB(int, int) override {}
  void addContactPoint(const btVector3&, const btVector3&, btScalar) override { ++points; }
};

// ---- 1. box-box manifold ---------------------------------------------------------------------

const Vec3 kBoxHalf(0.5, 0.4, 0.3);

// Every box-box case: collide() against btBoxBoxDetector on the same poses.
void run_tumble_box_box(benchmark::State& state, const std::vector<PosePair>& p) {
  const Shape box = Shape::box(kBoxHalf);
  Manifold m;
  std::size_t i = 0;
  for (auto _ : state) {
    const PosePair& q = p[i++ % p.size()];
    benchmark::DoNotOptimize(collide(box, q.a, box, q.b, 0, m));
  }
  state.SetItemsProcessed(state.iterations());
}

void run_bullet_box_box(benchmark::State& state, const std::vector<PosePair>& p) {
  btBoxShape box(btVector3(kBoxHalf.x(), kBoxHalf.y(), kBoxHalf.z()));
  box.setMargin(0);
  btBoxBoxDetector detector(&box, &box);
  std::size_t i = 0;
  for (auto _ : state) {
    const PosePair& q = p[i++ % p.size()];
    btDiscreteCollisionDetectorInterface::ClosestPointInput input;
    input.m_transformA = to_bullet(q.a);
    input.m_transformB = to_bullet(q.b);
    CountingResult result;
    detector.getClosestPoints(input, result, nullptr);
    benchmark::DoNotOptimize(result.points);
  }
  state.SetItemsProcessed(state.iterations());
}

// The batched path: collide_box_pairs over all the poses at once, timed per pair.
using BoxBatchVersion = int (*)(std::span<const BoxPairQuery>, std::span<Manifold>);

// `version`: collide_box_pairs (the best the CPU has) or one instruction-set version, which runs
// only when `supported` (the CPU has its instructions).
void run_tumble_box_batch(benchmark::State& state, const std::vector<PosePair>& p,
                          BoxBatchVersion version = collide_box_pairs, bool supported = true) {
  if (!supported) {
    state.SkipWithError("this CPU lacks the instruction set of this version");
    return;
  }
  std::vector<BoxPairQuery> queries;
  for (const PosePair& q : p)
    queries.push_back({kBoxHalf, q.a, kBoxHalf, q.b});
  std::vector<Manifold> out(queries.size());
  for (auto _ : state)
    benchmark::DoNotOptimize(version(queries, out));
  state.SetItemsProcessed(state.iterations() * std::int64_t(queries.size()));
}

void BM_BoxBoxManifold_Tumble(benchmark::State& state) {
  run_tumble_box_box(state, poses(0.2, 0.75, 2 * kBoxHalf.norm(), 1));
}
void BM_BoxBoxManifold_Bullet(benchmark::State& state) {
  run_bullet_box_box(state, poses(0.2, 0.75, 2 * kBoxHalf.norm(), 1));
}
void BM_BoxBoxManifold_TumbleBatch(benchmark::State& state) {
  run_tumble_box_batch(state, poses(0.2, 0.75, 2 * kBoxHalf.norm(), 1));
}
// The batch's narrower versions on the same poses (the same bits, for machines without AVX-512).
void BM_BoxBoxManifold_TumbleBatchAvx2(benchmark::State& state) {
  run_tumble_box_batch(state, poses(0.2, 0.75, 2 * kBoxHalf.norm(), 1),
                       detail::collide_box_pairs_avx2, __builtin_cpu_supports("avx2") != 0);
}
void BM_BoxBoxManifold_TumbleBatchBaseline(benchmark::State& state) {
  run_tumble_box_batch(state, poses(0.2, 0.75, 2 * kBoxHalf.norm(), 1),
                       detail::collide_box_pairs_portable);
}

// The same pair resting, as boxes in a stack or on a pallet do (the contacts a simulation mostly
// sees, unlike the deep random poses above): B on A's top face, turned by a random angle about
// A's z axis and tilted by up to 0.5 degrees about a random horizontal axis, its centre shifted
// sideways by up to 0.2 m and sunk by up to 1 % of its height; A in a random orientation.
std::vector<PosePair> resting_box_poses(std::uint64_t seed) {
  Rng rng(seed);
  std::uniform_real_distribution<Real> unit(-1, 1);
  std::uniform_real_distribution<Real> sink(0, 0.01 * 2 * kBoxHalf.z());
  std::vector<PosePair> out;
  for (int i = 0; i < kPoses; ++i) {
    const Quat qa = rotation(rng);
    const Quat yaw(Eigen::AngleAxis<Real>(M_PI * unit(rng), Vec3::UnitZ()));
    const Real tilt_direction = M_PI * unit(rng);
    const Quat tilt(
        Eigen::AngleAxis<Real>(0.5 * M_PI / 180 * std::abs(unit(rng)),
                               Vec3(std::cos(tilt_direction), std::sin(tilt_direction), 0)));
    const Vec3 offset(0.2 * unit(rng), 0.2 * unit(rng), 2 * kBoxHalf.z() - sink(rng));
    out.push_back({{Vec3::Zero(), qa}, {qa * offset, qa * tilt * yaw}});
  }
  return out;
}

void BM_BoxBoxResting_Tumble(benchmark::State& state) {
  run_tumble_box_box(state, resting_box_poses(7));
}
void BM_BoxBoxResting_Bullet(benchmark::State& state) {
  run_bullet_box_box(state, resting_box_poses(7));
}
void BM_BoxBoxResting_TumbleBatch(benchmark::State& state) {
  run_tumble_box_batch(state, resting_box_poses(7));
}

// ---- 2./3. GJK on separated pairs --------------------------------------------------------------

void run_tumble_gjk(benchmark::State& state, const Shape& shape, Real reach, bool with_epa,
                    Real low, Real high) {
  const auto p = poses(low, high, reach, 2);
  std::size_t i = 0;
  std::int64_t gjk_iterations = 0;
  std::int64_t epa_iterations = 0;
  for (auto _ : state) {
    const PosePair& q = p[i++ % p.size()];
    const ConvexSupport a = ConvexSupport::of(shape, q.a);
    const ConvexSupport b = ConvexSupport::of(shape, q.b);
    const GjkResult g = gjk(a, b);
    gjk_iterations += g.iterations;
    if (with_epa && g.status == GjkStatus::intersecting) {
      const EpaResult e = epa(a, b, g);
      epa_iterations += e.iterations;
      benchmark::DoNotOptimize(e.depth);
    } else {
      benchmark::DoNotOptimize(g.distance);
    }
  }
  state.SetItemsProcessed(state.iterations());
  // Mean iterations per query, to read the time per iteration off.
  state.counters["gjk_iterations"] = Real(gjk_iterations) / Real(state.iterations());
  if (with_epa)
    state.counters["epa_iterations"] = Real(epa_iterations) / Real(state.iterations());
}

void run_bullet_gjk(benchmark::State& state, const btConvexShape& shape, Real reach, Real low,
                    Real high) {
  const auto p = poses(low, high, reach, 2);
  btVoronoiSimplexSolver simplex;
  btGjkEpaPenetrationDepthSolver epa;
  btGjkPairDetector detector(&shape, &shape, &simplex, &epa);
  std::size_t i = 0;
  for (auto _ : state) {
    const PosePair& q = p[i++ % p.size()];
    btDiscreteCollisionDetectorInterface::ClosestPointInput input;
    input.m_transformA = to_bullet(q.a);
    input.m_transformB = to_bullet(q.b);
    input.m_maximumDistanceSquared = BT_LARGE_FLOAT;
    btPointCollector out;
    detector.getClosestPoints(input, out, nullptr);
    benchmark::DoNotOptimize(out.m_distance);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_GjkSeparatedBoxes_Tumble(benchmark::State& state) {
  run_tumble_gjk(state, Shape::box(kBoxHalf), 2 * kBoxHalf.norm(), false, 1.05, 1.5);
}

void BM_GjkSeparatedBoxes_Bullet(benchmark::State& state) {
  btBoxShape box(btVector3(kBoxHalf.x(), kBoxHalf.y(), kBoxHalf.z()));
  box.setMargin(0);
  run_bullet_gjk(state, box, 2 * kBoxHalf.norm(), 1.05, 1.5);
}

void BM_GjkSeparatedHulls43_Tumble(benchmark::State& state) {
  const Shape hull = Shape::convex_hull(hull43());
  run_tumble_gjk(state, hull, 2 * bounding_radius(hull), false, 1.05, 1.5);
}

void BM_GjkSeparatedHulls43_Bullet(benchmark::State& state) {
  const auto hull = hull43();
  const auto shape = bullet_hull(*hull);
  run_bullet_gjk(state, *shape, 2 * hull->bounding_radius(), 1.05, 1.5);
}

// ---- 4. GJK+EPA on penetrating hulls ---------------------------------------------------------

void BM_GjkEpaPenetratingHulls43_Tumble(benchmark::State& state) {
  const Shape hull = Shape::convex_hull(hull43());
  run_tumble_gjk(state, hull, 2 * bounding_radius(hull), true, 0.1, 0.5);
}

void BM_GjkEpaPenetratingHulls43_Bullet(benchmark::State& state) {
  const auto hull = hull43();
  const auto shape = bullet_hull(*hull);
  run_bullet_gjk(state, *shape, 2 * hull->bounding_radius(), 0.1, 0.5);
}

// ---- 5. sphere-sphere over 10,000 pairs ------------------------------------------------------

constexpr int kSpherePairs = 10000;

void BM_SphereSphereArray_Tumble(benchmark::State& state) {
  Rng rng(5);
  std::uniform_real_distribution<Real> u(0.5, 1.2);
  std::vector<Shape> shapes;
  std::vector<PosePair> pairs;
  for (int i = 0; i < kSpherePairs; ++i) {
    shapes.push_back(Shape::sphere(0.5));
    pairs.push_back({{Vec3(i, 0, 0), Quat::Identity()},
                     {Vec3(i, 0, 0) + unit_vector(rng) * u(rng), Quat::Identity()}});
  }
  const Shape sphere = Shape::sphere(0.5);
  Manifold m;
  for (auto _ : state) {
    int contacts = 0;
    for (const PosePair& q : pairs)
      contacts += collide(sphere, q.a, sphere, q.b, 0, m);
    benchmark::DoNotOptimize(contacts);
  }
  state.SetItemsProcessed(state.iterations() * kSpherePairs);
}

// The same pairs as structure-of-arrays (spheres 2i and 2i + 1 form pair i), for the batched
// paths (collision/narrow_phase/sphere_batch.hpp).
struct SphereSoa {
  std::vector<Real> x, y, z, radius;
  std::vector<SpherePair> pairs;
  SphereArrays arrays() const { return {x.data(), y.data(), z.data(), radius.data()}; }
};

SphereSoa sphere_pairs_soa() {
  Rng rng(5);
  std::uniform_real_distribution<Real> u(0.5, 1.2);
  SphereSoa soa;
  for (int i = 0; i < kSpherePairs; ++i) {
    const Vec3 b = Vec3(i, 0, 0) + unit_vector(rng) * u(rng);
    soa.x.insert(soa.x.end(), {Real(i), b.x()});
    soa.y.insert(soa.y.end(), {Real(0), b.y()});
    soa.z.insert(soa.z.end(), {Real(0), b.z()});
    soa.radius.insert(soa.radius.end(), {Real(0.5), Real(0.5)});
    soa.pairs.push_back({2 * i, 2 * i + 1});
  }
  return soa;
}

// Compact output: one SphereContact per touching pair.
void BM_SphereSphereArray_TumbleBatch(benchmark::State& state) {
  const SphereSoa soa = sphere_pairs_soa();
  std::vector<SphereContact> contacts(soa.pairs.size());
  for (auto _ : state) {
    const std::size_t written = collide_sphere_pairs(soa.arrays(), soa.pairs, 0, contacts);
    benchmark::DoNotOptimize(written);
    benchmark::DoNotOptimize(contacts.data());
  }
  state.SetItemsProcessed(state.iterations() * kSpherePairs);
}

// Dense output: results for every pair as structure-of-arrays, no compaction (the caller reads
// depth >= -margin).
void BM_SphereSphereArray_TumbleDense(benchmark::State& state) {
  const SphereSoa soa = sphere_pairs_soa();
  const std::size_t n = soa.pairs.size();
  std::vector<Real> out(7 * n);
  const SphereContactArrays results{out.data(),         out.data() + n,     out.data() + 2 * n,
                                    out.data() + 3 * n, out.data() + 4 * n, out.data() + 5 * n,
                                    out.data() + 6 * n};
  for (auto _ : state) {
    const std::size_t touching = collide_sphere_pairs_dense(soa.arrays(), soa.pairs, 0, results);
    benchmark::DoNotOptimize(touching);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * kSpherePairs);
}

void BM_SphereSphereArray_Bullet(benchmark::State& state) {
  Rng rng(5);
  std::uniform_real_distribution<Real> u(0.5, 1.2);
  btSphereShape sphere(0.5);
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  std::vector<std::unique_ptr<btCollisionObject>> objects;
  for (int i = 0; i < 2 * kSpherePairs; ++i) {
    auto object = std::make_unique<btCollisionObject>();
    object->setCollisionShape(&sphere);
    btTransform t;
    t.setIdentity();
    const Vec3 offset = i % 2 == 0 ? Vec3::Zero() : Vec3(unit_vector(rng) * u(rng));
    t.setOrigin(btVector3(i / 2 + offset.x(), offset.y(), offset.z()));
    object->setWorldTransform(t);
    objects.push_back(std::move(object));
  }
  std::vector<btPersistentManifold*> manifolds;
  std::vector<btCollisionAlgorithm*> algorithms;
  for (int i = 0; i < kSpherePairs; ++i) {
    btCollisionObject* a = objects[std::size_t(2 * i)].get();
    btCollisionObject* b = objects[std::size_t(2 * i + 1)].get();
    btCollisionObjectWrapper wa(nullptr, &sphere, a, a->getWorldTransform(), -1, -1);
    btCollisionObjectWrapper wb(nullptr, &sphere, b, b->getWorldTransform(), -1, -1);
    btPersistentManifold* manifold = dispatcher.getNewManifold(a, b);
    manifolds.push_back(manifold);
    algorithms.push_back(dispatcher.findAlgorithm(&wa, &wb, manifold, BT_CONTACT_POINT_ALGORITHMS));
  }
  btDispatcherInfo info;
  for (auto _ : state) {
    int contacts = 0;
    for (int i = 0; i < kSpherePairs; ++i) {
      btCollisionObject* a = objects[std::size_t(2 * i)].get();
      btCollisionObject* b = objects[std::size_t(2 * i + 1)].get();
      btCollisionObjectWrapper wa(nullptr, &sphere, a, a->getWorldTransform(), -1, -1);
      btCollisionObjectWrapper wb(nullptr, &sphere, b, b->getWorldTransform(), -1, -1);
      btManifoldResult result(&wa, &wb);
      algorithms[std::size_t(i)]->processCollision(&wa, &wb, info, &result);
      contacts += manifolds[std::size_t(i)]->getNumContacts();
    }
    benchmark::DoNotOptimize(contacts);
  }
  state.SetItemsProcessed(state.iterations() * kSpherePairs);
  for (btCollisionAlgorithm* algorithm : algorithms) {
    algorithm->~btCollisionAlgorithm();
    dispatcher.freeCollisionAlgorithm(algorithm);
  }
  for (btPersistentManifold* manifold : manifolds)
    dispatcher.releaseManifold(manifold);
}

// ---- 6. hull-hull manifolds: SAT vs GJK+EPA vs Bullet's polyhedral SAT ----------------------
// The 43-vertex hull pair on the poses of case 4 (penetrating, centres 0.1 to 0.5 of the sum of
// bounding radii apart), on shallow poses (shallow_hull_poses: touching, sunk by up to 1 %) and
// on the separated poses of case 3 (1.05 to 1.5). Every case builds the whole manifold:
//   tumble SAT      detail::hull_hull (hull_hull_sat.cpp: face and Gauss-map-pruned edge queries,
//                   face clipping, reduction to 4 points);
//   tumble GJK+EPA  detail::convex_convex (convex_pairs.cpp: GJK, EPA, feature clipping);
//   Bullet SAT      btPolyhedralContactClipping::findSeparatingAxis + clipHullAgainstHull on
//                   btConvexHullShape with initializePolyhedralFeatures() (margin 0, contact
//                   range [-1e30, 0] as btConvexConvexAlgorithm passes with a zero breaking
//                   threshold).

// Shallow contacts: B comes in from a random direction with a random orientation until the
// hulls touch (bisection on GJK's distance), then sinks by up to 1 % of the hull's bounding
// radius: the resting and sliding contacts a simulation mostly sees.
std::vector<PosePair> shallow_hull_poses(std::uint64_t seed) {
  const Shape hull = Shape::convex_hull(hull43());
  const Real radius = bounding_radius(hull);
  Rng rng(seed);
  std::uniform_real_distribution<Real> sink(0, 0.01 * radius);
  std::vector<PosePair> out;
  for (int i = 0; i < kPoses; ++i) {
    const Transform a{Vec3::Zero(), rotation(rng)};
    const Vec3 direction = unit_vector(rng);
    const Quat turn = rotation(rng);
    Real inside = 0;
    Real apart = 2 * radius + 1;
    for (int k = 0; k < 60; ++k) {
      const Real middle = 0.5 * (inside + apart);
      const GjkResult g = gjk(ConvexSupport::of(hull, a),
                              ConvexSupport::of(hull, Transform{direction * middle, turn}));
      (g.status == GjkStatus::intersecting ? inside : apart) = middle;
    }
    out.push_back({a, {direction * (inside - sink(rng)), turn}});
  }
  return out;
}

void run_tumble_hull_pair(benchmark::State& state, detail::PairFunction pair, Real low, Real high,
                          std::uint64_t seed) {
  const Shape hull = Shape::convex_hull(hull43());
  const auto p =
      low < 0 ? shallow_hull_poses(seed) : poses(low, high, 2 * bounding_radius(hull), seed);
  Manifold m;
  std::size_t i = 0;
  for (auto _ : state) {
    const PosePair& q = p[i++ % p.size()];
    m = Manifold{};
    benchmark::DoNotOptimize(pair(hull, q.a, hull, q.b, 0, m));
  }
  state.SetItemsProcessed(state.iterations());
  // Outside the timed loop: the share of poses in contact and the mean number of points.
  int touching = 0;
  int points = 0;
  for (const PosePair& q : p) {
    m = Manifold{};
    const int count = pair(hull, q.a, hull, q.b, 0, m);
    touching += count > 0 ? 1 : 0;
    points += count;
  }
  state.counters["touching"] = Real(touching) / Real(p.size());
  state.counters["points"] = Real(points) / Real(std::max(touching, 1));
}

void run_bullet_hull_sat(benchmark::State& state, Real low, Real high, std::uint64_t seed) {
  const auto hull = hull43();
  const auto shape = bullet_hull(*hull);
  shape->initializePolyhedralFeatures();
  const btConvexPolyhedron& polyhedron = *shape->getConvexPolyhedron();
  const auto p =
      low < 0 ? shallow_hull_poses(seed) : poses(low, high, 2 * hull->bounding_radius(), seed);
  btVertexArray vertices_1;
  btVertexArray vertices_2;
  std::size_t i = 0;
  for (auto _ : state) {
    const PosePair& q = p[i++ % p.size()];
    const btTransform ta = to_bullet(q.a);
    const btTransform tb = to_bullet(q.b);
    CountingResult result;
    btVector3 axis;
    if (btPolyhedralContactClipping::findSeparatingAxis(polyhedron, polyhedron, ta, tb, axis,
                                                        result)) {
      vertices_1.resize(0);
      btPolyhedralContactClipping::clipHullAgainstHull(
          axis, polyhedron, polyhedron, ta, tb, btScalar(-1e30), 0, vertices_1, vertices_2, result);
    }
    benchmark::DoNotOptimize(result.points);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_HullHull43Penetrating_TumbleSat(benchmark::State& state) {
  run_tumble_hull_pair(state, detail::hull_hull, 0.1, 0.5, 2);
}
void BM_HullHull43Penetrating_TumbleGjkEpa(benchmark::State& state) {
  run_tumble_hull_pair(state, detail::convex_convex, 0.1, 0.5, 2);
}
void BM_HullHull43Penetrating_BulletSat(benchmark::State& state) {
  run_bullet_hull_sat(state, 0.1, 0.5, 2);
}
void BM_HullHull43Shallow_TumbleSat(benchmark::State& state) {
  run_tumble_hull_pair(state, detail::hull_hull, -1, -1, 6);
}
void BM_HullHull43Shallow_TumbleGjkEpa(benchmark::State& state) {
  run_tumble_hull_pair(state, detail::convex_convex, -1, -1, 6);
}
void BM_HullHull43Shallow_BulletSat(benchmark::State& state) {
  run_bullet_hull_sat(state, -1, -1, 6);
}
void BM_HullHull43Separated_TumbleSat(benchmark::State& state) {
  run_tumble_hull_pair(state, detail::hull_hull, 1.05, 1.5, 2);
}
void BM_HullHull43Separated_TumbleGjkEpa(benchmark::State& state) {
  run_tumble_hull_pair(state, detail::convex_convex, 1.05, 1.5, 2);
}
void BM_HullHull43Separated_BulletSat(benchmark::State& state) {
  run_bullet_hull_sat(state, 1.05, 1.5, 2);
}

BENCHMARK(BM_BoxBoxManifold_Tumble);
BENCHMARK(BM_BoxBoxManifold_Bullet);
BENCHMARK(BM_BoxBoxManifold_TumbleBatch);
BENCHMARK(BM_BoxBoxManifold_TumbleBatchAvx2);
BENCHMARK(BM_BoxBoxManifold_TumbleBatchBaseline);
BENCHMARK(BM_BoxBoxResting_Tumble);
BENCHMARK(BM_BoxBoxResting_Bullet);
BENCHMARK(BM_BoxBoxResting_TumbleBatch);
BENCHMARK(BM_GjkSeparatedBoxes_Tumble);
BENCHMARK(BM_GjkSeparatedBoxes_Bullet);
BENCHMARK(BM_GjkSeparatedHulls43_Tumble);
BENCHMARK(BM_GjkSeparatedHulls43_Bullet);
BENCHMARK(BM_GjkEpaPenetratingHulls43_Tumble);
BENCHMARK(BM_GjkEpaPenetratingHulls43_Bullet);
BENCHMARK(BM_SphereSphereArray_Tumble);
BENCHMARK(BM_SphereSphereArray_TumbleBatch);
BENCHMARK(BM_SphereSphereArray_TumbleDense);
BENCHMARK(BM_SphereSphereArray_Bullet);
BENCHMARK(BM_HullHull43Penetrating_TumbleSat);
BENCHMARK(BM_HullHull43Penetrating_TumbleGjkEpa);
BENCHMARK(BM_HullHull43Penetrating_BulletSat);
BENCHMARK(BM_HullHull43Shallow_TumbleSat);
BENCHMARK(BM_HullHull43Shallow_TumbleGjkEpa);
BENCHMARK(BM_HullHull43Shallow_BulletSat);
BENCHMARK(BM_HullHull43Separated_TumbleSat);
BENCHMARK(BM_HullHull43Separated_TumbleGjkEpa);
BENCHMARK(BM_HullHull43Separated_BulletSat);

}  // namespace

BENCHMARK_MAIN();
