// A neural signed distance field: a multilayer perceptron from a point to its signed distance, as
// in Park et al., "DeepSDF" (CVPR 2019), with the positional encoding of Mildenhall et al.,
// "NeRF" (ECCV 2020, section 5.1): each coordinate x also enters as sin(2^k pi x) and
// cos(2^k pi x) for k < frequencies. The gradient is exact for the network (back-propagation
// through the layers and the encoding), so it is the gradient of what the network says, which
// approximates a distance's only as well as the network was trained (docs/sdf.md).
//
// Evaluation allocates nothing: the layers' activations live in fixed arrays, which is why the
// width and the depth are bounded.
#pragma once

#include <string>
#include <vector>

#include "collision/aabb.hpp"
#include "collision/math.hpp"
#include "collision/sdf/sdf_primitives.hpp"

namespace tumble {

enum class Activation : std::uint8_t { none, relu, softplus, tanh };

struct NeuralLayer {
  int inputs = 0;
  int outputs = 0;
  std::vector<Real> weights;  // row-major, outputs x inputs
  std::vector<Real> bias;     // outputs
  Activation activation = Activation::none;
  Real beta = 1;  // softplus sharpness: log(1 + exp(beta z)) / beta
};

struct NeuralSdfDescription {
  int frequencies = 0;  // positional encoding bands per coordinate
  // The network sees (x - offset) / scale and its output is multiplied by scale, so that it
  // works on a unit-sized object whatever the size in metres.
  Vec3 offset = Vec3::Zero();
  Real scale = 1;
  std::vector<NeuralLayer> layers;  // the last has one output
  Aabb bounds;                      // where the field was trained: points outside are extrapolated
};

class NeuralSdf {
 public:
  static constexpr int kMaxWidth = 512;
  static constexpr int kMaxLayers = 16;
  static constexpr int kMaxFrequencies = 12;

  // Throws tumble::Error naming the layer and what is wrong: sizes that do not chain (the first
  // layer takes 3 + 6 frequencies inputs, the last gives 1), a width above kMaxWidth, more than
  // kMaxLayers, a weight that is not finite, a scale not positive, bounds that are empty.
  explicit NeuralSdf(NeuralSdfDescription description);

  sdf::Sample sample(const Vec3& p) const;
  const Aabb& bounds() const { return d_.bounds; }
  int input_width() const { return 3 + 6 * d_.frequencies; }

 private:
  NeuralSdfDescription d_;
};

}  // namespace tumble
