// Neural SDF weights files (scenes/neural_sdf_file.hpp): the committed torus network reads and
// approximates the torus it was fitted to, its gradient is the network's own (central
// differences), and malformed files are refused naming line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "collision/sdf/neural_sdf.hpp"
#include "scenes/neural_sdf_file.hpp"
#include "tests/collision/field_gradient_tally.hpp"
#include "tests/property_scale.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

const std::string kTorus = std::string(TUMBLE_SOURCE_DIR) + "/tests/data/neural/torus_sdf.json";

Real torus_distance(const Vec3& p) {
  return std::hypot(std::hypot(p.x(), p.y()) - 0.6, p.z()) - 0.2;
}

TEST(NeuralSdfFile, TheCommittedTorusApproximatesItsTorus) {
  const NeuralSdf net(load_neural_sdf_file(kTorus));
  EXPECT_EQ(net.input_width(), 3 + 6 * 2);
  std::mt19937_64 rng(51);
  std::uniform_real_distribution<Real> angle(0, 2 * M_PI), noise(-0.04, 0.04);
  Real worst = 0, sum = 0, alignment = 0;
  const int count = 2000;
  for (int i = 0; i < count; ++i) {
    // Points within 4 cm of the surface, where the network was fitted hardest.
    const Real a = angle(rng), b = angle(rng), r = 0.2 + noise(rng);
    const Vec3 p((0.6 + r * std::cos(b)) * std::cos(a), (0.6 + r * std::cos(b)) * std::sin(a),
                 r * std::sin(b));
    const sdf::Sample s = net.sample(p);
    const Real error = std::abs(s.distance - torus_distance(p));
    worst = std::max(worst, error);
    sum += error;
    const Vec3 radial(std::cos(a), std::sin(a), 0);
    const Vec3 exact = (p - 0.6 * radial).normalized();
    alignment += s.gradient.normalized().dot(exact);
    // The gradient is the network's: central differences agree.
    const Real h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      Vec3 e = Vec3::Zero();
      e[k] = h;
      const Real fd = (net.sample(p + e).distance - net.sample(p - e).distance) / (2 * h);
      ASSERT_NEAR(fd, s.gradient[k], 1e-6);
    }
  }
  EXPECT_LT(sum / count, 0.004);  // metres: the fit's own figure was 1.4 mm
  EXPECT_LT(worst, 0.02);
  EXPECT_GT(alignment / count, 0.98);  // mean cosine to the exact normal
}

TEST(NeuralSdfFile, MalformedFilesNameLineAndField) {
  const auto expect = [](const std::string& text, const std::string& what) {
    try {
      load_neural_sdf_string(text, "net.json");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const std::string head =
      "{\"format\": \"tumble-neural-sdf\", \"version\": 1, \"frequencies\": 0, \"offset\": [0, 0, "
      "0], \"scale\": 1, \"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]},\n";
  expect(head +
             "\"layers\": [{\"weights\": [[0, 0, 1]], \"bias\": [0], \"activation\": "
             "\"gelu\"}]}",
         "net.json:2:");
  expect(head + "\"layers\": [{\"weights\": [[0, 0, 1], [1, 2]], \"bias\": [0, 0]}]}",
         "layers[0].weights[1]");
  expect(head + "\"layers\": [{\"weights\": [[0, 0, 1, 4]], \"bias\": [0]}]}",
         "layer 0 takes 4 inputs");
  expect(head + "\"layers\": [{\"weights\": [[0, 0, \"x\"]], \"bias\": [0]}]}",
         "layers[0].weights[0][2]");
  expect("{\"format\": \"other\"}", "format");
  expect(head + "\"layers\": []}", "non-empty list of layers");
  // A well-formed linear layer reads.
  const NeuralSdfDescription d = load_neural_sdf_string(
      head + "\"layers\": [{\"weights\": [[0, 0, 1]], \"bias\": [0]}]}", "net.json");
  EXPECT_NEAR(NeuralSdf(d).sample(Vec3(0, 0, 0.25)).distance, 0.25, 1e-12);
}

}  // namespace
}  // namespace tumble

namespace tumble {
namespace {

// distance_between of a ball and a capsule against the committed network's field: the gradients
// (grad phi by back-propagation at the core's least point) against central differences of the
// distance (tests/collision/field_gradient_tally.hpp), on 10,000 random configurations of the
// ball and 500 of the capsule (each capsule query samples the network about 50 times along the
// core, 25 queries a configuration: 10,000 took 160 s; the capsule-field pair itself is checked on
// 10,000 against analytic fields in tests/collision/sdf_distance_test.cpp; 200 and 50 in the
// instrumented run, where the network is ten times slower). The network is smooth
// (softplus), so every disagreement is unexplained but for a capsule's least point jumping
// between two basins along its core (a kink: the one-sided differences disagree).
TEST(NeuralSdfFile, DistanceGradientsOnTheCommittedTorusMatchCentralDifferences) {
  const SdfNode field =
      SdfNode::from_network(std::make_shared<const NeuralSdf>(load_neural_sdf_file(kTorus)));
  const std::vector<FieldCase> cases = {{"sphere-neural", field, Shape::sphere(0.15)},
                                        {"capsule-neural", field, Shape::capsule(0.1, 0.3)}};
  std::mt19937_64 rng(57);
  for (const FieldCase& c : cases) {
    const bool ball = c.round.type == ShapeType::sphere;
    const int count = property_scale() < 1 ? (ball ? 200 : 50) : (ball ? 10000 : 500);
    expect_round_gradients_match(c, rng, count);
  }
}

}  // namespace
}  // namespace tumble
