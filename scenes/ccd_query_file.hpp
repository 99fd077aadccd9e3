// The query files of the CCD benchmark of Wang et al. 2021 (`tumble ccd`;
// tests/data/external/ccd-sample-queries/README.md): rows of 7 comma-separated fields, a
// coordinate's numerator and denominator for x, y and z and the query's ground truth, 8 rows per
// query (its 4 vertices at t = 0, then the same 4 at t = 1).
#pragma once

#include <array>
#include <filesystem>
#include <string_view>
#include <vector>

#include "collision/math.hpp"

namespace tumble {

struct CcdQuery {
  std::array<Vec3, 4> start;
  std::array<Vec3, 4> end;
  bool truth = false;  // whether the features touch for some t in [0, 1]
};

// Reads every query of `path`. Throws tumble::Error naming the file and line of the first
// mistake (a field that is not a finite number, a zero denominator, a truth other than 0 or 1 or
// one that differs inside a query, a query cut short), or the file when it cannot be read or is
// not a regular file.
std::vector<CcdQuery> read_ccd_query_file(const std::filesystem::path& path);
// The same from text; `source_name` names it in messages.
std::vector<CcdQuery> read_ccd_query_text(std::string_view text, std::string_view source_name);

}  // namespace tumble
