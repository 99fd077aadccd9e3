#include "apps/ccd_command.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "apps/json_text.hpp"
#include "collision/ccd/mesh_ccd.hpp"
#include "scenes/printable_text.hpp"

namespace tumble::app {
namespace {

struct Query {
  std::array<Vec3, 4> start;
  std::array<Vec3, 4> end;
  bool truth = false;
};

[[noreturn]] void fail(const std::filesystem::path& file, int line, const std::string& what) {
  throw std::runtime_error(file.string() + ":" + std::to_string(line) + ": " + what);
}

// A coordinate num/den: the numerator fits in int64 and the denominator is a power of two up to
// 2^111 (README of the sample), so both parse exactly as doubles and the quotient is exact.
double parse_number(const std::string& text, const std::filesystem::path& file, int line,
                    const char* field) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || !std::isfinite(value))
    fail(file, line,
         std::string("field ") + field + ": expected a number, got '" + printable(text) + "'");
  return value;
}

std::vector<Query> read_queries(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::status(file, ec).type() != std::filesystem::file_type::regular)
    throw std::runtime_error(file.string() + ": cannot open (not a regular file)");
  std::ifstream in(file);
  if (!in)
    throw std::runtime_error(file.string() + ": cannot open");
  static const char* const kFields[7] = {"x_num", "x_den", "y_num", "y_den",
                                         "z_num", "z_den", "truth"};
  std::vector<Query> queries;
  std::string text;
  int line = 0;
  Query current;
  int row = 0;
  while (std::getline(in, text)) {
    ++line;
    if (!text.empty() && text.back() == '\r')
      text.pop_back();
    if (text.empty())
      continue;
    std::array<double, 7> v{};
    std::stringstream ss(text);
    std::string cell;
    int n = 0;
    while (std::getline(ss, cell, ',')) {
      if (n == 7)
        fail(file, line, "expected 7 comma-separated fields, got more");
      v[n] = parse_number(cell, file, line, kFields[n]);
      ++n;
    }
    if (n != 7)
      fail(file, line, "expected 7 comma-separated fields, got " + std::to_string(n));
    for (int k : {1, 3, 5}) {
      if (v[k] == 0)
        fail(file, line, std::string("field ") + kFields[k] + ": denominator is zero");
    }
    if (v[6] != 0 && v[6] != 1)
      fail(file, line, "field truth: expected 0 or 1");
    const Vec3 p(v[0] / v[1], v[2] / v[3], v[4] / v[5]);
    if (row < 4)
      current.start[row] = p;
    else
      current.end[row - 4] = p;
    if (row == 0) {
      current.truth = v[6] == 1;
    } else if (current.truth != (v[6] == 1)) {
      fail(file, line, "field truth: differs from the first row of its query");
    }
    if (++row == 8) {
      queries.push_back(current);
      row = 0;
    }
  }
  if (row != 0)
    fail(file, line, "the file ends inside a query (rows come in groups of 8)");
  return queries;
}

}  // namespace

int ccd_command(const CcdOptions& options) {
  std::vector<Query> queries = read_queries(options.file);
  if (queries.empty())
    throw std::runtime_error(options.file.string() +
                             ": no queries (expected rows of 7 comma-separated fields, 8 rows "
                             "per query)");
  const bool vertex_face = options.kind == "vf";
  if (vertex_face && options.reverse_faces) {
    for (Query& q : queries) {
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
  for (const Query& q : queries) {
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
