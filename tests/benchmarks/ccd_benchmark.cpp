// CCD benchmark (docs/ccd.md). Per query kind, on fixed random inputs (seeded):
//   - conservative advancement on a convex pair (sphere-sphere, box-box, capsule-box) with
//     rotation, and on translating boxes against the time-extended SAT (same inputs);
//   - the time-extended SAT for boxes and hulls, translating and turning, against conservative
//     advancement on the same inputs, with the largest time difference as a counter;
//   - vertex-face and edge-edge mesh CCD on every query of
//     tests/data/external/ccd-sample-queries, and vertex-face on 512 vertices sliding in a
//     triangle's plane beside an edge (the hard case, tests/ccd/ccd_test_support.hpp), with the
//     parameter boxes per query as counters;
//   - the high-speed scene (scenes/high_speed.yaml: 2000 bodies at 250 m/s in a closed box),
//     36 steps, tumble with CCD against Bullet 3 (btDiscreteDynamicsWorld) with its swept-sphere
//     CCD and without it. Each run reports the bodies that left the box as the counter `escaped`.
// Bullet settings, stated so the comparison is repeatable: collision margin 0.001 m on every
// shape (Bullet's default 0.04 m would be 40% of a body), dbvt broad phase, sequential impulse
// solver with 10 iterations, fixed 1/60 s steps (stepSimulation(dt, 0)), friction 0.2 and
// restitution 0.8 as in the scene; with CCD each body has ccdMotionThreshold = its radius and a
// swept sphere of radius 0.8 times its thickness.
//
// Run: bench_ccd --benchmark_out=ccd.json --benchmark_out_format=json
#include <benchmark/benchmark.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "collision/ccd/conservative_advancement.hpp"
#include "collision/ccd/mesh_ccd.hpp"
#include "collision/ccd/swept_box_sat.hpp"
#include "collision/ccd/swept_hull_sat.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"
#include "tests/ccd/ccd_test_support.hpp"

namespace tumble::bench {
namespace {

Vec3 random_vector(std::mt19937_64& rng, Real lo, Real hi) {
  std::uniform_real_distribution<Real> u(lo, hi);
  return Vec3(u(rng), u(rng), u(rng));
}

Quat random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<Real> n(0, 1);
  return Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
}

struct PairQuery {
  Shape a, b;
  RigidMotion ma, mb;
};

// 1024 random pairs of one kind, aimed at each other (about two thirds hit).
std::vector<PairQuery> pair_queries(int kind, bool rotate) {
  std::mt19937_64 rng(7 + kind);
  std::vector<PairQuery> out;
  while (out.size() < 1024) {
    PairQuery q;
    q.a = kind == 0   ? Shape::sphere(0.3)
          : kind == 1 ? Shape::box(Vec3(0.3, 0.2, 0.4))
                      : Shape::capsule(0.2, 0.3);
    q.b = kind == 0 ? Shape::sphere(0.4) : Shape::box(Vec3(0.4, 0.3, 0.2));
    const Transform pa{random_vector(rng, -2, 2), random_rotation(rng)};
    const Transform pb{random_vector(rng, -2, 2), random_rotation(rng)};
    if ((pa.translation - pb.translation).norm() < 1.6)
      continue;
    const Vec3 w = rotate ? random_vector(rng, -5, 5) : Vec3::Zero();
    q.ma = RigidMotion::from_velocity(
        pa, (pb.translation - pa.translation) * 1.2 + random_vector(rng, -1, 1), w);
    q.mb = RigidMotion::from_velocity(pb, random_vector(rng, -0.5, 0.5),
                                      rotate ? random_vector(rng, -5, 5) : Vec3::Zero());
    out.push_back(q);
  }
  return out;
}

void BM_ConservativeAdvancement(benchmark::State& state) {
  const auto queries = pair_queries(static_cast<int>(state.range(0)), true);
  ToiSettings settings;
  settings.tolerance = 1e-6;
  std::size_t i = 0;
  std::int64_t hits = 0, iterations = 0;
  for (auto _ : state) {
    const PairQuery& q = queries[i++ & 1023];
    const ToiResult r = time_of_impact(q.a, q.ma, q.b, q.mb, settings);
    hits += r.hit() ? 1 : 0;
    iterations += r.iterations;
    benchmark::DoNotOptimize(r);
  }
  state.counters["hit_rate"] = double(hits) / double(state.iterations());
  state.counters["distance_queries"] = double(iterations) / double(state.iterations());
}
BENCHMARK(BM_ConservativeAdvancement)->ArgName("pair")->Arg(0)->Arg(1)->Arg(2);

// Translating boxes: the same inputs to conservative advancement and to the time-extended SAT.
void BM_TranslatingBoxes(benchmark::State& state) {
  const auto queries = pair_queries(1, false);
  const bool sat = state.range(0) >= 1;
  ToiSettings settings;
  settings.tolerance = 1e-9;
  std::size_t i = 0;
  std::int64_t hits = 0;
  for (auto _ : state) {
    const PairQuery& q = queries[i++ & 1023];
    ToiResult r;
    if (state.range(0) == 2) {
      r = time_extended_sat(q.a, q.ma, q.b, q.mb);  // the general polytope code on boxes
    } else if (sat) {
      r = swept_box_sat(q.a.half_extents, q.ma.start(), q.ma.linear_velocity(), q.b.half_extents,
                        q.mb.start(), q.mb.linear_velocity());
    } else {
      r = time_of_impact(q.a, q.ma, q.b, q.mb, settings);
    }
    hits += r.hit() ? 1 : 0;
    benchmark::DoNotOptimize(r);
  }
  state.counters["hit_rate"] = double(hits) / double(state.iterations());
  state.SetLabel(state.range(0) == 2 ? "time-extended SAT, polytope code"
                 : sat               ? "time-extended SAT"
                                     : "conservative advancement");
}
BENCHMARK(BM_TranslatingBoxes)->ArgName("sat")->Arg(0)->Arg(1)->Arg(2);

// Time-extended SAT for boxes and hulls (collision/ccd/swept_hull_sat.hpp) against conservative
// advancement (box-box SAT bound; GJK for hulls) on the same inputs. Pairs: 0 boxes (the queries
// above), 1 hulls of 12 random points, 2 hulls of 40 random points. Counters: hit rate, distance
// evaluations (CA) or axis-set evaluations (SAT) per query, and, for the SAT runs, the largest
// |t - t_CA| over the 1024 queries (CA with tolerance 1e-12 as the reference), the queries that
// either method left at its iteration cap, and hit/miss disagreements.
std::vector<PairQuery> polytope_queries(int pairs, bool rotate) {
  if (pairs == 0)
    return pair_queries(1, rotate);
  std::mt19937_64 rng(100 + pairs);
  std::vector<Shape> hulls;
  for (int h = 0; h < 16; ++h) {
    std::vector<Vec3> points;
    const Vec3 radii = random_vector(rng, 0.2, 0.5);
    for (int k = 0; k < (pairs == 1 ? 12 : 40); ++k)
      points.push_back(random_vector(rng, -1, 1).normalized().cwiseProduct(radii));
    hulls.push_back(
        Shape::convex_hull(std::make_shared<const ConvexHull>(ConvexHull::from_points(points))));
  }
  std::vector<PairQuery> out = pair_queries(1, rotate);  // the same poses and motions
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i].a = hulls[i % 16];
    out[i].b = hulls[(i / 16) % 16];
  }
  return out;
}

void polytope_toi_benchmark(benchmark::State& state, bool rotate) {
  const int pairs = static_cast<int>(state.range(0));
  const bool sat = state.range(1) == 1;
  const auto queries = polytope_queries(pairs, rotate);
  ToiSettings settings;
  settings.tolerance = 1e-9;
  settings.max_iterations = 1000;
  if (sat) {
    ToiSettings reference = settings;
    reference.tolerance = 1e-12;
    reference.max_iterations = 10000;
    Real worst = 0;
    int capped = 0, disagree = 0;
    for (const PairQuery& q : queries) {
      const ToiResult a = time_extended_sat(q.a, q.ma, q.b, q.mb, settings);
      const ToiResult b = time_of_impact(q.a, q.ma, q.b, q.mb, reference);
      if (a.status == ToiStatus::max_iterations || b.status == ToiStatus::max_iterations) {
        ++capped;  // a graze that neither settles within its cap
      } else if (a.hit() != b.hit()) {
        ++disagree;
      } else if (a.hit()) {
        worst = std::max(worst, std::abs(a.time_of_impact - b.time_of_impact));
      }
    }
    state.counters["max_time_difference"] = worst;
    state.counters["capped"] = capped;
    state.counters["hit_disagreements"] = disagree;
  }
  std::size_t i = 0;
  std::int64_t hits = 0, iterations = 0;
  for (auto _ : state) {
    const PairQuery& q = queries[i++ & 1023];
    const ToiResult r = sat ? time_extended_sat(q.a, q.ma, q.b, q.mb, settings)
                            : time_of_impact(q.a, q.ma, q.b, q.mb, settings);
    hits += r.hit() ? 1 : 0;
    iterations += r.iterations;
    benchmark::DoNotOptimize(r);
  }
  state.counters["hit_rate"] = double(hits) / double(state.iterations());
  state.counters["evaluations"] = double(iterations) / double(state.iterations());
  state.SetLabel(sat ? "time-extended SAT" : "conservative advancement");
}

void BM_TranslatingPolytopes(benchmark::State& state) {
  polytope_toi_benchmark(state, false);
}
BENCHMARK(BM_TranslatingPolytopes)->ArgNames({"pairs", "sat"})->ArgsProduct({{0, 1, 2}, {0, 1}});

void BM_TurningPolytopes(benchmark::State& state) {
  polytope_toi_benchmark(state, true);
}
BENCHMARK(BM_TurningPolytopes)->ArgNames({"pairs", "sat"})->ArgsProduct({{0, 1, 2}, {0, 1}});

struct FeatureQuery {
  std::array<Vec3, 4> start, end;
};

std::vector<FeatureQuery> sample_queries(const std::string& kind) {
  std::vector<FeatureQuery> out;
  const std::filesystem::path root =
      std::filesystem::path(TUMBLE_SOURCE_DIR) / "tests/data/external/ccd-sample-queries";
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
    if (e.path().extension() == ".csv" && e.path().parent_path().filename() == kind)
      files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    std::ifstream in(f);
    std::string line;
    FeatureQuery q;
    int row = 0;
    while (std::getline(in, line)) {
      if (line.empty())
        continue;
      std::stringstream ss(line);
      std::string cell;
      std::array<double, 6> v{};
      for (int k = 0; k < 6 && std::getline(ss, cell, ','); ++k)
        v[k] = std::stod(cell);
      const Vec3 p(v[0] / v[1], v[2] / v[3], v[4] / v[5]);
      (row < 4 ? q.start[row] : q.end[row - 4]) = p;
      if (++row == 8) {
        out.push_back(q);
        row = 0;
      }
    }
  }
  return out;
}

// Parameter boxes per query (deterministic work, MeshCcdResult::boxes) as counters: mean,
// median, largest, and the queries that ran out of boxes.
void box_counters(benchmark::State& state, const std::vector<FeatureQuery>& queries, bool vf) {
  std::vector<std::int32_t> boxes;
  std::int64_t total = 0, capped = 0;
  for (const FeatureQuery& q : queries) {
    const MeshCcdResult r = vf ? vertex_face_ccd(q.start, q.end) : edge_edge_ccd(q.start, q.end);
    boxes.push_back(r.boxes);
    total += r.boxes;
    capped += r.status == MeshCcdStatus::max_iterations ? 1 : 0;
  }
  std::sort(boxes.begin(), boxes.end());
  state.counters["boxes_mean"] = double(total) / double(queries.size());
  state.counters["boxes_median"] = boxes[boxes.size() / 2];
  state.counters["boxes_max"] = boxes.back();
  state.counters["capped"] = double(capped);
}

// One iteration runs the whole sample (a few hard queries dominate; cycling through a prefix
// would weigh them by chance); items are queries.
void BM_MeshCcdSample(benchmark::State& state) {
  const bool vf = state.range(0) == 0;
  const auto queries = sample_queries(vf ? "vertex-face" : "edge-edge");
  box_counters(state, queries, vf);
  for (auto _ : state) {
    for (const FeatureQuery& q : queries) {
      const MeshCcdResult r = vf ? vertex_face_ccd(q.start, q.end) : edge_edge_ccd(q.start, q.end);
      benchmark::DoNotOptimize(r);
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(queries.size()));
  state.SetLabel(vf ? "vertex-face, ccd-sample-queries" : "edge-edge, ccd-sample-queries");
}
BENCHMARK(BM_MeshCcdSample)->ArgName("ee")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// A vertex sliding in a triangle's plane beside an edge, 1e-6 m to 1e-3 m outside it (one in
// four crossing in): the coplanar near miss that tiled a curve of parameter boxes. The whole set
// per iteration, as for the sample.
void BM_MeshCcdSliding(benchmark::State& state) {
  std::vector<FeatureQuery> queries;
  for (const testing::SlidingQuery& s : testing::sliding_vertex_face_queries(31, 512))
    queries.push_back({s.start, s.end});
  box_counters(state, queries, true);
  for (auto _ : state) {
    for (const FeatureQuery& q : queries)
      benchmark::DoNotOptimize(vertex_face_ccd(q.start, q.end));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(queries.size()));
  state.SetLabel("vertex-face, sliding beside an edge");
}
BENCHMARK(BM_MeshCcdSliding)->Unit(benchmark::kMillisecond);

// Random features (vertices in the unit cube moving up to 0.5): the common, easy case.
void BM_MeshCcdRandom(benchmark::State& state) {
  const bool vf = state.range(0) == 0;
  std::mt19937_64 rng(9);
  std::vector<FeatureQuery> queries(1024);
  for (auto& q : queries) {
    for (int k = 0; k < 4; ++k) {
      q.start[k] = random_vector(rng, -1, 1);
      q.end[k] = q.start[k] + random_vector(rng, -0.5, 0.5);
    }
  }
  std::size_t i = 0;
  for (auto _ : state) {
    const FeatureQuery& q = queries[i++ & 1023];
    const MeshCcdResult r = vf ? vertex_face_ccd(q.start, q.end) : edge_edge_ccd(q.start, q.end);
    benchmark::DoNotOptimize(r);
  }
  state.SetLabel(vf ? "vertex-face, random" : "edge-edge, random");
}
BENCHMARK(BM_MeshCcdRandom)->ArgName("ee")->Arg(0)->Arg(1);

// ---------------------------------------------------------------------------------------------
// The high-speed scene in tumble and in Bullet.

constexpr int kHighSpeedSteps = 36;

std::shared_ptr<const Scene> high_speed_scene() {
  static const auto scene = std::make_shared<const Scene>(
      load_scene_file(std::string(TUMBLE_SOURCE_DIR) + "/scenes/high_speed.yaml"));
  return scene;
}

int escaped(const std::vector<Vec3>& positions) {
  int n = 0;
  for (const Vec3& p : positions)
    n += p.cwiseAbs().maxCoeff() > 50.5 ? 1 : 0;
  return n;
}

void BM_HighSpeedTumble(benchmark::State& state) {
  auto scene = std::make_shared<Scene>(*high_speed_scene());
  scene->world.ccd = state.range(0) == 1 ? CcdMode::automatic : CcdMode::off;
  int lost = 0;
  for (auto _ : state) {
    Simulation world(scene);
    for (int k = 0; k < kHighSpeedSteps; ++k)
      world.step();
    std::vector<Vec3> positions;
    for (std::size_t i = 0; i < scene->bodies.size(); ++i) {
      if (!scene->bodies[i].is_static)
        positions.push_back(world.state().bodies[i].position);
    }
    lost = escaped(positions);
  }
  state.counters["escaped"] = lost;
  state.SetLabel(state.range(0) == 1 ? "tumble, ccd auto" : "tumble, ccd off");
}
BENCHMARK(BM_HighSpeedTumble)
    ->ArgName("ccd")
    ->Arg(1)
    ->Arg(0)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

btVector3 bt(const Vec3& v) {
  return btVector3(v.x(), v.y(), v.z());
}

void BM_HighSpeedBullet(benchmark::State& state) {
  const auto scene = high_speed_scene();
  const bool ccd = state.range(0) == 1;
  int lost = 0;
  for (auto _ : state) {
    btDefaultCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher(&configuration);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
    world.setGravity(bt(scene->world.gravity));
    world.getSolverInfo().m_numIterations = 10;
    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btDefaultMotionState>> motions;
    std::vector<std::unique_ptr<btRigidBody>> bodies;
    std::vector<btRigidBody*> dynamic;
    for (const BodyDesc& d : scene->bodies) {
      std::unique_ptr<btCollisionShape> shape;
      Real thickness = 0;
      switch (d.shape.type) {
        case ShapeType::sphere:
          shape = std::make_unique<btSphereShape>(d.shape.radius);
          thickness = d.shape.radius;
          break;
        case ShapeType::box:
          shape = std::make_unique<btBoxShape>(bt(d.shape.half_extents));
          thickness = d.shape.half_extents.minCoeff();
          break;
        case ShapeType::capsule:
          shape = std::make_unique<btCapsuleShapeZ>(d.shape.radius, 2 * d.shape.half_length);
          thickness = d.shape.radius;
          break;
        case ShapeType::plane:
          shape = std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0);
          break;
        default:  // the high-speed scene uses only the shapes above
          throw std::runtime_error("bench_ccd: shape type not in the high-speed scene");
      }
      shape->setMargin(0.001);
      btVector3 inertia(0, 0, 0);
      const btScalar mass = d.is_static ? 0 : d.mass;
      if (!d.is_static)
        shape->calculateLocalInertia(mass, inertia);
      btTransform t;
      t.setOrigin(bt(d.position));
      t.setRotation(
          btQuaternion(d.orientation.x(), d.orientation.y(), d.orientation.z(), d.orientation.w()));
      auto motion = std::make_unique<btDefaultMotionState>(t);
      btRigidBody::btRigidBodyConstructionInfo info(mass, motion.get(), shape.get(), inertia);
      info.m_friction = 0.2;
      info.m_restitution = 0.8;
      auto body = std::make_unique<btRigidBody>(info);
      if (!d.is_static) {
        body->setLinearVelocity(bt(d.velocity));
        body->setAngularVelocity(bt(d.angular_velocity));
        body->setActivationState(DISABLE_DEACTIVATION);
        if (ccd) {
          body->setCcdMotionThreshold(thickness);
          body->setCcdSweptSphereRadius(0.8 * thickness);
        }
        dynamic.push_back(body.get());
      }
      world.addRigidBody(body.get());
      shapes.push_back(std::move(shape));
      motions.push_back(std::move(motion));
      bodies.push_back(std::move(body));
    }
    for (int k = 0; k < kHighSpeedSteps; ++k)
      world.stepSimulation(scene->world.dt, 0);
    std::vector<Vec3> positions;
    for (btRigidBody* b : dynamic) {
      const btVector3 p = b->getWorldTransform().getOrigin();
      positions.emplace_back(p.x(), p.y(), p.z());
    }
    lost = escaped(positions);
    for (auto& b : bodies)
      world.removeRigidBody(b.get());
  }
  state.counters["escaped"] = lost;
  state.SetLabel(ccd ? "Bullet, swept-sphere ccd" : "Bullet, no ccd");
}
BENCHMARK(BM_HighSpeedBullet)
    ->ArgName("ccd")
    ->Arg(1)
    ->Arg(0)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace tumble::bench

BENCHMARK_MAIN();
