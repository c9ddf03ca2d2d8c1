// SPDX-License-Identifier: Apache-2.0
// The public API (morphmill/morphmill.h) against closed forms: the single slot job (a ball end of
// radius 2 through a 40 x 20 x 10 block, its centre on the top face: half a cylinder leaves it)
// and a cube measured against itself moved.
#include <morph/exceptions.h>
#include <morphmill/morphmill.h>

#include <gtest/gtest.h>

#include "common/test_jobs.h"

#include <cmath>
#include <regex>
#include <string>

namespace {

const std::string kData = MORPHMILL_TEST_DATA;
const double kPi = std::acos(-1.0);
// 40 x 20 x 10 block minus half a cylinder of radius 2 and length 40.
const double kSlotVolume = 40.0 * 20.0 * 10.0 - 0.5 * kPi * 2.0 * 2.0 * 40.0;

TEST(MorphmillApi, VersionIsTheProjectVersion) {
  EXPECT_TRUE(std::regex_match(morphmill::version(), std::regex(R"(\d+\.\d+\.\d+)"))) << morphmill::version();
}

TEST(MorphmillApi, ErodeGivesTheClosedFormVolumeAndAValidSolid) {
  const morph::Job job = morphmill::load_job(kData + "/jobs/single_slot.json");
  const morphmill::ErodeReport part = morphmill::erode(job);
  EXPECT_TRUE(part.valid());
  EXPECT_EQ(part.self_intersections, 0u);
  EXPECT_EQ(part.topology.components, 1);
  // The surface lies within the tolerance 0.01 of the exact one, which is flat but for the slot's
  // half cylinder (area pi * 2 * 40 ~ 251): the volume is off by at most 0.01 times that area.
  EXPECT_NEAR(part.topology.volume, kSlotVolume, 0.01 * kPi * 2.0 * 40.0);
  EXPECT_EQ(part.mesh.tags.size(), part.mesh.triangle_count());
}

TEST(MorphmillApi, ReferenceAtTheGivenVoxelSizeHasTheClosedFormVolume) {
  const morph::Job job = morphmill::load_job(kData + "/jobs/single_slot.json");
  morphmill::ReferenceSettings settings;
  settings.voxel_size = 0.5;
  const vdb_ref::ReferenceResult reference = morphmill::reference(job, settings);
  EXPECT_DOUBLE_EQ(reference.stats.voxel_size, 0.5);
  ASSERT_EQ(reference.pieces.size(), 1u);
  // Dual contouring cuts each sharp edge by about one voxel: a loss of the order of voxel^2 times
  // the length of the sharp edges (the block's 280 mm and the slot rims' 80 mm).
  EXPECT_NEAR(reference.volume(), kSlotVolume, 0.5 * 0.5 * 360.0);
}

TEST(MorphmillApi, DefaultVoxelSizeIsASixthOfTheToolRadius) {
  const morph::Job job = morphmill::load_job(kData + "/jobs/single_slot.json");
  EXPECT_DOUBLE_EQ(morphmill::default_voxel_size(job), 2.0 / 6.0);
}

TEST(MorphmillApi, DeviationOfAMovedCubeIsTheDisplacement) {
  const morph::TriangleMesh cube = morphmill::read_mesh(kData + "/meshes/cube.stl");
  morph::TriangleMesh moved = cube;
  for (Eigen::Vector3d& vertex : moved.vertices) vertex.z() += 0.3;
  morphmill::DeviationSettings settings;
  settings.face_samples = 5000;
  const raytest::TwoSidedDeviation same = morphmill::deviation(cube, cube, settings);
  EXPECT_LE(same.hausdorff, 1e-12);
  const raytest::TwoSidedDeviation d = morphmill::deviation(cube, moved, settings);
  // The bottom face's points are 0.3 below the moved cube's bottom and farther from its sides.
  EXPECT_NEAR(d.hausdorff, 0.3, 1e-9);
  EXPECT_EQ(d.a_to_b.values.size(), d.a_to_b.samples.size());
  EXPECT_GE(d.a_to_b.samples.size(), 5000u);
}

TEST(MorphmillApi, VerifyHoldsOnTheSingleSlot) {
  const morph::Job job = morphmill::load_job(kData + "/jobs/single_slot.json");
  morphmill::VerifySettings settings;
  settings.voxel_size = 0.5;
  settings.face_samples = 5000;
  const morphmill::VerifyReport report = morphmill::verify(job, settings);
  EXPECT_TRUE(report.verdict);
  EXPECT_TRUE(report.generator_within_tolerance);
  EXPECT_TRUE(report.generator_skipped.empty());
  EXPECT_DOUBLE_EQ(report.tolerance, 0.01);
  EXPECT_NEAR(report.agreement_bound, 0.01 + std::sqrt(3.0) * 0.5, 1e-12);
  EXPECT_LE(report.generator_to_exact.stats.max_abs, 0.01);
  EXPECT_GT(report.generator_mesh.triangle_count(), 0u);
  EXPECT_GT(report.reference_mesh.triangle_count(), 0u);
  EXPECT_TRUE(report.summary.is_object());
}

TEST(MorphmillApi, ErrorsAreExceptionsNamingTheProblem) {
  try {
    morphmill::load_job(kData + "/jobs/no_such_job.json");
    FAIL() << "no exception";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_job.json"), std::string::npos) << e.what();
  }
  // A negative tolerance is bad input, named.
  const morph::Job flat = morphmill::load_job(kData + "/jobs/tool_flat.json");
  morphmill::ErodeSettings negative;
  negative.tolerance = -0.01;
  try {
    morphmill::erode(flat, negative);
    FAIL() << "no exception";
  } catch (const morph::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tolerance"), std::string::npos) << e.what();
  }
}

// A flat end mill of radius 3 cutting level 2 deep straight through a 40 x 20 x 10 block removes a
// 40 x 6 x 2 box: the surface is valid and holds that volume.
TEST(MorphmillApi, ErodeBuildsAFlatEndMillsSlot) {
  const morph::Job job = morphmill_test::box_polyline_job(
      Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(40, 20, 10)), morph::flat_tool(3.0, 20.0),
      {Eigen::Vector3d(-5, 10, 8), Eigen::Vector3d(45, 10, 8)}, 0.01);
  const morphmill::ErodeReport part = morphmill::erode(job);
  EXPECT_TRUE(part.valid());
  EXPECT_EQ(part.topology.components, 1);
  // The slot's walls are the tool's polygonal side, within the tolerance of the cylinder: the
  // volume is off by at most 0.01 times the cut area (walls 2 x 40 x 2, floor 40 x 6).
  EXPECT_NEAR(part.topology.volume, 40.0 * 20.0 * 10.0 - 40.0 * 6.0 * 2.0, 0.01 * (160.0 + 240.0));
  // Deterministic: the same surface again.
  const morphmill::ErodeReport again = morphmill::erode(job);
  EXPECT_EQ(again.mesh.vertices, part.mesh.vertices);
  EXPECT_DOUBLE_EQ(again.topology.volume, part.topology.volume);
}

}  // namespace
