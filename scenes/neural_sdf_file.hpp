// The weights file of a neural SDF (docs/sdf.md, "Neural SDFs"), JSON as
// examples/python/fit_neural_sdf.py writes it:
//   {"format": "tumble-neural-sdf", "version": 1, "frequencies": 2, "offset": [x, y, z],
//    "scale": s, "bounds": {"min": [...], "max": [...]},
//    "layers": [{"weights": [[...], ...], "bias": [...], "activation": "softplus", "beta": 20},
//               ..., {"weights": [[...]], "bias": [b], "activation": "none"}]}
// Weights are rows of outputs (PyTorch's Linear.weight). Read with the scene loader's strict
// readers (JSON is YAML), so a mistake names the file, line and field.
#pragma once

#include <filesystem>
#include <string_view>

#include "collision/sdf/neural_sdf.hpp"

namespace tumble {

NeuralSdfDescription load_neural_sdf_file(const std::filesystem::path& path);
NeuralSdfDescription load_neural_sdf_string(std::string_view text, std::string_view source_name);

}  // namespace tumble
