// Answers each query (docs/scene-format.md, "Query files"):
//   contact, convex pair (sphere, box, capsule, cylinder, hull on both sides): GJK
//     (collision/narrow_phase/gjk_epa/gjk.hpp) in a pair-local frame (poses relative to a's
//     position) gives the signed distance, the normal and the witness points; when the cores
//     intersect, EPA (collision/narrow_phase/gjk_epa/epa.hpp) gives the depth. "status" is the GJK
//     status name ("separated", "max_iterations", "degenerate") or, when GJK found the cores
//     intersecting, the EPA status name ("converged", ...); "status_source" is "gjk" or "epa".
//   contact, a pair with a plane, mesh or compound: the narrow phase's manifold, whose deepest
//     point gives the distance and witnesses ("status_source": "manifold"; statuses
//     "penetrating", "touching", "separated", "beyond_margin", "unsupported" for two static
//     shapes such as mesh and mesh). A pair with a field adds "refinements" and
//     "refinements_capped": its surface walks, and those that stopped at their step cap, and
//     "deepest_walk": "converged" or "capped", the status of the walk that ended deepest.
//   Both list the manifold's "contacts" from collide() with the query's margin (default 10 m,
//     so apart shapes are listed too), and "state" (penetrating / touching / separated) from the
//     sign of the distance.
//   toi: conservative advancement (collision/ccd/conservative_advancement.hpp) over the
//     query's duration with each shape moving at constant velocity and angular velocity, or with
//     `method: sat` the time-extended SAT (collision/ccd/swept_hull_sat.hpp; boxes and hulls).
#include "apps/query_command.hpp"

#include <iostream>
#include <sstream>

#include "apps/number_format.hpp"
#include "apps/scene_access.hpp"
#include "collision/ccd/conservative_advancement.hpp"
#include "collision/ccd/swept_hull_sat.hpp"
#include "collision/narrow_phase/gjk_epa/epa.hpp"
#include "collision/narrow_phase/gjk_epa/gjk.hpp"
#include "collision/narrow_phase/narrow_phase.hpp"

namespace tumble::app {
namespace {

void write_vector(std::ostream& out, const Vec3& v) {
  out << '[';
  write_number(out, v.x());
  out << ',';
  write_number(out, v.y());
  out << ',';
  write_number(out, v.z());
  out << ']';
}

void write_string(std::ostream& out, const std::string& s) {
  out << '"';
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out << '\\' << c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      static const char* const hex = "0123456789abcdef";
      out << "\\u00" << hex[(c >> 4) & 0xf] << hex[c & 0xf];
    } else {
      out << c;
    }
  }
  out << '"';
}

void write_quaternion(std::ostream& out, const Quat& q) {  // w first, as in scene files
  out << '[';
  write_number(out, q.w());
  out << ',';
  write_number(out, q.x());
  out << ',';
  write_number(out, q.y());
  out << ',';
  write_number(out, q.z());
  out << ']';
}

bool convex(ShapeType type) {
  return type == ShapeType::sphere || type == ShapeType::box || type == ShapeType::capsule ||
         type == ShapeType::cylinder || type == ShapeType::hull;
}

const char* state_of(Real distance) {
  return distance < 0 ? "penetrating" : (distance > 0 ? "separated" : "touching");
}

void write_contacts(std::ostream& out, const Manifold& m, int count) {
  out << ",\"contacts\":[";
  for (int i = 0; i < count; ++i) {
    const ContactPoint& p = m.points[i];
    out << (i ? "," : "") << "{\"position\":";
    write_vector(out, p.position);
    out << ",\"depth\":";
    write_number(out, p.depth);
    out << ",\"feature\":[" << p.feature.a << ',' << p.feature.b << "]}";
  }
  out << ']';
}

// GJK, then EPA when the cores intersect, in the frame centred on a's position (distances far
// from the origin keep their precision); points are moved back to the world.
void write_convex_answer(std::ostream& out, const ShapeQuery& q) {
  const Vec3 origin = q.pose_a.translation;
  Transform local_a = q.pose_a;
  local_a.translation = Vec3::Zero();
  Transform local_b = q.pose_b;
  local_b.translation -= origin;
  const ConvexSupport a = ConvexSupport::of(q.a, local_a);
  const ConvexSupport b = ConvexSupport::of(q.b, local_b);
  const GjkResult g = gjk(a, b);
  const char* status = gjk_status_name(g.status);
  const char* source = "gjk";
  Real distance = g.distance;
  Vec3 normal = g.normal;
  Vec3 point_a = g.point_a;
  Vec3 point_b = g.point_b;
  if (g.status == GjkStatus::intersecting) {
    const EpaResult e = epa(a, b, g);
    status = epa_status_name(e.status);
    source = "epa";
    distance = -e.depth;
    normal = e.normal;
    point_a = e.point_a;
    point_b = e.point_b;
  }
  out << "\"status\":\"" << status << "\",\"status_source\":\"" << source << "\",\"state\":\""
      << state_of(distance) << "\",\"distance\":";
  write_number(out, distance);
  out << ",\"normal\":";
  write_vector(out, normal);
  out << ",\"point_a\":";
  write_vector(out, point_a + origin);
  out << ",\"point_b\":";
  write_vector(out, point_b + origin);
  Manifold m;
  const int count = collide(q.a, q.pose_a, q.b, q.pose_b, q.margin, m);
  write_contacts(out, m, count);
}

bool both_static(ShapeType a, ShapeType b) {
  const auto fixed = [](ShapeType t) { return t == ShapeType::plane || t == ShapeType::mesh; };
  return fixed(a) && fixed(b);
}

std::string answer_contact(const ShapeQuery& q) {
  std::ostringstream out;
  out << "{\"name\":";
  write_string(out, q.name);
  out << ",\"kind\":\"contact\",";
  if (convex(q.a.type) && convex(q.b.type)) {
    write_convex_answer(out, q);
    out << '}';
    return out.str();
  }
  if (both_static(q.a.type, q.b.type)) {
    out << "\"status\":\"unsupported\",\"status_source\":\"manifold\",\"state\":null,"
           "\"distance\":null,\"normal\":null,\"point_a\":null,\"point_b\":null,\"contacts\":[]}";
    return out.str();
  }
  Manifold m;
  const int count = collide(q.a, q.pose_a, q.b, q.pose_b, q.margin, m);
  if (count == 0) {
    out << "\"status\":\"beyond_margin\",\"status_source\":\"manifold\",\"state\":null,"
           "\"margin\":";
    write_number(out, q.margin);
    out << ",\"distance\":null,\"normal\":null,\"point_a\":null,\"point_b\":null,\"contacts\":[]}";
    return out.str();
  }
  int deepest = 0;
  for (int i = 1; i < count; ++i)
    if (m.points[i].depth > m.points[deepest].depth)
      deepest = i;
  const ContactPoint& d = m.points[deepest];
  const Real distance = -d.depth;
  out << "\"status\":\"" << state_of(distance) << "\",\"status_source\":\"manifold\",\"state\":\""
      << state_of(distance) << "\",\"distance\":";
  write_number(out, distance);
  out << ",\"normal\":";
  write_vector(out, m.normal);
  out << ",\"point_a\":";
  write_vector(out, d.point_on_a(m.normal));
  out << ",\"point_b\":";
  write_vector(out, d.point_on_b(m.normal));
  if (q.a.type == ShapeType::sdf || q.b.type == ShapeType::sdf) {
    // The surface walks of a field pair, and those stopped at their step cap (docs/sdf.md).
    out << ",\"refinements\":" << m.refined << ",\"refinements_capped\":" << m.refine_capped
        << ",\"deepest_walk\":\"" << (m.deepest_walk_capped ? "capped" : "converged") << '"';
  }
  write_contacts(out, m, count);
  out << '}';
  return out.str();
}

void write_pose(std::ostream& out, const Transform& pose) {
  out << "{\"position\":";
  write_vector(out, pose.translation);
  out << ",\"orientation\":";
  write_quaternion(out, pose.rotation);
  out << '}';
}

// Conservative advancement over s in [0, 1] = [0, duration] s, in the frame centred on a's
// starting position. The tolerance is tight (1 nm: the time error is about tolerance / closing
// speed) because a query is answered once, not every step; the iteration cap is raised to match.
std::string answer_toi(const ShapeQuery& q) {
  std::ostringstream out;
  out << "{\"name\":";
  write_string(out, q.name);
  out << ",\"kind\":\"toi\",";
  if (both_static(q.a.type, q.b.type)) {
    out << "\"status\":\"unsupported\",\"toi\":null,\"duration\":";
    write_number(out, q.duration);
    out << ",\"normal\":null,\"pose_a\":null,\"pose_b\":null}";
    return out.str();
  }
  const Vec3 origin = q.pose_a.translation;
  Transform start_a = q.pose_a;
  start_a.translation = Vec3::Zero();
  Transform start_b = q.pose_b;
  start_b.translation -= origin;
  const RigidMotion motion_a = RigidMotion::from_velocity(start_a, q.velocity_a * q.duration,
                                                          q.angular_velocity_a * q.duration);
  const RigidMotion motion_b = RigidMotion::from_velocity(start_b, q.velocity_b * q.duration,
                                                          q.angular_velocity_b * q.duration);
  ToiSettings settings;
  settings.tolerance = Real(1e-9);
  settings.max_iterations = 1000;
  const bool sat = q.method == ToiMethod::sat;
  const ToiResult r = sat ? time_extended_sat(q.a, motion_a, q.b, motion_b, settings)
                          : time_of_impact(q.a, motion_a, q.b, motion_b, settings);
  out << "\"method\":\"" << (sat ? "sat" : "advancement") << "\",";
  out << "\"status\":\"" << toi_status_name(r.status) << "\",\"toi\":";
  if (r.hit()) {
    write_number(out, r.time_of_impact * q.duration);
  } else {
    out << "null";
  }
  out << ",\"duration\":";
  write_number(out, q.duration);
  if (r.status == ToiStatus::max_iterations) {
    out << ",\"safe_until\":";  // no contact before this time (s)
    write_number(out, r.time_of_impact * q.duration);
  }
  if (r.hit()) {
    Transform at_a = motion_a.at(r.time_of_impact);
    Transform at_b = motion_b.at(r.time_of_impact);
    at_a.translation += origin;
    at_b.translation += origin;
    out << ",\"distance\":";
    write_number(out, r.distance);
    out << ",\"normal\":";
    write_vector(out, r.normal);
    out << ",\"pose_a\":";
    write_pose(out, at_a);
    out << ",\"pose_b\":";
    write_pose(out, at_b);
    out << '}';
  } else {
    out << ",\"normal\":null,\"pose_a\":null,\"pose_b\":null}";
  }
  return out.str();
}

}  // namespace

std::string answer_query(const ShapeQuery& query) {
  switch (query.kind) {
    case QueryKind::contact:
      return answer_contact(query);
    case QueryKind::toi:
      return answer_toi(query);
  }
  return {};
}

int query_command(const std::filesystem::path& file) {
  const std::vector<ShapeQuery> queries = load_query_file(file, scene_load_options());
  for (const ShapeQuery& q : queries)
    std::cout << answer_query(q) << '\n';
  std::cout.flush();
  return 0;
}

}  // namespace tumble::app
