// Neural SDF weights files (scenes/neural_sdf_file.hpp).
#include "scenes/neural_sdf_file.hpp"

#include "scenes/yaml_reader.hpp"

namespace tumble {
namespace scene_yaml {
namespace {

constexpr std::array<std::string_view, 7> kNeuralKeys{"format", "version", "frequencies", "offset",
                                                      "scale",  "bounds",  "layers"};
constexpr std::array<std::string_view, 2> kBoundsKeys{"min", "max"};
constexpr std::array<std::string_view, 4> kLayerKeys{"weights", "bias", "activation", "beta"};
constexpr RealSpec kWeight{"a finite number", "-1e12 to 1e12", -1e12, 1e12};
constexpr RealSpec kScale{"a positive length in metres", "1e-9 to 1e9", 1e-9, 1e9};
constexpr RealSpec kBeta{"a positive sharpness", "greater than 0, at most 1e6", 0, 1e6, true};
constexpr IntSpec kFrequencies{"a whole number of bands", "0 to 12", 0, NeuralSdf::kMaxFrequencies};
constexpr IntSpec kVersion{"the format version", "1", 1, 1};

}  // namespace

NeuralSdfDescription Loader::load_neural(std::string_view text) const {
  DocumentBuilder doc;
  const Node& root = parse(text, doc, "layers");
  const YAML::Mark start = text_start();
  const Fields f = read_map(root, mark_or(root, start), "", "a neural SDF weights file", false);
  check_known(f, kNeuralKeys);
  const auto require = [&](std::string_view key) -> const Entry& {
    const Entry* x = f.find(key);
    if (x == nullptr)
      fail(f.mark, std::string(key), "missing required field '" + std::string(key) + "'");
    return *x;
  };
  const std::string format = read_word(require("format"), "format", "a format name");
  if (format != "tumble-neural-sdf")
    fail(require("format").mark(), "format",
         "expected tumble-neural-sdf, got '" + printable(format) + "'");
  (void)read_int(require("version"), "version", kVersion);
  NeuralSdfDescription d;
  d.frequencies = static_cast<int>(read_int(require("frequencies"), "frequencies", kFrequencies));
  d.offset = read_vector<3>(require("offset"), "offset", "[x, y, z]", "metres", kCoordinate);
  d.scale = read_real(require("scale"), "scale", kScale);
  const Entry& bounds = require("bounds");
  const Fields b = read_map(bounds.value, bounds.mark(), "bounds", "{min, max}", false);
  check_known(b, kBoundsKeys);
  for (const char* side : {"min", "max"}) {
    const Entry* x = b.find(side);
    if (x == nullptr)
      fail(b.mark, child("bounds", side), std::string("missing required field '") + side + "'");
    (side[1] == 'i' ? d.bounds.min : d.bounds.max) =
        read_vector<3>(*x, child("bounds", side), "[x, y, z]", "metres", kCoordinate);
  }
  const Entry& layers = require("layers");
  if (!layers.value.is_sequence() || layers.value.items.empty())
    fail(layers.mark(), "layers",
         "expected a non-empty list of layers, got " + describe(layers.value));
  for (std::size_t l = 0; l < layers.value.items.size(); ++l) {
    const Node& node = *layers.value.items[l];
    const std::string path = index("layers", l);
    const Fields lf = read_map(node, mark_or(node, layers.mark()), path,
                               "a layer {weights, bias, activation, beta}", false);
    check_known(lf, kLayerKeys);
    NeuralLayer layer;
    const Entry* weights = lf.find("weights");
    const Entry* bias = lf.find("bias");
    if (weights == nullptr || bias == nullptr)
      fail(lf.mark, path, "a layer needs 'weights' (rows of outputs) and 'bias'");
    if (!weights->value.is_sequence() || weights->value.items.empty())
      fail(weights->mark(), child(path, "weights"), "expected a list of rows, one per output");
    layer.outputs = static_cast<int>(weights->value.items.size());
    for (std::size_t o = 0; o < weights->value.items.size(); ++o) {
      const Node& row = *weights->value.items[o];
      const std::string row_path = index(child(path, "weights"), o);
      if (!row.is_sequence() || row.items.empty())
        fail(mark_or(row, weights->mark()), row_path, "expected a row of numbers");
      if (o == 0)
        layer.inputs = static_cast<int>(row.items.size());
      else if (static_cast<int>(row.items.size()) != layer.inputs)
        fail(mark_or(row, weights->mark()), row_path,
             "expected " + std::to_string(layer.inputs) + " numbers like the first row, got " +
                 std::to_string(row.items.size()));
      for (std::size_t i = 0; i < row.items.size(); ++i)
        layer.weights.push_back(read_real(*row.items[i], mark_or(*row.items[i], weights->mark()),
                                          index(row_path, i), kWeight));
    }
    if (!bias->value.is_sequence())
      fail(bias->mark(), child(path, "bias"), "expected a list of numbers");
    for (std::size_t i = 0; i < bias->value.items.size(); ++i)
      layer.bias.push_back(read_real(*bias->value.items[i],
                                     mark_or(*bias->value.items[i], bias->mark()),
                                     index(child(path, "bias"), i), kWeight));
    if (const Entry* a = lf.find("activation")) {
      const std::string name = read_word(*a, child(path, "activation"), "an activation");
      if (name == "none")
        layer.activation = Activation::none;
      else if (name == "relu")
        layer.activation = Activation::relu;
      else if (name == "softplus")
        layer.activation = Activation::softplus;
      else if (name == "tanh")
        layer.activation = Activation::tanh;
      else
        fail(a->mark(), child(path, "activation"),
             "expected one of: none, relu, softplus, tanh, got '" + printable(name) + "'");
    }
    if (const Entry* x = lf.find("beta"))
      layer.beta = read_real(*x, child(path, "beta"), kBeta);
    d.layers.push_back(std::move(layer));
  }
  try {
    (void)NeuralSdf(d);  // how the layers chain, which no single field shows
  } catch (const Error& e) {
    fail(layers.mark(), "layers", e.what());
  }
  return d;
}

}  // namespace scene_yaml

NeuralSdfDescription load_neural_sdf_string(std::string_view text, std::string_view source_name) {
  const std::string source(source_name);
  scene_yaml::Loader loader{source};
  return scene_yaml::with_yaml_errors(source, [&] { return loader.load_neural(text); });
}

NeuralSdfDescription load_neural_sdf_file(const std::filesystem::path& path) {
  const std::string source = path.string();
  return load_neural_sdf_string(scene_yaml::read_file(path, source), source);
}

}  // namespace tumble
