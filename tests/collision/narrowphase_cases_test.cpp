// External narrow-phase cases (tests/data/external/narrowphase-cases/cases.json: transcribed from
// the test suites of libccd, FCL, Coal, Jolt and Bullet, with their expected depth, distance,
// normal and witness points). Every case whose shapes are all sphere, box, capsule, halfspace,
// cylinder or convex hull or triangle (as a one-triangle mesh) is run; the others (cone) and
// queries that are not a contact query (time of impact) are skipped and counted.
//
// The file's conventions differ from ours: its normal points from A to B (ours from B to A), its
// boxes are given by half extents (as ours), its halfspace is {x : n.x <= offset} (ours is the
// plane's local z <= 0, so a halfspace becomes a plane rotated to n and moved to n * offset).
// Depth, distance and signed distance are compared with our deepest point's depth (signed
// distance = -depth; a margin larger than the expected distance makes separated pairs report).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/shapes/convex_hull.hpp"
#include "collision/shapes/triangle_mesh.hpp"
#include "tests/collision/oracle.hpp"

namespace tumble::testing {
namespace {

using json = nlohmann::json;

const char* const kCasesPath =
    TUMBLE_SOURCE_DIR "/tests/data/external/narrowphase-cases/cases.json";

// A shape of the file placed by a pose of the file (a halfspace carries its own plane frame).
struct PlacedShape {
  Shape shape;
  Transform local;  // the shape's frame inside the pose the file gives it
};

Vec3 to_vec(const json& j) {
  return {j[0].get<Real>(), j[1].get<Real>(), j[2].get<Real>()};
}

std::optional<PlacedShape> to_shape(const json& j) {
  const std::string type = j.at("type");
  if (type == "sphere")
    return PlacedShape{Shape::sphere(j.at("radius")), {}};
  if (type == "box") {
    return PlacedShape{Shape::box(to_vec(j.at("half_extents"))), {}};
  }
  if (type == "capsule") {
    return PlacedShape{Shape::capsule(j.at("radius"), j.at("half_length")), {}};
  }
  if (type == "halfspace") {
    const Vec3 n = to_vec(j.at("normal")).normalized();
    const Real offset = j.at("offset");
    return PlacedShape{Shape::plane(), {n * offset, Quat::FromTwoVectors(Vec3::UnitZ(), n)}};
  }
  if (type == "cylinder") {
    return PlacedShape{Shape::cylinder(j.at("radius"), j.at("half_height")), {}};
  }
  if (type == "convex_hull") {
    // Simulation vertices: the hull is re-centred on its centre of mass, which the local frame puts
    // back.
    std::vector<Vec3> points;
    for (const json& v : j.at("vertices"))
      points.push_back(to_vec(v));
    auto hull = std::make_shared<const ConvexHull>(ConvexHull::from_points(points));
    const Vec3 offset = hull->centre_of_mass_offset();
    return PlacedShape{Shape::convex_hull(std::move(hull)), {offset, Quat::Identity()}};
  }
  if (type == "triangle" && j.contains("vertices_body")) {
    // A one-triangle mesh (vertices in the body frame; its normal follows their order).
    std::vector<Vec3> v;
    for (const json& p : j.at("vertices_body"))
      v.push_back(to_vec(p));
    return PlacedShape{Shape::triangle_mesh(std::make_shared<const TriangleMesh>(
                           TriangleMesh::build(std::move(v), {{0, 1, 2}}))),
                       {}};
  }
  return std::nullopt;  // cone and triangle-triangle: not supported
}

Quat to_quat(const json& j) {
  return Quat(j[0].get<Real>(), j[1].get<Real>(), j[2].get<Real>(), j[3].get<Real>()).normalized();
}

Transform to_pose(const json& j) {
  Transform pose;
  if (j.contains("position"))
    pose.translation = to_vec(j.at("position"));
  if (j.contains("quat_wxyz"))
    pose.rotation = to_quat(j.at("quat_wxyz"));
  return pose;
}

Transform pose_in_world(const Transform& outer, const Transform& inner) {
  return {outer.apply(inner.translation), outer.rotation * inner.rotation};
}

// One contact query, resolved from a case and one of its variants.
struct Query {
  std::string label;
  PlacedShape a;
  PlacedShape b;
  Transform pose_a;
  Transform pose_b;
  json expected;
  json tolerance;
};

struct Counts {
  int checked = 0;
  int skipped = 0;
};

struct Result {
  Manifold manifold;
  int deepest = -1;
  Real depth = -std::numeric_limits<Real>::infinity();
};

Result run(const Query& q, Real margin) {
  Result r;
  collide(q.a.shape, pose_in_world(q.pose_a, q.a.local), q.b.shape,
          pose_in_world(q.pose_b, q.b.local), margin, r.manifold);
  r.deepest = deepest_point(r.manifold);
  if (r.deepest >= 0)
    r.depth = r.manifold.points[r.deepest].depth;
  return r;
}

Real tolerance_for(const json& tolerance, const char* key, Real value) {
  const Real fallback = 1e-9 * (1 + std::abs(value));
  if (tolerance.is_object() && tolerance.contains(key)) {
    return std::max(tolerance.at(key).get<Real>(), fallback);
  }
  return fallback;
}

// Compares the numeric coordinates of an expected point (some are "any z" strings).
void expect_point(const json& expected, const Vec3& actual, Real tolerance,
                  const std::string& what) {
  for (int k = 0; k < 3; ++k) {
    if (!expected[k].is_number())
      continue;
    EXPECT_NEAR(actual[k], expected[k].get<Real>(), tolerance) << what << " coordinate " << k;
  }
}

// The first "(x,y,z)" written in a prose statement, if any.
std::optional<Vec3> vector_in_prose(const std::string& prose) {
  for (std::size_t open = prose.find('('); open != std::string::npos;
       open = prose.find('(', open + 1)) {
    const char* cursor = prose.c_str() + open + 1;
    Vec3 v;
    bool ok = true;
    for (int k = 0; k < 3 && ok; ++k) {
      char* end = nullptr;
      v[k] = std::strtod(cursor, &end);
      ok = end != cursor && *end == (k < 2 ? ',' : ')');
      cursor = end + 1;
    }
    if (ok)
      return v;
  }
  return std::nullopt;
}

// Checks every expectation the query states.
void check(const Query& q, const std::function<void(const Result&)>& extra = {}) {
  SCOPED_TRACE(q.label);
  const json& e = q.expected;
  Real margin = 0;
  for (const char* key : {"distance", "signed_distance"}) {
    if (e.contains(key) && e.at(key).is_number())
      margin = std::abs(e.at(key).get<Real>()) + 1;
  }
  const Result r = run(q, margin);
  const Manifold& m = r.manifold;
  if (m.count > 0) {
    ASSERT_TRUE(m.normal.allFinite());
    EXPECT_NEAR(m.normal.norm(), 1, 1e-12);
  }
  if (e.contains("intersecting")) {
    EXPECT_EQ(r.depth >= 0, e.at("intersecting").get<bool>()) << "depth " << r.depth;
  }
  const Real depth_tolerance =
      tolerance_for(q.tolerance, "depth", e.value("penetration_depth", Real(0)));
  if (e.contains("penetration_depth")) {
    EXPECT_NEAR(r.depth, e.at("penetration_depth").get<Real>(), depth_tolerance);
  }
  if (e.contains("distance") && e.at("distance").is_number()) {
    const Real distance = e.at("distance");
    EXPECT_NEAR(-r.depth, distance, tolerance_for(q.tolerance, "distance", distance));
  }
  if (e.contains("signed_distance") && e.at("signed_distance").is_number()) {
    const Real signed_distance = e.at("signed_distance");
    EXPECT_NEAR(-r.depth, signed_distance, tolerance_for(q.tolerance, "distance", signed_distance));
  }
  if (r.deepest < 0)
    return;
  if (e.contains("normal")) {
    if (e.at("normal").is_array()) {
      // Theirs from A to B, ours from B to A.
      const Vec3 theirs = to_vec(e.at("normal")).normalized();
      const Real angle = std::atan2((-m.normal).cross(theirs).norm(), (-m.normal).dot(theirs));
      EXPECT_LE(angle, tolerance_for(q.tolerance, "normal_angle_rad", 0))
          << "normal " << m.normal.transpose();
    } else {
      const std::string prose = e.at("normal");
      std::optional<Vec3> documented = vector_in_prose(prose);
      if (documented) {
        // A documented choice for a degenerate case, e.g. FCL's "(-1,0,0)" for coincident
        // sphere and box centres.
        EXPECT_LT((-m.normal - documented->normalized()).norm(), 1e-12) << prose;
      } else if (prose.find("axis") != std::string::npos) {
        EXPECT_NEAR(m.normal.cwiseAbs().maxCoeff(), 1, 1e-12) << "expected an axis direction";
      }
    }
  }
  const ContactPoint& deepest = m.points[r.deepest];
  const Real point_tolerance = std::max(depth_tolerance, 1e-8 * (1 + std::abs(r.depth)));
  if (e.contains("witness_a")) {
    expect_point(e.at("witness_a"), deepest.point_on_a(m.normal), point_tolerance, "witness_a");
  }
  if (e.contains("witness_b")) {
    expect_point(e.at("witness_b"), deepest.point_on_b(m.normal), point_tolerance, "witness_b");
  }
  if (e.contains("contact_point") && e.at("contact_point").is_array()) {
    // Ours may be a face of points; theirs is its centre: compare with the deepest points' mean.
    Vec3 sum = Vec3::Zero();
    int n = 0;
    for (int i = 0; i < m.count; ++i) {
      if (m.points[i].depth >= r.depth - 1e-9) {
        sum += m.points[i].position;
        ++n;
      }
    }
    expect_point(e.at("contact_point"), sum / n, point_tolerance, "contact_point");
  }
  if (extra)
    extra(r);
}

// Merges a variant into its case (variant keys override), as the file's "variants" rule says.
json merged(const json& base, const json& variant) {
  json q = base;
  q.erase("variants");
  for (auto it = variant.begin(); it != variant.end(); ++it)
    q[it.key()] = it.value();
  if (q.contains("recomputed")) {
    // Where the helper recomputed a source's rounded value, the recomputed one is the truth.
    for (auto it = q["recomputed"].begin(); it != q["recomputed"].end(); ++it) {
      q["expected"][it.key()] = it.value();
    }
  }
  return q;
}

// Builds the query of a resolved case, or says why it cannot.
std::optional<Query> resolve(const std::string& label, const json& q, std::string& why_not) {
  Query query;
  query.label = label;
  query.expected = q.value("expected", json::object());
  query.tolerance = q.value("suggested_tolerance", json::object());
  if (q.contains("box_min")) {
    // Jolt's sphere-versus-box cases: A is the box between two corners, B the sphere.
    const Vec3 low = to_vec(q.at("box_min"));
    const Vec3 high = to_vec(q.at("box_max"));
    query.a = {Shape::box((high - low) / 2), {}};
    query.pose_a.translation = (high + low) / 2;
    query.b = {Shape::sphere(q.at("sphere_radius")), {}};
    query.pose_b.translation = to_vec(q.at("sphere_center"));
    return query;
  }
  if (!q.contains("shapes")) {
    why_not = "no shapes";
    return std::nullopt;
  }
  const json& shapes = q.at("shapes");
  const std::optional<PlacedShape> a = to_shape(shapes[0]);
  const std::optional<PlacedShape> b = to_shape(shapes[1]);
  if (!a || !b) {
    why_not = "shape " + (a ? shapes[1] : shapes[0]).at("type").get<std::string>();
    return std::nullopt;
  }
  query.a = *a;
  query.b = *b;
  if (q.contains("poses")) {
    query.pose_a = to_pose(q.at("poses")[0]);
    query.pose_b = to_pose(q.at("poses")[1]);
  }
  if (q.contains("A_pose"))
    query.pose_a = to_pose(q.at("A_pose"));
  if (q.contains("B_pose"))
    query.pose_b = to_pose(q.at("B_pose"));
  if (q.contains("A_position"))
    query.pose_a.translation = to_vec(q.at("A_position"));
  if (q.contains("B_position"))
    query.pose_b.translation = to_vec(q.at("B_position"));
  if (q.contains("A_quat_wxyz"))
    query.pose_a.rotation = to_quat(q.at("A_quat_wxyz"));
  if (q.contains("triangle_translation")) {
    PlacedShape& triangle = query.a.shape.type == ShapeType::mesh ? query.a : query.b;
    triangle.local.translation += to_vec(q.at("triangle_translation"));
  }
  if (q.contains("halfspace_translation")) {
    PlacedShape& halfspace = query.a.shape.type == ShapeType::plane ? query.a : query.b;
    halfspace.local.translation += to_vec(q.at("halfspace_translation"));
  }
  return query;
}

Quat turn_about(const Vec3& axis, Real angle) {
  return Quat(Eigen::AngleAxis<Real>(angle, axis));
}

// FCL repeats its two box-box contact cases with B pre-rotated in its own frame (B is a cube,
// so nothing changes) and with A and B swapped (the normal flips).
void check_fcl_permutations(const Query& base, const std::function<void(const Result&)>& extra,
                            Counts& counts) {
  const Real pi = std::numbers::pi;
  const std::vector<Quat> pre_rotations = {Quat::Identity(),
                                           turn_about(Vec3::UnitX(), pi),
                                           turn_about(Vec3::UnitX(), pi / 2),
                                           turn_about(Vec3::UnitX(), 1.5 * pi),
                                           turn_about(Vec3::UnitY(), pi / 2),
                                           turn_about(Vec3::UnitY(), 1.5 * pi)};
  for (std::size_t k = 0; k < pre_rotations.size(); ++k) {
    Query q = base;
    q.pose_b.rotation = base.pose_b.rotation * pre_rotations[k];
    q.label = base.label + " pre-rotation " + std::to_string(k);
    check(q, extra);
    ++counts.checked;
    Query swapped = q;
    std::swap(swapped.a, swapped.b);
    std::swap(swapped.pose_a, swapped.pose_b);
    swapped.label += " swapped";
    swapped.expected["normal"] = -to_vec(q.expected.at("normal"));
    check(swapped, extra);
    ++counts.checked;
  }
}

// libccd's boolean sweeps: shape A moves in steps past B; intersecting exactly on the stated
// range. The exact-touching steps the source does not assert are left out here too.
void check_sweeps(const json& c, Counts& counts) {
  const json& sweeps = c.at("sweeps");
  const auto intersects = [](const Shape& a, const Transform& pa, const Shape& b,
                             const Transform& pb) {
    Manifold m;
    return collide(a, pa, b, pb, 0, m) > 0;
  };
  for (std::size_t s = 0; s < sweeps.size(); ++s) {
    const json& sweep = sweeps[s];
    const std::optional<PlacedShape> a = to_shape(sweep.at("shapes")[0]);
    const std::optional<PlacedShape> b = to_shape(sweep.at("shapes")[1]);
    if (!a || !b) {
      counts.skipped += 3 * 100;  // X, Y and Z sweeps of 100 steps
      continue;
    }
    const Transform pose_b = to_pose(sweep.at("B_pose"));
    SCOPED_TRACE("sweep " + std::to_string(s));
    if (sweep.contains("A_rotation")) {
      // Sweep 2: A at a fixed place, turned by k pi / 20 about +Y; apart only when aligned.
      for (int k = 0; k < 30; ++k) {
        const Transform pose_a{to_vec(sweep.at("A_position")),
                               turn_about(Vec3::UnitY(), k * std::numbers::pi / 20)};
        EXPECT_EQ(intersects(a->shape, pose_a, b->shape, pose_b), k != 0 && k != 10 && k != 20)
            << "k " << k;
        ++counts.checked;
      }
      continue;
    }
    const Vec3 start = to_vec(sweep.at("A_start"));
    const Vec3 step = to_vec(sweep.at("step"));
    const int steps = sweep.at("steps");
    const Quat rotation =
        sweep.contains("A_quat_wxyz") ? to_quat(sweep.at("A_quat_wxyz")) : Quat::Identity();
    const Real start_along = start.x();
    const Real step_along = step.x();
    struct Run {
      int axis;
      Real scale;
      Vec3 offset;  // the start's other coordinates
    };
    std::vector<Run> runs;
    if (s == 0) {
      // Along X, Y and Z; the same scaled by 1/10; and along X from y = -0.1.
      for (int axis = 0; axis < 3; ++axis) {
        runs.push_back({axis, 1, Vec3::Zero()});
        runs.push_back({axis, 0.1, Vec3::Zero()});
      }
      runs.push_back({0, 1, Vec3(0, -0.1, 0)});
    } else if (s == 3) {
      for (int axis = 0; axis < 3; ++axis)
        runs.push_back({axis, 1, Vec3::Zero()});
    } else {
      runs.push_back({0, 1, Vec3(0, start.y(), start.z())});
    }
    for (const Run& run : runs) {
      Shape shape_a = a->shape;
      Shape shape_b = b->shape;
      shape_a.half_extents *= run.scale;
      shape_a.radius *= run.scale;
      shape_b.half_extents *= run.scale;
      shape_b.radius *= run.scale;
      for (int i = 0; i < steps; ++i) {
        Vec3 position = run.offset;
        position[run.axis] = (start_along + i * step_along) * run.scale;
        const bool hit = intersects(shape_a, {position, rotation}, shape_b, pose_b);
        const Real x = std::abs(start_along + i * step_along);
        if (s == 0) {
          if (i == 35 || i == 65)
            continue;  // exact touching, not asserted by the source
          EXPECT_EQ(hit, 35 < i && i < 65)
              << "axis " << run.axis << " scale " << run.scale << " i " << i;
        } else if (s == 1) {
          EXPECT_EQ(hit, x < 0.5 * std::numbers::sqrt2 + 1) << "i " << i;
        } else {
          EXPECT_EQ(hit, 42 <= i && i <= 58) << "axis " << run.axis << " i " << i;
        }
        ++counts.checked;
      }
    }
  }
}

TEST(NarrowPhaseCases, ExternalCasesAgreeWithinTheirTolerances) {
  std::ifstream file(kCasesPath);
  ASSERT_TRUE(file.good()) << "cannot open " << kCasesPath;
  const json root = json::parse(file);
  ASSERT_TRUE(root.contains("conventions"));
  // The conventions this test translates from; fail loudly if the file changes them.
  ASSERT_NE(root["conventions"]["expected"]["normal"].get<std::string>().find("from shape A"),
            std::string::npos);
  ASSERT_NE(root["conventions"]["shapes"]["box"].get<std::string>().find("half_extents"),
            std::string::npos);

  const Real sqrt2 = std::numbers::sqrt2;
  // Their contact-point statements that are prose rather than numbers.
  const std::map<std::string, std::function<void(const Result&)>> constraints = {
      {"fcl_boxbox_edge_on_face_all_contacts",
       [&](const Result& r) {
         for (int i = 0; i < r.manifold.count; ++i) {
           const ContactPoint& p = r.manifold.points[i];
           if (p.depth < r.depth - 1e-9)
             continue;
           EXPECT_NEAR(p.position.z(), -sqrt2 / 4, 1e-12);
           EXPECT_NEAR(p.position.x(), 0, 1e-12);
           EXPECT_LE(std::abs(p.position.y()), 0.5 + 1e-12);
         }
       }},
      {"fcl_boxbox_edge_on_edge_cull",
       [&](const Result& r) {
         const Real y = -(sqrt2 / 2) * std::sin(std::numbers::pi / 8);
         for (int i = 0; i < r.manifold.count; ++i) {
           const ContactPoint& p = r.manifold.points[i];
           if (p.depth < r.depth - 1e-9)
             continue;
           EXPECT_NEAR(p.position.z(), -0.25 - r.depth / 2, 1e-12);
           EXPECT_NEAR(p.position.y(), y, 1e-12);
           EXPECT_LE(std::abs(p.position.x()), sqrt2 / 2 + y + 1e-12);
         }
       }},
  };

  std::map<std::string, Counts> per_case;
  std::map<std::string, std::string> skip_reasons;
  for (const json& c : root.at("cases")) {
    const std::string id = c.at("id");
    Counts& counts = per_case[id];
    const std::string query_kind = c.value("query", "");
    if (query_kind.find("linear_cast") != std::string::npos) {
      counts.skipped += int(c.value("variants", json::array()).size());
      skip_reasons[id] = "time of impact, not a contact query";
      continue;
    }
    if (c.contains("sweeps")) {
      check_sweeps(c, counts);
      if (counts.skipped > 0)
        skip_reasons[id] = "cylinder sweeps";
      continue;
    }
    if (c.contains("generator")) {
      // Bullet's grid of sphere pairs.
      const json& g = c.at("generator");
      int generated = 0;
      for (int j = 1; j <= 4; ++j) {
        for (int rb = 1; rb <= 4; ++rb) {
          for (int i = -5; i <= 4; ++i) {
            for (int z = -5; z <= 4; ++z) {
              if (z == i)
                continue;
              ++generated;
              const Shape a = Shape::sphere(j);
              const Shape b = Shape::sphere(0.1 * rb);
              const Transform pose_a{Vec3(0, i, 0), Quat::Identity()};
              const Transform pose_b{Vec3(0, z, 0), Quat::Identity()};
              const Real expected = std::abs(i - z) - j - 0.1 * rb;
              Manifold m;
              ASSERT_EQ(collide(a, pose_a, b, pose_b, std::abs(expected) + 1, m), 1);
              EXPECT_NEAR(-m.points[0].depth, expected, 1e-12);
              // pointOnA = pointOnB + distance * normalBtoA
              const Vec3 on_a = m.points[0].point_on_a(m.normal);
              const Vec3 on_b = m.points[0].point_on_b(m.normal);
              EXPECT_LT((on_a - (on_b + m.normal * expected)).norm(), 1e-12);
              EXPECT_NEAR(signed_distance_to_shape(a, pose_a, on_a), 0, 1e-12);
              EXPECT_NEAR(signed_distance_to_shape(b, pose_b, on_b), 0, 1e-12);
              ++counts.checked;
            }
          }
        }
      }
      EXPECT_EQ(generated, g.at("count").get<int>());
      continue;
    }
    std::vector<json> variants;
    if (c.contains("variants")) {
      for (const json& v : c.at("variants"))
        variants.push_back(merged(c, v));
    } else {
      variants.push_back(merged(c, json::object()));
    }
    const auto extra =
        constraints.count(id) ? constraints.at(id) : std::function<void(const Result&)>{};
    for (std::size_t v = 0; v < variants.size(); ++v) {
      std::string why_not;
      const std::optional<Query> q =
          resolve(id + " variant " + std::to_string(v), variants[v], why_not);
      if (!q) {
        ++counts.skipped;
        std::string& reasons = skip_reasons[id];
        if (reasons.find(why_not) == std::string::npos) {
          reasons += (reasons.empty() ? "" : ", ") + why_not;
        }
        continue;
      }
      if (constraints.count(id)) {
        check_fcl_permutations(*q, extra, counts);
      } else {
        check(*q, extra);
        ++counts.checked;
      }
    }
  }

  int used = 0;
  int partial = 0;
  int skipped = 0;
  int checked = 0;
  int skipped_queries = 0;
  for (const auto& [id, counts] : per_case) {
    checked += counts.checked;
    skipped_queries += counts.skipped;
    if (counts.checked == 0) {
      ++skipped;
    } else if (counts.skipped > 0) {
      ++partial;
    } else {
      ++used;
    }
  }
  std::printf(
      "[ stats    ] narrowphase-cases: %zu cases: %d used, %d partly used, %d skipped; %d queries "
      "checked, %d skipped\n",
      per_case.size(), used, partial, skipped, checked, skipped_queries);
  for (const auto& [id, reason] : skip_reasons) {
    std::printf("[ stats    ]   %-44s %s %d skipped (%s)\n", id.c_str(),
                per_case[id].checked ? "partly:" : "whole: ", per_case[id].skipped, reason.c_str());
  }
  EXPECT_GT(checked, 2000);
}

}  // namespace
}  // namespace tumble::testing
