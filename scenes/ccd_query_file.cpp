#include "scenes/ccd_query_file.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "engine/printable_text.hpp"
#include "scenes/scene_files.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

[[noreturn]] void fail(std::string_view source, int line, const std::string& what) {
  throw Error(std::string(source) + ":" + std::to_string(line) + ": " + what);
}

// A coordinate num/den: the numerator fits in int64 and the denominator is a power of two up to
// 2^111 (README of the sample), so both parse exactly as doubles and the quotient is exact.
double parse_number(const std::string& text, std::string_view source, int line, const char* field) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || !std::isfinite(value))
    fail(source, line,
         std::string("field ") + field + ": expected a number, got '" + printable(text) + "'");
  return value;
}

}  // namespace

std::vector<CcdQuery> read_ccd_query_text(std::string_view text, std::string_view source) {
  static const char* const kFields[7] = {"x_num", "x_den", "y_num", "y_den",
                                         "z_num", "z_den", "truth"};
  std::vector<CcdQuery> queries;
  std::istringstream in{std::string(text)};
  std::string row_text;
  int line = 0;
  CcdQuery current;
  int row = 0;
  while (std::getline(in, row_text)) {
    ++line;
    if (!row_text.empty() && row_text.back() == '\r')
      row_text.pop_back();
    if (row_text.empty())
      continue;
    std::array<double, 7> v{};
    std::istringstream cells(row_text);
    std::string cell;
    int n = 0;
    while (std::getline(cells, cell, ',')) {
      if (n == 7)
        fail(source, line, "expected 7 comma-separated fields, got more");
      v[n] = parse_number(cell, source, line, kFields[n]);
      ++n;
    }
    if (n != 7)
      fail(source, line, "expected 7 comma-separated fields, got " + std::to_string(n));
    for (int k : {1, 3, 5}) {
      if (v[k] == 0)
        fail(source, line, std::string("field ") + kFields[k] + ": denominator is zero");
    }
    if (v[6] != 0 && v[6] != 1)
      fail(source, line, "field truth: expected 0 or 1");
    const Vec3 p(v[0] / v[1], v[2] / v[3], v[4] / v[5]);
    if (!p.allFinite())
      fail(source, line,
           "the coordinates overflow (a numerator over its denominator is not finite)");
    if (row < 4)
      current.start[row] = p;
    else
      current.end[row - 4] = p;
    if (row == 0) {
      current.truth = v[6] == 1;
    } else if (current.truth != (v[6] == 1)) {
      fail(source, line, "field truth: differs from the first row of its query");
    }
    if (++row == 8) {
      queries.push_back(current);
      row = 0;
    }
  }
  if (row != 0)
    fail(source, line, "the file ends inside a query (rows come in groups of 8)");
  return queries;
}

std::vector<CcdQuery> read_ccd_query_file(const std::filesystem::path& path) {
  std::string why;
  const std::optional<std::string> text = regular_file_text(path, why);
  if (!text)
    throw Error(printable_name(path.string()) + ": cannot open (" + why + ")");
  return read_ccd_query_text(*text, path.string());
}

}  // namespace tumble
