// The CCD benchmark's query reader (scenes/ccd_query_file.hpp): queries with finite vertices, or
// tumble::Error naming the line. Each query read is then run through the mesh-feature CCD.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "collision/ccd/mesh_ccd.hpp"
#include "scenes/ccd_query_file.hpp"
#include "tumble/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::vector<tumble::CcdQuery> queries;
  try {
    queries = tumble::read_ccd_query_text(text, "fuzz.csv");
  } catch (const tumble::Error&) {
    return 0;
  }
  tumble::MeshCcdSettings settings;
  settings.max_boxes = 2000;  // a bounded search per query: the fuzzer looks for faults, not hits
  for (std::size_t i = 0; i < queries.size() && i < 4; ++i) {
    const tumble::CcdQuery& q = queries[i];
    for (const tumble::Vec3& v : q.start)
      if (!v.allFinite())
        std::abort();
    for (const tumble::Vec3& v : q.end)
      if (!v.allFinite())
        std::abort();
    const tumble::MeshCcdResult vf = tumble::vertex_face_ccd(q.start, q.end, settings);
    const tumble::MeshCcdResult ee = tumble::edge_edge_ccd(q.start, q.end, settings);
    for (const tumble::MeshCcdResult& r : {vf, ee}) {
      if (!(r.time_of_impact >= 0 && r.time_of_impact <= 1))
        std::abort();
    }
  }
  return 0;
}
