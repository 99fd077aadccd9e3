// Sweep files (scenes/sweep_file.hpp): values, ranges, seeds and references as written, and
// every mistake named by file, line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scenes/sweep_file.hpp"

namespace tumble {
namespace {

std::string sweep_error_of(const std::string& yaml) {
  try {
    load_sweep_string(yaml, "dir/sweep.yaml");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(SweepFile, ReadsAxesInFileOrder) {
  const SweepSpec s = load_sweep_string(
      "scene: stack.yaml\nduration: 2\nvary:\n  world.dt: [0.01, 0.005]\n"
      "  world.solver: [impulse, penalty]\n  world.gravity: [[0, 0, -9.81], [0, 0, -1.62]]\n"
      "seeds: 3\nreference: {world.dt: 0.001, world.substeps: 8}\ntrajectory: true\n",
      "dir/sweep.yaml");
  EXPECT_EQ(s.scene, std::filesystem::path("dir/stack.yaml"));  // beside the sweep file
  EXPECT_EQ(*s.duration, 2.0);
  ASSERT_EQ(s.axes.size(), 3u);
  EXPECT_EQ(s.axes[0].field, "world.dt");
  EXPECT_EQ(s.axes[0].values, (std::vector<std::string>{"0.01", "0.005"}));
  EXPECT_EQ(s.axes[0].places[1].line, 4);
  EXPECT_EQ(s.axes[1].values, (std::vector<std::string>{"impulse", "penalty"}));
  EXPECT_EQ(s.axes[2].values[1], "[0, 0, -1.62]");
  EXPECT_EQ(s.seeds, (std::vector<std::uint64_t>{0, 1, 2}));
  ASSERT_EQ(s.reference.size(), 2u);
  EXPECT_EQ(s.reference[1].field, "world.substeps");
  EXPECT_EQ(s.reference[1].value, "8");
  EXPECT_TRUE(s.trajectory);
}

TEST(SweepFile, RangesHitTheirEndsExactly) {
  for (int count = 1; count <= 50; ++count) {
    const SweepSpec s = load_sweep_string(
        "scene: a.yaml\nvary:\n  world.dt: {from: 0.1, to: 0.7, count: " + std::to_string(count) +
            "}\n  world.contact_hertz: {from: 1, to: 1000, count: " + std::to_string(count) +
            ", scale: log}\n",
        "s.yaml");
    ASSERT_EQ(s.axes[0].values.size(), std::size_t(count));
    EXPECT_EQ(std::stod(s.axes[0].values.front()), 0.1);
    EXPECT_EQ(std::stod(s.axes[1].values.front()), 1.0);
    if (count > 1) {
      EXPECT_EQ(std::stod(s.axes[0].values.back()), 0.7);
      EXPECT_EQ(std::stod(s.axes[1].values.back()), 1000.0);
    }
    for (int k = 0; k < count; ++k) {
      const double t = count == 1 ? 0 : double(k) / (count - 1);
      EXPECT_NEAR(std::stod(s.axes[0].values[std::size_t(k)]), 0.1 + 0.6 * t, 1e-15);
      EXPECT_NEAR(std::log10(std::stod(s.axes[1].values[std::size_t(k)])), 3 * t, 1e-13);
    }
  }
  // Numbers are written to read back to the same double.
  EXPECT_EQ(sweep_number_text(0.1 + 0.2), "0.30000000000000004");
}

// A plain scalar that would end early inside a flow collection goes back quoted.
TEST(SweepFile, ValuesWrittenInBlockStyleReadBackTheSame) {
  const SweepSpec s = load_sweep_string(
      "scene: a.yaml\nvary:\n  materials.steel:\n    - friction: 0.4\n      note: steel, polished\n"
      "    - {friction: 0.5}\n",
      "s.yaml");
  EXPECT_EQ(s.axes[0].values[0], "{friction: 0.4, note: \"steel, polished\"}");
  EXPECT_EQ(s.axes[0].values[1], "{friction: 0.5}");
}

TEST(SweepFile, SeedsAsAList) {
  const SweepSpec s =
      load_sweep_string("scene: a.yaml\nvary: {world.dt: [0.01]}\nseeds: [7, 11]\n", "s.yaml");
  EXPECT_EQ(s.seeds, (std::vector<std::uint64_t>{7, 11}));
  EXPECT_TRUE(
      load_sweep_string("scene: a.yaml\nvary: {world.dt: [0.01]}\n", "s.yaml").seeds.empty());
}

TEST(SweepFile, MistakesNameTheLineAndField) {
  const auto expect = [](const std::string& yaml, const std::string& where,
                         const std::string& what) {
    const std::string e = sweep_error_of(yaml);
    EXPECT_NE(e.find(where), std::string::npos) << yaml << "\n-> " << e;
    EXPECT_NE(e.find(what), std::string::npos) << yaml << "\n-> " << e;
  };
  expect("vary: {world.dt: [0.1]}\n", "dir/sweep.yaml", "missing required field 'scene'");
  expect("scene: a.yaml\n", "field 'vary'", "missing required field 'vary'");
  expect("scene: a.yaml\nvary:\n  world.dt: []\n", "dir/sweep.yaml:3:13", "an empty list");
  expect("scene: a.yaml\nvary:\n  world.dt: {from: 1, to: 2, count: 0}\n",
         "field 'vary.world.dt.count'", "an empty range");
  expect("scene: a.yaml\nvary:\n  world.dt: {from: 1, to: 2}\n", "vary.world.dt.count",
         "missing required field 'count'");
  expect("scene: a.yaml\nvary:\n  world.dt: {from: 0, to: 2, count: 3, scale: log}\n",
         "vary.world.dt.scale", "greater than 0");
  expect("scene: a.yaml\nvary:\n  world.dt: 0.1\n", "vary.world.dt", "expected a list of values");
  expect("scene: a.yaml\nvary: {}\n", "field 'vary'", "at least one field");
  expect("scene: a.yaml\nvary: {world.dt: [1]}\nseeds: 0\n", "field 'seeds'", "at least one seed");
  expect("scene: a.yaml\nvary: {world.dt: [1]}\nseeds: [1, -2]\n", "seeds[1]", "got -2");
  expect("scene: a.yaml\nvary: {world.dt: [1]}\nrefrence: {world.dt: 1}\n", "refrence",
         "did you mean 'reference'");
  expect(
      "scene: a.yaml\nvary:\n  a: {from: 0, to: 1, count: 1000}\n  b: {from: 0, to: 1, count: "
      "1000}\n  c: [1, 2]\n",
      "field 'vary'", "at most 1e6");
  expect("scene: a.yaml\nvary: {world..dt: [1]}\n", "vary.world..dt", "dotted field path");
}

}  // namespace
}  // namespace tumble
