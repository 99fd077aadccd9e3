// NeuralSdf: the back-propagated gradient against central differences on random networks of
// every activation and encoding width, a linear network against the plane it is, and bad
// descriptions refused naming the layer.
#include <gtest/gtest.h>

#include <random>

#include "collision/sdf/neural_sdf.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

NeuralSdfDescription random_network(std::mt19937_64& rng, int frequencies, Activation hidden,
                                    int width, int hidden_layers) {
  std::normal_distribution<Real> n(0, 1);
  NeuralSdfDescription d;
  d.frequencies = frequencies;
  d.offset = Vec3(0.1, -0.2, 0.3);
  d.scale = 1.7;
  d.bounds = {Vec3::Constant(-2), Vec3::Constant(2)};
  int inputs = 3 + 6 * frequencies;
  for (int l = 0; l <= hidden_layers; ++l) {
    NeuralLayer layer;
    layer.inputs = inputs;
    layer.outputs = l == hidden_layers ? 1 : width;
    layer.activation = l == hidden_layers ? Activation::none : hidden;
    layer.beta = 10;
    for (int k = 0; k < layer.inputs * layer.outputs; ++k)
      layer.weights.push_back(n(rng) / std::sqrt(Real(layer.inputs)));
    for (int k = 0; k < layer.outputs; ++k)
      layer.bias.push_back(0.1 * n(rng));
    d.layers.push_back(layer);
    inputs = layer.outputs;
  }
  return d;
}

TEST(NeuralSdf, BackPropagationMatchesCentralDifferences) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<Real> u(-2, 2);
  int kinks = 0;
  int points = 0;
  for (const Activation a : {Activation::softplus, Activation::tanh, Activation::relu}) {
    for (int frequencies = 0; frequencies <= 6; frequencies += 2) {
      const NeuralSdf net(random_network(rng, frequencies, a, 32, 3));
      for (int i = 0; i < 300; ++i) {
        const Vec3 p(u(rng), u(rng), u(rng));
        const sdf::Sample s = net.sample(p);
        const Real h = 1e-6;
        Vec3 fd;
        for (int k = 0; k < 3; ++k) {
          Vec3 e = Vec3::Zero();
          e[k] = h;
          fd[k] = (net.sample(p + e).distance - net.sample(p - e).distance) / (2 * h);
        }
        ++points;
        const Real error = (fd - s.gradient).norm();
        const Real size = 1 + s.gradient.norm();
        if (a == Activation::relu && error > 1e-6 * size) {
          ++kinks;  // a unit switching on or off within the step
          continue;
        }
        ASSERT_LT(error, 1e-6 * size) << int(a) << " frequencies " << frequencies;
      }
    }
  }
  EXPECT_EQ(points, 3600);
  EXPECT_LT(kinks, 24);  // relu's kinks are a thin set: met rarely
}

TEST(NeuralSdf, ALinearNetworkIsItsPlane) {
  NeuralSdfDescription d;
  d.scale = 2.5;
  d.offset = Vec3(1, 2, 3);
  d.bounds = {Vec3::Constant(-10), Vec3::Constant(10)};
  NeuralLayer layer;
  layer.inputs = 3;
  layer.outputs = 1;
  layer.weights = {0, 0, 1};
  layer.bias = {0};
  d.layers.push_back(layer);
  const NeuralSdf net(d);
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(4, -1, 7), Vec3(-3, 2, 3)}) {
    const sdf::Sample s = net.sample(p);
    EXPECT_NEAR(s.distance, p.z() - 3, 1e-12);  // (z - 3) / 2.5 * 2.5
    EXPECT_NEAR((s.gradient - Vec3::UnitZ()).norm(), 0, 1e-12);
  }
}

TEST(NeuralSdf, BadDescriptionsNameTheLayer) {
  std::mt19937_64 rng(42);
  const auto message = [](NeuralSdfDescription d) {
    try {
      NeuralSdf net(std::move(d));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  NeuralSdfDescription d = random_network(rng, 2, Activation::softplus, 8, 2);
  d.layers[1].inputs = 7;
  EXPECT_NE(message(d).find("layer 1 takes 7 inputs"), std::string::npos) << message(d);
  d = random_network(rng, 2, Activation::softplus, 8, 2);
  d.layers[0].weights[3] = std::nan("");
  EXPECT_NE(message(d).find("layer 0: a weight is not finite"), std::string::npos);
  d = random_network(rng, 0, Activation::tanh, 600, 1);
  EXPECT_NE(message(d).find("1 to 512 outputs"), std::string::npos) << message(d);
  d = random_network(rng, 0, Activation::tanh, 8, 1);
  d.layers.back().outputs = 2;
  d.layers.back().weights.resize(16);
  d.layers.back().bias.resize(2);
  EXPECT_NE(message(d).find("last layer must give 1 output"), std::string::npos) << message(d);
  d = random_network(rng, 13, Activation::tanh, 8, 1);
  EXPECT_NE(message(d).find("frequencies"), std::string::npos);
  d = random_network(rng, 1, Activation::tanh, 8, 1);
  d.scale = 0;
  EXPECT_NE(message(d).find("scale"), std::string::npos);
}

}  // namespace
}  // namespace tumble
