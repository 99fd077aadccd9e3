// `tumble ccd FILE.csv --kind vf|ee`: runs the exact mesh-feature CCD (collision/ccd/mesh_ccd)
// on every query of a file in the format of the CCD benchmark of Wang et al. 2021 (8 rows of
// rational coordinates per query plus its ground truth;
// tests/data/external/ccd-sample-queries/README.md) and prints one JSON object: queries, true/false
// positives/negatives, seconds_per_query, and the parameter boxes per query (mean, median, largest,
// and which query had the most).
#pragma once

#include <filesystem>
#include <string>

namespace tumble::app {

struct CcdOptions {
  std::filesystem::path file;
  std::string kind;            // "vf" or "ee"
  bool reverse_faces = false;  // vertex-face: swap the triangle's second and third vertices
  double tolerance = 1e-6;     // m, MeshCcdSettings::tolerance
};

// Returns 0 on success; a malformed file throws std::runtime_error naming file and line.
int ccd_command(const CcdOptions& options);

}  // namespace tumble::app
