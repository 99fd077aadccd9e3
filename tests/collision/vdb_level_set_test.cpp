// OpenVDB level sets (collision/sdf/vdb_level_set.hpp): built from closed meshes, their band
// against the brute-force distance and tumble's own grid, the interpolants' gradients against
// central differences, a file written and read back bit for bit in double and within float
// rounding in single precision, the narrow band's memory against a dense grid's, and bad input
// refused with a reason. Skipped in a build without OpenVDB (the option TUMBLE_WITH_OPENVDB).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

#include <unistd.h>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/sdf/sdf_grid.hpp"
#include "collision/sdf/sdf_primitives.hpp"
#include "collision/sdf/vdb_level_set.hpp"
#include "collision/shapes/sdf_shape.hpp"
#include "tests/collision/closed_meshes.hpp"
#include "tests/property_scale.hpp"
#include "tumble/distance.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

#define SKIP_WITHOUT_OPENVDB()                                           \
  do {                                                                   \
    if (!VdbLevelSet::available())                                       \
      GTEST_SKIP() << "this build has no OpenVDB (TUMBLE_WITH_OPENVDB)"; \
  } while (false)

std::filesystem::path scratch_file(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("tumble_vdb_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

// The level set of a closed box mesh of half extents `half`, voxels of `voxel` metres.
std::shared_ptr<const VdbLevelSet> box_level_set(const Vec3& half, Real voxel) {
  std::vector<Vec3> v;
  test_meshes::Triangles t;
  test_meshes::box_mesh(half, v, t);
  return VdbLevelSet::from_mesh(v, t, voxel);
}

TEST(VdbLevelSet, BandOfAMeshIsItsDistanceAndAgreesWithTheDenseGrid) {
  SKIP_WITHOUT_OPENVDB();
  std::vector<Vec3> v;
  test_meshes::Triangles t;
  test_meshes::uv_sphere(0.5, 48, 24, v, t);
  const Real voxel = 0.02;
  VdbLevelSet::BuildReport report;
  const auto level_set = VdbLevelSet::from_mesh(v, t, voxel, 3, &report);
  EXPECT_GT(report.active_voxels, 1000);
  EXPECT_EQ(report.active_voxels, level_set->active_voxels());
  EXPECT_NEAR(level_set->band(), 3 * voxel, 1e-6);
  const SdfGrid dense = SdfGrid::from_mesh(v, t, voxel);
  std::mt19937_64 rng(61);
  std::uniform_real_distribution<Real> u(-0.6, 0.6);
  int checked = 0;
  Real worst = 0, worst_dense = 0;
  const int wanted = int(4000 * property_scale()) + 200;
  while (checked < wanted) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const Real exact_unsigned = test_meshes::brute_force_distance(p, v, t);
    if (exact_unsigned > voxel)
      continue;  // where contacts are: tricubic reaches two voxels on, still inside the band
    ++checked;
    // The sign of the mesh (a polyhedron inside the sphere by at most 4.3 mm): inside when the
    // sphere is, away from its chords.
    const Real sphere = p.norm() - 0.5;
    for (GridInterpolation how : {GridInterpolation::trilinear, GridInterpolation::tricubic}) {
      const Real value = level_set->sample(p, how).distance;
      if (std::abs(sphere) > 0.005) {
        ASSERT_EQ(value < 0, sphere < 0) << p.transpose();
      }
      worst = std::max(worst, std::abs(std::abs(value) - exact_unsigned));
      worst_dense = std::max(worst_dense, std::abs(value - dense.sample(p, how).distance));
    }
  }
  // Exact values at the voxels (single-precision vertices, 1e-7 m), interpolated: the
  // interpolation error of a polyhedral sphere's distance at 2 cm voxels is a few tenths of a
  // millimetre.
  EXPECT_LT(worst, 0.1 * voxel) << "worst error in the band " << worst;
  EXPECT_LT(worst_dense, 0.1 * voxel) << "worst difference from tumble's grid " << worst_dense;
}

TEST(VdbLevelSet, GradientsAreThoseOfTheInterpolant) {
  SKIP_WITHOUT_OPENVDB();
  std::vector<Vec3> v;
  test_meshes::Triangles t;
  test_meshes::box_mesh(Vec3(0.4, 0.3, 0.2), v, t);
  const auto level_set = VdbLevelSet::from_mesh(v, t, 0.05, 4);
  std::mt19937_64 rng(62);
  std::uniform_real_distribution<Real> u(-0.55, 0.55);
  const Real h = 1e-6, voxel = level_set->voxel();
  for (GridInterpolation how : {GridInterpolation::trilinear, GridInterpolation::tricubic}) {
    int checked = 0;
    for (int i = 0; i < 3000; ++i) {
      const Vec3 p(u(rng), u(rng), u(rng));
      bool near_face = false;
      Vec3 fd;
      for (int k = 0; k < 3; ++k) {
        Vec3 e = Vec3::Zero();
        e[k] = h;
        fd[k] = (level_set->sample(p + e, how).distance - level_set->sample(p - e, how).distance) /
                (2 * h);
        const Real f = p[k] / voxel;  // voxel centres at integer multiples of the voxel
        near_face = near_face || std::abs(f - std::round(f)) < 1e-4;
      }
      if (near_face && how == GridInterpolation::trilinear)
        continue;
      ++checked;
      ASSERT_LT((level_set->sample(p, how).gradient - fd).norm(), 1e-5) << p.transpose();
    }
    EXPECT_GT(checked, 2900);
  }
}

TEST(VdbLevelSet, FilesReadBackAsWritten) {
  SKIP_WITHOUT_OPENVDB();
  const auto level_set = box_level_set(Vec3(0.5, 0.5, 0.25), 0.04);
  const auto doubles = scratch_file("box_double.vdb");
  const auto floats = scratch_file("box_float.vdb");
  level_set->save(doubles);
  level_set->save(floats, true);
  EXPECT_FALSE(std::filesystem::exists(doubles.string() + ".tmp." + std::to_string(::getpid())));
  const auto read_doubles = VdbLevelSet::load(doubles);
  const auto read_floats = VdbLevelSet::load(floats, "surface");
  EXPECT_EQ(read_doubles->active_voxels(), level_set->active_voxels());
  EXPECT_EQ(read_floats->active_voxels(), level_set->active_voxels());
  std::mt19937_64 rng(63);
  std::uniform_real_distribution<Real> u(-0.8, 0.8);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const sdf::Sample a = level_set->sample(p, GridInterpolation::tricubic);
    const sdf::Sample b = read_doubles->sample(p, GridInterpolation::tricubic);
    ASSERT_EQ(a.distance, b.distance) << p.transpose();
    ASSERT_EQ(a.gradient, b.gradient) << p.transpose();
    ASSERT_NEAR(read_floats->sample(p, GridInterpolation::tricubic).distance, a.distance, 1e-6);
  }
  // Beyond the band |phi| is a lower bound of the distance (the band's edge, or the way to the
  // voxels' box plus the edge) with the right sign: inside stays inside, outside outside.
  int inside = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 p(1.5 * u(rng), 1.5 * u(rng), 0.5 * u(rng));
    const Real exact = sdf::box(p, Vec3(0.5, 0.5, 0.25)).distance;
    if (std::abs(exact) < level_set->band() + level_set->voxel())
      continue;  // in the band the interpolant's error applies (checked above)
    const Real value = level_set->sample(p, GridInterpolation::trilinear).distance;
    ASSERT_EQ(value < 0, exact < 0) << p.transpose();
    ASSERT_LE(std::abs(value), std::abs(exact) + 1e-3) << p.transpose();
    inside += exact < 0 ? 1 : 0;
  }
  EXPECT_GT(inside, 20);
  std::filesystem::remove_all(doubles.parent_path());
}

TEST(VdbLevelSet, MemoryGrowsWithTheSurfaceNotTheVolume) {
  SKIP_WITHOUT_OPENVDB();
  std::vector<Vec3> v;
  test_meshes::Triangles t;
  test_meshes::uv_sphere(0.5, 64, 32, v, t);
  std::size_t band[2], dense[2];
  const Real voxels[2] = {0.02, 0.01};
  for (int i = 0; i < 2; ++i) {
    band[i] = VdbLevelSet::from_mesh(v, t, voxels[i])->bytes();
    SdfGrid::BuildReport report;
    (void)SdfGrid::from_mesh(v, t, voxels[i], SdfGrid::kBand + 1, &report);
    dense[i] = report.bytes;
  }
  // Halving the voxel: the band's memory grows as the surface's voxels (about 4x), the dense
  // grid's as the volume's (about 8x).
  const double band_growth = double(band[1]) / double(band[0]);
  const double dense_growth = double(dense[1]) / double(dense[0]);
  EXPECT_LT(band_growth, 5.0) << band[0] << " -> " << band[1] << " bytes";
  EXPECT_GT(dense_growth, 5.5) << dense[0] << " -> " << dense[1] << " bytes";
  std::printf("band %zu -> %zu bytes (x%.2f), dense %zu -> %zu bytes (x%.2f)\n", band[0], band[1],
              band_growth, dense[0], dense[1], dense_growth);
}

TEST(VdbLevelSet, ABodyOfALevelSetHasTheMeshsMass) {
  SKIP_WITHOUT_OPENVDB();
  std::vector<Vec3> v;
  test_meshes::Triangles t;
  const Vec3 half(0.5, 0.3, 0.2);
  test_meshes::box_mesh(half, v, t);
  const SdfShape shape(SdfNode::from_level_set(VdbLevelSet::from_mesh(v, t, 0.02)));
  const Real volume = 8 * half.prod();
  EXPECT_NEAR(shape.volume(), volume, 0.01 * volume);
  EXPECT_LT(shape.centre_in_tree().norm(), 1e-3);
  const Real ixx = (half.y() * half.y() + half.z() * half.z()) / 3;  // per unit mass
  EXPECT_NEAR(shape.unit_inertia()(0, 0), ixx, 0.02 * ixx);
}

TEST(VdbLevelSet, RoundShapesWiderThanTheBandTouchItsSurface) {
  SKIP_WITHOUT_OPENVDB();
  // A box of half extents (0.5, 0.5, 0.2) as a level set with a band of 3 voxels of 2 cm: a ball
  // of radius 0.1 has its centre beyond the band when it touches, so its contact comes from the
  // field's surface points in the ball's exact distance; the depth must still be the box's.
  const auto level_set = box_level_set(Vec3(0.5, 0.5, 0.2), 0.02);
  const Shape field = sdf_shape(SdfNode::from_level_set(level_set));
  ASSERT_LT(field.sdf->reach(), 0.1);
  const Vec3 centre_offset = field.sdf->centre_in_tree();  // the body frame is the mass centre's
  std::mt19937_64 rng(64);
  std::uniform_real_distribution<Real> u(-0.3, 0.3), depth_of(0.001, 0.01);
  for (ShapeType type : {ShapeType::sphere, ShapeType::capsule}) {
    const Shape round = type == ShapeType::sphere ? Shape::sphere(0.1) : Shape::capsule(0.1, 0.2);
    for (int i = 0; i < 200; ++i) {
      const Real depth = depth_of(rng);
      Transform pose_a;
      pose_a.translation = Vec3(u(rng), u(rng), 0.2 + 0.1 - depth) - centre_offset;
      if (type == ShapeType::capsule)  // lying along x
        pose_a.rotation = Quat(Eigen::AngleAxis<Real>(Real(1.5707963267948966), Vec3::UnitY()));
      Manifold m;
      ASSERT_GT(collide(round, pose_a, field, Transform{}, 0.01, m), 0);
      Real deepest = -1;
      for (int k = 0; k < m.count; ++k)
        deepest = std::max(deepest, m.points[std::size_t(k)].depth);
      EXPECT_NEAR(deepest, depth, 1e-3) << shape_type_name(type) << " " << i;
      EXPECT_GT(m.normal.z(), 0.99) << shape_type_name(type) << " " << m.normal.transpose();
    }
    // Its distance from the field cannot be measured at its core: refused, not guessed.
    Transform above;
    above.translation = Vec3(0, 0, 0.2 + 0.05) - centre_offset;
    EXPECT_THROW(distance_between(round, above, field, Transform{}), Error);
  }
}

TEST(VdbLevelSet, BadInputIsRefusedWithAReason) {
  SKIP_WITHOUT_OPENVDB();
  const auto expect_error = [](auto&& make, const std::string& part) {
    try {
      make();
      ADD_FAILURE() << "no error; expected one mentioning '" << part << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expect_error([] { VdbLevelSet::load("/nonexistent/part.vdb"); }, "/nonexistent/part.vdb");
  const auto text = scratch_file("not_a_volume.vdb");
  std::ofstream(text) << "not a volume\n";
  expect_error([&] { VdbLevelSet::load(text); }, text.string());
  std::vector<Vec3> v;
  test_meshes::Triangles t;
  test_meshes::box_mesh(Vec3(0.5, 0.5, 0.5), v, t);
  const auto file = scratch_file("cube.vdb");
  VdbLevelSet::from_mesh(v, t, 0.1)->save(file);
  expect_error([&] { VdbLevelSet::load(file, "density"); }, "no grid named 'density'");
  test_meshes::Triangles open(t.begin() + 1, t.end());
  expect_error([&] { VdbLevelSet::from_mesh(v, open, 0.1); }, "not closed");
  expect_error([&] { VdbLevelSet::from_mesh(v, t, 0); }, "voxel size");
  expect_error([&] { VdbLevelSet::from_mesh(v, t, 1e-7); }, "too many voxels");
  expect_error([&] { VdbLevelSet::from_mesh(v, t, 0.1, 0.5); }, "band");
  std::filesystem::remove_all(file.parent_path());
}

}  // namespace
}  // namespace tumble
