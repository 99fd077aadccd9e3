// Robustness: random edits of a valid scene either load or throw SceneError; nothing else
// escapes, nothing crashes (this binary also runs under ASan and UBSan), and whatever loads is
// a scene the engine can run. The generator is a fixed-seed mt19937_64, which the standard
// specifies exactly, so every run and every platform sees the same inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <random>
#include <string>
#include <string_view>

#include "scenes/scene_loader.hpp"

namespace tumble {
namespace {

constexpr std::string_view kSeedScene = R"(world:
  gravity: [0, 0, -9.81]
  dt: 0.01
  duration: 2
  substeps: 2
  solver: impulse
  iterations: 8
  broadphase: brute
  ccd: auto
  contact_margin: 0.005
materials:
  default: {friction: 0.5, restitution: 0.0}
  rubber: {friction: 0.9, restitution: 0.8}
bodies:
  - name: ball
    shape: {type: sphere, radius: 0.5}
    position: [0, 0, 2]
    orientation: [1, 0, 0, 0]
    velocity: [1, 0, 0]
    angular_velocity: [0, 0, 1]
    mass: 1.0
    material: rubber
    fast: true
  - name: crate
    shape:
      type: box
      half_extents: [0.5, 0.25, 0.125]
    position: [2, 0, 1]
    density: 500
  - name: pill
    shape: {type: capsule, radius: 0.2, half_length: 0.3}
    orientation: [0.7071067811865476, 0, 0.7071067811865476, 0]
    inertia: [0.1, 0.1, 0.05]
  - name: floor
    shape: {type: plane}
    static: true
camera: {position: [6, -6, 4], target: [0, 0, 1], fov: 45}
)";

// Characters and tokens that matter to YAML or to the validator, so that edits reach past the
// parser into every field check more often than uniformly random bytes would.
constexpr std::string_view kAlphabet = "-:[]{},#&*!|>'\"%@`? \n\t.0123456789eE+abz~\x01\xff";
constexpr std::string_view kTokens[] = {"-1",
                                        "0",
                                        ".nan",
                                        ".inf",
                                        "-.inf",
                                        "1e308",
                                        "1e-308",
                                        "1e999",
                                        "abc",
                                        "[]",
                                        "{}",
                                        "[1, 2]",
                                        "[1, 2, 3, 4]",
                                        "true",
                                        "null",
                                        "~",
                                        "\"1\"",
                                        "&a ",
                                        "*a",
                                        "*b",
                                        "!!str ",
                                        "\n  - ",
                                        "\n    ",
                                        ": ",
                                        "type: plane",
                                        "type: hull",
                                        "static: true",
                                        "mass: 0",
                                        "radius: 1e-12",
                                        "steps: 1e12",
                                        "<<: ",
                                        "---\n",
                                        "...\n",
                                        "? ",
                                        "%YAML 1.2\n"};

// Numbers at and around the loader's bounds, to replace numbers in the seed with: these edits
// mostly keep the YAML valid, so they reach the range checks and, when accepted, check_runnable.
constexpr std::string_view kEdgeNumbers[] = {
    "0",         "-0",        "1",      "-1",    "1e-9",
    "0.99e-9",   "1e9",       "1.01e9", "-1e9",  "1e6",
    "-1e6",      "1e-300",    "5e-324", "1e308", "1.7976931348623157e308",
    "0.9999995", "1.0000015", "2",      "179",   "180",
    "1e15",      "1e16",      "100",    "1e4",   "3.5"};

// What any loaded scene must satisfy for the engine to run it.
void check_runnable(const Scene& s) {
  ASSERT_FALSE(s.bodies.empty());
  ASSERT_FALSE(s.materials.empty());
  EXPECT_EQ(s.materials[0].name, "default");
  const WorldSettings& w = s.world;
  EXPECT_TRUE(w.gravity.allFinite());
  EXPECT_GT(w.dt, 0);
  EXPECT_LE(w.dt, 1);
  EXPECT_GT(w.duration, 0);
  EXPECT_GE(w.substeps, 1);
  EXPECT_GE(w.iterations, 1);
  for (const Material& m : s.materials) {
    EXPECT_GE(m.friction, 0);
    EXPECT_GE(m.restitution, 0);
    EXPECT_LE(m.restitution, 1);
  }
  for (const BodyDesc& b : s.bodies) {
    EXPECT_FALSE(b.name.empty());
    EXPECT_TRUE(b.position.allFinite());
    EXPECT_TRUE(b.velocity.allFinite());
    EXPECT_TRUE(b.angular_velocity.allFinite());
    EXPECT_NEAR(b.orientation.norm(), 1, 1e-12);
    EXPECT_GE(b.material, 0);
    EXPECT_LT(b.material, static_cast<int>(s.materials.size()));
    if (b.is_static) {
      EXPECT_EQ(b.mass, 0);
    } else {
      EXPECT_TRUE(b.shape.is_bounded());
      EXPECT_TRUE(std::isfinite(b.mass));
      EXPECT_GT(b.mass, 0);
      EXPECT_TRUE(b.inertia.allFinite());
      EXPECT_GT(b.inertia.diagonal().minCoeff(), 0);
    }
  }
}

std::string mutate(std::string text, std::mt19937_64& rng) {
  const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  const std::size_t edits = 1 + pick(4);
  for (std::size_t k = 0; k < edits; ++k) {
    const std::size_t at = pick(text.size() + 1);
    switch (pick(6)) {
      case 0:  // delete a short run
        if (at < text.size())
          text.erase(at, 1 + pick(4));
        break;
      case 1:  // insert a character
        text.insert(at, 1, kAlphabet[pick(kAlphabet.size())]);
        break;
      case 2:  // replace a character
        if (at < text.size())
          text[at] = kAlphabet[pick(kAlphabet.size())];
        break;
      case 3:  // insert a token
        text.insert(at, kTokens[pick(std::size(kTokens))]);
        break;
      default: {  // replace the number nearest after `at` with an edge value
        const std::size_t start = text.find_first_of("0123456789", std::min(at, text.size()));
        if (start == std::string::npos)
          break;
        const std::size_t end = text.find_first_not_of("0123456789.e-", start);
        text.replace(start, (end == std::string::npos ? text.size() : end) - start,
                     kEdgeNumbers[pick(std::size(kEdgeNumbers))]);
        break;
      }
    }
  }
  return text;
}

TEST(SceneFuzz, SeedSceneLoads) {
  const Scene s = load_scene_string(kSeedScene, "seed.yaml");
  EXPECT_EQ(s.bodies.size(), 4u);
  check_runnable(s);
}

TEST(SceneFuzz, MutationsLoadOrThrowSceneError) {
  // TUMBLE_FUZZ_MUTATIONS and TUMBLE_FUZZ_SEED run a longer or different campaign by hand; the
  // defaults keep the suite fast and reproducible.
  const char* count = std::getenv("TUMBLE_FUZZ_MUTATIONS");
  const char* seed = std::getenv("TUMBLE_FUZZ_SEED");
  const int kMutations = count != nullptr ? std::atoi(count) : 4000;
  std::mt19937_64 rng(seed != nullptr ? std::strtoull(seed, nullptr, 10) : 20240611);
  int loaded = 0;
  int rejected = 0;
  for (int i = 0; i < kMutations; ++i) {
    const std::string text = mutate(std::string(kSeedScene), rng);
    try {
      const Scene s = load_scene_string(text, "fuzz.yaml");
      ++loaded;
      SCOPED_TRACE(text);
      check_runnable(s);
    } catch (const SceneError& e) {
      ++rejected;
      const std::string_view what = e.what();
      EXPECT_EQ(what.substr(0, 10), "fuzz.yaml:") << what;
      EXPECT_EQ(what.find('\n'), std::string_view::npos) << what;
      EXPECT_FALSE(e.reason.empty());
    } catch (const std::exception& e) {
      ADD_FAILURE() << "non-SceneError exception: " << e.what() << "\ninput:\n" << text;
    } catch (...) {
      ADD_FAILURE() << "unknown exception\ninput:\n" << text;
    }
    if (HasFailure())
      break;  // one reproducer is enough
  }
  // Both outcomes must be common, or the mutations are not testing what they claim to.
  EXPECT_GT(loaded, kMutations / 100);
  EXPECT_GT(rejected, kMutations / 4);
  RecordProperty("loaded", loaded);
  RecordProperty("rejected", rejected);
}

// Arbitrary bytes, not edits of a scene: the parser's own error paths.
TEST(SceneFuzz, RandomBytesThrowSceneError) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 2000; ++i) {
    std::string text(static_cast<std::size_t>(rng() % 200), '\0');
    for (char& c : text)
      c = kAlphabet[static_cast<std::size_t>(rng() % kAlphabet.size())];
    try {
      load_scene_string(text, "bytes.yaml");
    } catch (const SceneError&) {
    } catch (...) {
      ADD_FAILURE() << "non-SceneError exception for input:\n" << text;
      break;
    }
  }
}

TEST(SceneFuzz, DeepNestingIsRejectedNotACrash) {
  for (const std::size_t depth : {100u, 10000u, 100000u}) {
    const std::string text = "bodies: " + std::string(depth, '[') + std::string(depth, ']') + "\n";
    EXPECT_THROW(load_scene_string(text, "deep.yaml"), SceneError) << depth;
    const std::string maps = "bodies:\n  - shape: " + std::string(depth, '{') + "\n";
    EXPECT_THROW(load_scene_string(maps, "deep.yaml"), SceneError) << depth;
  }
}

}  // namespace
}  // namespace tumble
