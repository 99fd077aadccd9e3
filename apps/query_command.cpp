// Answers each query with the narrow phase's manifold: the deepest point gives the signed
// distance and the witness points, computed with the query's margin (default 10 m) so that
// apart shapes report their distance too. The status says where the answer came from
// ("status_source": "narrow_phase"); convex pairs move to GJK/EPA when that lands (branch
// `narrow`), and a new kind (time of impact) adds a case to answer_query.
//
// Statuses: "penetrating" (distance < 0), "touching" (distance 0), "separated" (distance > 0),
// "beyond_margin" (no contact within the margin: distance null), "unsupported" (a pair the
// narrow phase has no function for yet, or two static shapes such as mesh and mesh).
#include "apps/query_command.hpp"

#include <iostream>
#include <sstream>

#include "apps/number_format.hpp"
#include "collision/narrow_phase.hpp"

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

// Pairs the dispatch table answers today; the rest report "unsupported" instead of a silent
// "beyond_margin".
bool supported(ShapeType type) {
  return type != ShapeType::cylinder && type != ShapeType::hull;
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
  const auto compound_supported = [](const Shape& s) {
    if (s.type != ShapeType::compound)
      return supported(s.type);
    return true;  // parts are checked when the compound is built
  };
  if (!compound_supported(q.a) || !compound_supported(q.b) || both_static(q.a.type, q.b.type)) {
    out << "\"status\":\"unsupported\",\"status_source\":\"narrow_phase\",\"distance\":null,"
           "\"normal\":null,\"point_a\":null,\"point_b\":null,\"contacts\":[]}";
    return out.str();
  }
  Manifold m;
  const int count = collide(q.a, q.pose_a, q.b, q.pose_b, q.margin, m);
  if (count == 0) {
    out << "\"status\":\"beyond_margin\",\"status_source\":\"narrow_phase\",\"margin\":";
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
  const char* status = distance < 0 ? "penetrating" : (distance > 0 ? "separated" : "touching");
  out << "\"status\":\"" << status << "\",\"status_source\":\"narrow_phase\",\"distance\":";
  write_number(out, distance);
  out << ",\"normal\":";
  write_vector(out, m.normal);
  out << ",\"point_a\":";
  write_vector(out, d.point_on_a(m.normal));
  out << ",\"point_b\":";
  write_vector(out, d.point_on_b(m.normal));
  out << ",\"contacts\":[";
  for (int i = 0; i < count; ++i) {
    const ContactPoint& p = m.points[i];
    out << (i ? "," : "") << "{\"position\":";
    write_vector(out, p.position);
    out << ",\"depth\":";
    write_number(out, p.depth);
    out << ",\"feature\":[" << p.feature.a << ',' << p.feature.b << "]}";
  }
  out << "]}";
  return out.str();
}

}  // namespace

std::string answer_query(const ShapeQuery& query) {
  switch (query.kind) {
    case QueryKind::contact:
      return answer_contact(query);
  }
  return {};
}

int query_command(const std::filesystem::path& file) {
  const std::vector<ShapeQuery> queries = load_query_file(file);
  for (const ShapeQuery& q : queries)
    std::cout << answer_query(q) << '\n';
  std::cout.flush();
  return 0;
}

}  // namespace tumble::app
