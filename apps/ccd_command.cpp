#include "apps/ccd_command.hpp"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "apps/json_text.hpp"
#include "collision/ccd/mesh_ccd.hpp"
#include "scenes/ccd_query_file.hpp"

namespace tumble::app {

int ccd_command(const CcdOptions& options) {
  std::vector<CcdQuery> queries = read_ccd_query_file(options.file);
  if (queries.empty())
    throw std::runtime_error(options.file.string() +
                             ": no queries (expected rows of 7 comma-separated fields, 8 rows "
                             "per query)");
  const bool vertex_face = options.kind == "vf";
  if (vertex_face && options.reverse_faces) {
    for (CcdQuery& q : queries) {
      std::swap(q.start[2], q.start[3]);
      std::swap(q.end[2], q.end[3]);
    }
  }
  MeshCcdSettings settings;
  settings.tolerance = options.tolerance;
  std::int64_t tp = 0, fp = 0, tn = 0, fn = 0, capped = 0;
  // Parameter boxes per query (MeshCcdResult::boxes): the work, free of the machine's load. A few
  // queries can dominate the time (docs/ccd.md, "Mesh features"), so the largest is named.
  std::vector<std::int32_t> boxes;
  boxes.reserve(queries.size());
  const auto begin = std::chrono::steady_clock::now();
  for (const CcdQuery& q : queries) {
    const MeshCcdResult r = vertex_face ? vertex_face_ccd(q.start, q.end, settings)
                                        : edge_edge_ccd(q.start, q.end, settings);
    boxes.push_back(r.boxes);
    capped += r.status == MeshCcdStatus::max_iterations ? 1 : 0;
    if (r.hit())
      (q.truth ? tp : fp) += 1;
    else
      (q.truth ? fn : tn) += 1;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  nlohmann::json out;
  out["file"] = options.file.string();
  out["kind"] = options.kind;
  out["reverse_faces"] = options.reverse_faces;
  out["tolerance"] = options.tolerance;
  out["queries"] = queries.size();
  out["true_positives"] = tp;
  out["false_positives"] = fp;
  out["true_negatives"] = tn;
  out["false_negatives"] = fn;
  out["max_iterations"] = capped;
  out["seconds_per_query"] = queries.empty() ? 0.0 : seconds / double(queries.size());
  if (!boxes.empty()) {
    const auto largest = std::max_element(boxes.begin(), boxes.end());
    // 1-based, as the file's line numbers: query i starts on line 8 (i - 1) + 1.
    out["most_boxes_query"] = largest - boxes.begin() + 1;
    out["boxes_max"] = *largest;
    std::int64_t total = 0;
    for (std::int32_t b : boxes)
      total += b;
    out["boxes_mean"] = double(total) / double(boxes.size());
    std::nth_element(boxes.begin(), boxes.begin() + boxes.size() / 2, boxes.end());
    out["boxes_median"] = boxes[boxes.size() / 2];
  }
  std::cout << json_text(out) << "\n";
  return 0;
}

}  // namespace tumble::app
