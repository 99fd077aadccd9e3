// NeuralSdf (collision/sdf/neural_sdf.hpp): the checks, the forward pass and back-propagation.
#include "collision/sdf/neural_sdf.hpp"

#include <array>
#include <cmath>
#include <numbers>

#include "tumble/error.hpp"

namespace tumble {
namespace {

Real activate(Activation a, Real z, Real beta) {
  switch (a) {
    case Activation::none:
      return z;
    case Activation::relu:
      return z > 0 ? z : 0;
    case Activation::softplus: {
      // log(1 + exp(b z)) / b without overflow for large b z.
      const Real bz = beta * z;
      return (bz > 0 ? bz + std::log1p(std::exp(-bz)) : std::log1p(std::exp(bz))) / beta;
    }
    case Activation::tanh:
      return std::tanh(z);
  }
  return z;
}

Real slope(Activation a, Real z, Real beta) {
  switch (a) {
    case Activation::none:
      return 1;
    case Activation::relu:
      return z > 0 ? 1 : 0;
    case Activation::softplus: {
      const Real bz = beta * z;  // the logistic function of b z, written to stay finite
      return bz >= 0 ? 1 / (1 + std::exp(-bz)) : std::exp(bz) / (1 + std::exp(bz));
    }
    case Activation::tanh: {
      const Real t = std::tanh(z);
      return 1 - t * t;
    }
  }
  return 1;
}

}  // namespace

NeuralSdf::NeuralSdf(NeuralSdfDescription description) : d_(std::move(description)) {
  if (d_.frequencies < 0 || d_.frequencies > kMaxFrequencies)
    throw Error("neural SDF: frequencies must be 0 to " + std::to_string(kMaxFrequencies) +
                ", got " + std::to_string(d_.frequencies));
  if (!(std::isfinite(d_.scale) && d_.scale > 0) || !d_.offset.allFinite())
    throw Error("neural SDF: scale must be positive and finite, offset finite");
  if (d_.layers.empty() || d_.layers.size() > std::size_t(kMaxLayers))
    throw Error("neural SDF: 1 to " + std::to_string(kMaxLayers) + " layers, got " +
                std::to_string(d_.layers.size()));
  int width = input_width();
  for (std::size_t l = 0; l < d_.layers.size(); ++l) {
    const NeuralLayer& layer = d_.layers[l];
    const std::string name = "neural SDF: layer " + std::to_string(l);
    if (layer.inputs != width)
      throw Error(name + " takes " + std::to_string(layer.inputs) + " inputs, but " +
                  (l == 0 ? "the encoded point has " : "the layer before gives ") +
                  std::to_string(width));
    if (layer.outputs < 1 || layer.outputs > kMaxWidth)
      throw Error(name + ": 1 to " + std::to_string(kMaxWidth) + " outputs, got " +
                  std::to_string(layer.outputs));
    if (layer.weights.size() != std::size_t(layer.inputs) * std::size_t(layer.outputs) ||
        layer.bias.size() != std::size_t(layer.outputs))
      throw Error(name + ": expected " + std::to_string(layer.outputs) + " x " +
                  std::to_string(layer.inputs) + " weights and " + std::to_string(layer.outputs) +
                  " biases");
    for (const Real w : layer.weights)
      if (!std::isfinite(w))
        throw Error(name + ": a weight is not finite");
    for (const Real b : layer.bias)
      if (!std::isfinite(b))
        throw Error(name + ": a bias is not finite");
    if (!(std::isfinite(layer.beta) && layer.beta > 0))
      throw Error(name + ": softplus beta must be positive and finite");
    width = layer.outputs;
  }
  if (width != 1)
    throw Error("neural SDF: the last layer must give 1 output, got " + std::to_string(width));
  if (!(d_.bounds.min.allFinite() && d_.bounds.max.allFinite()) ||
      (d_.bounds.max.array() < d_.bounds.min.array()).any())
    throw Error("neural SDF: the bounds must be a finite, non-empty box");
}

sdf::Sample NeuralSdf::sample(const Vec3& world) const {
  // Forward: keep every layer's pre-activations for the backward pass.
  std::array<Real, 3 + 6 * kMaxFrequencies> encoded{};
  const Vec3 x = (world - d_.offset) / d_.scale;
  int width = input_width();
  for (int c = 0; c < 3; ++c) {
    encoded[std::size_t(c)] = x[c];
    for (int k = 0; k < d_.frequencies; ++k) {
      const Real w = std::ldexp(std::numbers::pi_v<Real>, k);  // 2^k pi
      encoded[std::size_t(3 + 6 * k + 2 * c)] = std::sin(w * x[c]);
      encoded[std::size_t(3 + 6 * k + 2 * c + 1)] = std::cos(w * x[c]);
    }
  }
  std::array<std::array<Real, kMaxWidth>, kMaxLayers> pre{};
  std::array<Real, kMaxWidth> in{};
  std::array<Real, kMaxWidth> out{};
  for (int i = 0; i < width; ++i)
    in[std::size_t(i)] = encoded[std::size_t(i)];
  const std::size_t depth = d_.layers.size();
  for (std::size_t l = 0; l < depth; ++l) {
    const NeuralLayer& layer = d_.layers[l];
    for (int o = 0; o < layer.outputs; ++o) {
      Real z = layer.bias[std::size_t(o)];
      const Real* row = layer.weights.data() + std::size_t(o) * std::size_t(layer.inputs);
      for (int i = 0; i < layer.inputs; ++i)
        z += row[i] * in[std::size_t(i)];
      pre[l][std::size_t(o)] = z;
      out[std::size_t(o)] = activate(layer.activation, z, layer.beta);
    }
    in = out;
    width = layer.outputs;
  }
  sdf::Sample s;
  s.distance = in[0] * d_.scale;
  // Backward: g holds d output / d (this layer's outputs), from the last layer to the input.
  std::array<Real, kMaxWidth> g{};
  std::array<Real, kMaxWidth> below{};
  g[0] = 1;
  for (std::size_t l = depth; l-- > 0;) {
    const NeuralLayer& layer = d_.layers[l];
    for (int i = 0; i < layer.inputs; ++i)
      below[std::size_t(i)] = 0;
    for (int o = 0; o < layer.outputs; ++o) {
      const Real gz =
          g[std::size_t(o)] * slope(layer.activation, pre[l][std::size_t(o)], layer.beta);
      const Real* row = layer.weights.data() + std::size_t(o) * std::size_t(layer.inputs);
      for (int i = 0; i < layer.inputs; ++i)
        below[std::size_t(i)] += gz * row[i];
    }
    g = below;
  }
  // Through the encoding; the scale cancels (output times scale, input over scale).
  Vec3 grad;
  for (int c = 0; c < 3; ++c) {
    Real v = g[std::size_t(c)];
    for (int k = 0; k < d_.frequencies; ++k) {
      const Real w = std::ldexp(std::numbers::pi_v<Real>, k);
      v += g[std::size_t(3 + 6 * k + 2 * c)] * w * std::cos(w * x[c]);
      v -= g[std::size_t(3 + 6 * k + 2 * c + 1)] * w * std::sin(w * x[c]);
    }
    grad[c] = v;
  }
  s.gradient = grad;
  return s;
}

}  // namespace tumble
