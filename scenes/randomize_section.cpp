// The `randomize` section of a scene file (docs/scene-format.md, "randomize"): what each world of
// a batch draws at its reset (include/tumble/randomization.hpp).
#include <string>

#include "scenes/yaml_reader.hpp"

namespace tumble::scene_yaml {
namespace {

constexpr std::array<std::string_view, 7> kRandomizeKeys{
    "friction",       "restitution",       "mass_scale", "size_noise",
    "position_noise", "orientation_noise", "gravity"};
constexpr std::array<std::string_view, 2> kGravityKeys{"low", "high"};

}  // namespace

void Loader::load_randomize(const Entry* e, Randomization& r) const {
  if (e == nullptr)
    return;
  const Fields f =
      read_map(e->value, e->mark(), "randomize", "a map of randomized quantities", true);
  check_known(f, kRandomizeKeys);
  const auto path = [](std::string_view key) { return child("randomize", key); };
  const auto interval = [&](std::string_view key, std::string_view unit, const RealSpec& spec) {
    std::optional<Interval> out;
    if (const Entry* x = f.find(key)) {
      const Eigen::Matrix<Real, 2, 1> v = read_vector<2>(*x, path(key), "[low, high]", unit, spec);
      if (!(v[0] <= v[1]))
        fail(x->mark(), path(key),
             "expected [low, high] with low <= high, got [" + fmt(v[0]) + ", " + fmt(v[1]) + "]");
      out = Interval{v[0], v[1]};
    }
    return out;
  };
  r.friction = interval("friction", "", kFriction);
  r.restitution = interval("restitution", "", kRestitution);
  r.mass_scale = interval("mass_scale", "", kMassScale);
  if (const Entry* x = f.find("size_noise"))
    r.size_noise = read_real(*x, path("size_noise"), kSizeNoise);
  if (const Entry* x = f.find("position_noise"))
    r.position_noise = read_real(*x, path("position_noise"), kDistance);
  if (const Entry* x = f.find("orientation_noise"))
    r.orientation_noise = read_real(*x, path("orientation_noise"), kAngleNoise);
  if (const Entry* x = f.find("gravity")) {
    const Fields g = read_map(x->value, x->mark(), path("gravity"),
                              "a map {low: [x, y, z], high: [x, y, z]}", false);
    check_known(g, kGravityKeys);
    const Entry* low = g.find("low");
    const Entry* high = g.find("high");
    if (low == nullptr || high == nullptr)
      fail(x->mark(), path("gravity"),
           std::string("missing field '") + (low == nullptr ? "low" : "high") +
               "' (gravity is drawn between low and high)");
    const std::string gravity_path = path("gravity");
    r.gravity_low =
        read_vector<3>(*low, child(gravity_path, "low"), "[x, y, z]", "m/s^2", kAcceleration);
    r.gravity_high =
        read_vector<3>(*high, child(gravity_path, "high"), "[x, y, z]", "m/s^2", kAcceleration);
    for (int k = 0; k < 3; ++k)
      if (!((*r.gravity_low)[k] <= (*r.gravity_high)[k]))
        fail(high->mark(), child(gravity_path, "high"),
             "expected high >= low on every axis, got " + fmt((*r.gravity_high)[k]) + " < " +
                 fmt((*r.gravity_low)[k]) + " on axis " + std::to_string(k));
  }
}

}  // namespace tumble::scene_yaml
