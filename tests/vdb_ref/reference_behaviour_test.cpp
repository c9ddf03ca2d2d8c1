// SPDX-License-Identifier: Apache-2.0
// The reference's contract besides accuracy: errors before long work, provenance tags,
// determinism across thread counts, progress stages and interruption, voxel-size helpers.
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <vdb_ref/reference.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "vdb_ref/job_builders.h"

namespace {

using namespace vdb_ref_test;
using Eigen::Vector3d;

morph::Job groove_job() {
  morph::Job job = box_job(Vector3d(0, 0, 0), Vector3d(20, 16, 8));
  add_tool(job, 1, morph::ToolType::Sphere, 3.0);
  add_path(job, {line(Vector3d(-5, 8, 9), Vector3d(25, 8, 9), 1, 42)});
  return job;
}

vdb_ref::ReferenceOptions options_with_voxel(double voxel) {
  vdb_ref::ReferenceOptions options;
  options.voxel_size = voxel;
  return options;
}

template <class Error>
std::string message_of(const morph::Job& job, const vdb_ref::ReferenceOptions& options) {
  try {
    vdb_ref::compute_reference(job, options);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an exception";
  return "";
}

TEST(ReferenceInput, RejectsVoxelSizesThatAreNotFinitePositive) {
  for (double voxel :
       {0.0, -0.5, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    const std::string message = message_of<morph::InputError>(groove_job(), options_with_voxel(voxel));
    EXPECT_NE(message.find("voxel size"), std::string::npos) << message;
  }
}

TEST(ReferenceInput, RejectsANonClosedStockMeshNamingIt) {
  morph::Job job = groove_job();
  job.stock.type = morph::StockType::Mesh;
  job.stock.mesh_path = "part.stl";
  // A tetrahedron missing one face.
  job.stock.mesh.vertices = {Vector3d(0, 0, 0), Vector3d(10, 0, 0), Vector3d(0, 10, 0), Vector3d(0, 0, 10)};
  job.stock.mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}};
  const std::string message = message_of<morph::InputError>(job, options_with_voxel(1.0));
  EXPECT_NE(message.find("part.stl"), std::string::npos) << message;
  EXPECT_NE(message.find("not closed"), std::string::npos) << message;
}

TEST(ReferenceInput, RejectsAGridOverTheMemoryCapBeforeComputing) {
  vdb_ref::ReferenceOptions options = options_with_voxel(0.001);  // ~10^9 narrow-band voxels
  options.memory_cap_bytes = std::size_t(1) << 30;
  struct CountingProgress : morph::Progress {
    int stages = 0;
    void begin(const std::string&, std::size_t) override { ++stages; }
  } progress;
  options.progress = &progress;
  const std::string message = message_of<morph::LimitError>(groove_job(), options);
  EXPECT_NE(message.find("MiB"), std::string::npos) << message;
  EXPECT_EQ(progress.stages, 0) << "the cap is checked before any stage starts";
  // The same job fits at a sensible voxel.
  EXPECT_LT(vdb_ref::estimate_reference_memory(groove_job(), options_with_voxel(0.5)), std::size_t(1) << 30);
}

TEST(ReferenceInput, RejectsToolsWithoutAProfileNamingThem) {
  morph::Job job = groove_job();
  job.tools[1].type = morph::ToolType::Flat;  // assembled field by field: no profile to rasterise
  const std::string message = message_of<morph::InputError>(job, options_with_voxel(1.0));
  EXPECT_NE(message.find("flat"), std::string::npos) << message;
  EXPECT_NE(message.find("profile"), std::string::npos) << message;
}

TEST(ReferenceInput, ParsesVoxelListsAndNamesOutputs) {
  EXPECT_EQ(vdb_ref::parse_voxel_sizes("0.4,0.2, 0.1", "--voxel"), (std::vector<double>{0.4, 0.2, 0.1}));
  EXPECT_THROW(vdb_ref::parse_voxel_sizes("0.4,abc", "--voxel"), morph::InputError);
  EXPECT_THROW(vdb_ref::parse_voxel_sizes("0.4,-1", "--voxel"), morph::InputError);
  EXPECT_THROW(vdb_ref::parse_voxel_sizes("", "--voxel"), morph::InputError);
  EXPECT_EQ(vdb_ref::path_with_voxel_suffix("out/ref.ply", 0.4), "out/ref_v0.4.ply");
  EXPECT_EQ(vdb_ref::path_with_voxel_suffix("out.d/ref", 0.25), "out.d/ref_v0.25");
  EXPECT_EQ(vdb_ref::path_with_voxel_suffix("stats.json", 0.1), "stats_v0.1.json");
}

TEST(ReferenceOutput, TagsSweptFacesWithTheirMoveAndStockFacesWithout) {
  const morph::Job job = groove_job();
  const vdb_ref::ReferenceResult result = vdb_ref::compute_reference(job, options_with_voxel(0.5));
  ASSERT_EQ(result.mesh.tags.size(), result.mesh.triangle_count());
  std::size_t swept = 0, stock = 0;
  for (std::size_t t = 0; t < result.mesh.triangle_count(); ++t) {
    const morph::FaceTag& tag = result.mesh.tags[t];
    EXPECT_EQ(tag.kind, morph::PatchKind::Reference);
    const auto& tri = result.mesh.triangles[t];
    const Vector3d c =
        (result.mesh.vertices[tri[0]] + result.mesh.vertices[tri[1]] + result.mesh.vertices[tri[2]]) / 3;
    // The groove floor (deeper than 0.5 below the top, near the groove's axis) is swept; the
    // bottom face is stock.
    if (c.z() < 7.5 && c.z() > 5.5 && std::abs(c.y() - 8) < 2 && c.x() > 2 && c.x() < 18) {
      EXPECT_EQ(tag.source, 0);
      EXPECT_EQ(tag.line, 42);
      ++swept;
    }
    if (c.z() < 0.1) {
      EXPECT_EQ(tag.source, -1);
      EXPECT_EQ(tag.line, 0);
      ++stock;
    }
  }
  EXPECT_GT(swept, 10u);
  EXPECT_GT(stock, 10u);
}

TEST(ReferenceOutput, IdenticalWithAndWithoutThreads) {
  const morph::Job job = groove_job();
  vdb_ref::ReferenceOptions threaded = options_with_voxel(0.4), sequential = options_with_voxel(0.4);
  sequential.threaded = false;
  const vdb_ref::ReferenceResult a = vdb_ref::compute_reference(job, threaded);
  const vdb_ref::ReferenceResult b = vdb_ref::compute_reference(job, sequential);
  ASSERT_EQ(a.mesh.vertex_count(), b.mesh.vertex_count());
  ASSERT_EQ(a.mesh.triangle_count(), b.mesh.triangle_count());
  EXPECT_TRUE(a.mesh.vertices == b.mesh.vertices);
  EXPECT_TRUE(a.mesh.triangles == b.mesh.triangles);
  EXPECT_TRUE(a.mesh.tags == b.mesh.tags);
  ASSERT_EQ(a.pieces.size(), b.pieces.size());
  EXPECT_EQ(a.pieces[0].volume, b.pieces[0].volume);
  EXPECT_EQ(a.pieces[0].area, b.pieces[0].area);
  EXPECT_EQ(a.stats.active_voxels, b.stats.active_voxels);
}

TEST(ReferenceOutput, ReportsStagesAndStopsWhenInterrupted) {
  struct RecordingProgress : morph::Progress {
    std::vector<std::string> stages;
    std::string stop_at;
    void begin(const std::string& stage, std::size_t) override { stages.push_back(stage); }
    bool interrupted() const override {
      return !stop_at.empty() && !stages.empty() && stages.back() == stop_at;
    }
  } progress;
  vdb_ref::ReferenceOptions options = options_with_voxel(0.5);
  options.progress = &progress;
  vdb_ref::compute_reference(groove_job(), options);
  EXPECT_EQ(progress.stages, (std::vector<std::string>{"stock", "sweep culling", "sweep sampling",
                                                       "difference", "mesh", "segment"}));
  progress.stages.clear();
  progress.stop_at = "sweep sampling";
  EXPECT_THROW(vdb_ref::compute_reference(groove_job(), options), morph::Interrupted);
  EXPECT_EQ(progress.stages.back(), "sweep sampling");
}

TEST(ReferenceStock, MeshStockMatchesTheBoxItDescribes) {
  // The same groove job with the box given as a closed 12-triangle mesh (OpenVDB mesh-to-volume).
  morph::Job job = groove_job();
  const vdb_ref::ReferenceResult from_box = vdb_ref::compute_reference(job, options_with_voxel(0.3));
  const Eigen::AlignedBox3d box = job.stock.box;
  job.stock.type = morph::StockType::Mesh;
  for (int i = 0; i < 8; ++i)
    job.stock.mesh.vertices.push_back(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)));
  // Corners: bit 0 = x, bit 1 = y, bit 2 = z; faces wound counter-clockwise seen from outside.
  job.stock.mesh.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                              {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  const vdb_ref::ReferenceResult from_mesh = vdb_ref::compute_reference(job, options_with_voxel(0.3));
  ASSERT_EQ(from_mesh.pieces.size(), 1u);
  // The groove: a sphere of radius 3 whose lowest point is 2 below the top, along all 20 of x.
  const double volume = 20.0 * 16.0 * 8.0 - circular_segment_area(3.0, 2.0) * 20.0;
  EXPECT_NEAR(from_box.volume(), volume, 0.005 * volume);
  EXPECT_NEAR(from_mesh.volume(), volume, 0.005 * volume);
}

TEST(ReferenceStock, CylinderStockVolumeAndArea) {
  morph::Job job;
  job.stock.type = morph::StockType::Cylinder;
  job.stock.base = Vector3d(1, 2, 3);
  job.stock.axis = Vector3d(1, 1, 1).normalized();
  job.stock.radius = 6.0;
  job.stock.height = 15.0;
  const vdb_ref::ReferenceResult result = vdb_ref::compute_reference(job, options_with_voxel(0.3));
  const vdb_ref::ReferenceResult fine = vdb_ref::compute_reference(job, options_with_voxel(0.15));
  ASSERT_EQ(result.pieces.size(), 1u);
  const double volume = M_PI * 36.0 * 15.0, area = 2.0 * M_PI * 6.0 * (6.0 + 15.0);
  EXPECT_NEAR(result.volume(), volume, 0.005 * volume);
  // The two rim circles are sharp edges, cut by about a voxel: the area converges linearly, and
  // its Richardson extrapolation cancels that term.
  EXPECT_LT(result.area(), fine.area());
  EXPECT_LT(fine.area(), area);
  EXPECT_NEAR(2.0 * fine.area() - result.area(), area, 0.005 * area);
  EXPECT_TRUE(result.mesh.tags.empty() || result.mesh.tags[0].source == -1);
}

TEST(ReferenceStats, CountsVoxelsMemoryAndStageTimes) {
  const vdb_ref::ReferenceResult result = vdb_ref::compute_reference(groove_job(), options_with_voxel(0.5));
  const vdb_ref::ReferenceStats& s = result.stats;
  EXPECT_EQ(s.voxel_size, 0.5);
  // The narrow band of 2 * 3 voxels around ~ area / voxel^2 surface voxels.
  const double surface_voxels = result.area() / (0.5 * 0.5);
  EXPECT_GT(static_cast<double>(s.active_voxels), 4.0 * surface_voxels);
  EXPECT_LT(static_cast<double>(s.active_voxels), 9.0 * surface_voxels);
  EXPECT_GT(s.memory_bytes, s.active_voxels * sizeof(float));
  EXPECT_GE(s.estimated_bytes, s.memory_bytes) << "the up-front estimate should not undershoot";
  EXPECT_LT(s.estimated_bytes, 8 * s.memory_bytes) << "nor overshoot wildly";
  EXPECT_GT(s.sweep_leaf_evaluations, 0u);
  EXPECT_GT(s.total_seconds, 0.0);
  EXPECT_GE(s.total_seconds, s.stock_seconds + s.sweep_seconds + s.difference_seconds);
}

}  // namespace

TEST(ReferenceFile, VdbGridCarriesUnitsVoxelJobAndGivenMetadata) {
  morph::Job job = groove_job();
  job.name = "groove";
  vdb_ref::ReferenceOptions options = options_with_voxel(0.5);
  options.vdb_output_path =
      ::testing::TempDir() + "/reference_metadata_" + std::to_string(::getpid()) + ".vdb";
  options.vdb_metadata = {{"morphmill_version", "test-1"}};
  vdb_ref::compute_reference(job, options);
  const std::vector<vdb_ref::GridMetadata> grids = vdb_ref::read_grid_metadata(options.vdb_output_path);
  std::remove(options.vdb_output_path.c_str());
  ASSERT_EQ(grids.size(), 1u);
  EXPECT_EQ(grids[0].grid_name, "erosion");
  auto value = [&](const std::string& name) {
    for (const auto& [key, text] : grids[0].entries)
      if (key == name) return text;
    return std::string("(missing)");
  };
  EXPECT_EQ(value("units"), "mm");
  EXPECT_EQ(value("voxel_size"), "0.5");
  EXPECT_EQ(value("job"), "groove");
  EXPECT_EQ(value("morphmill_version"), "test-1");
  EXPECT_EQ(value("class"), "level set");  // OpenVDB's own, so Blender/Houdini read it as an SDF
  EXPECT_THROW(vdb_ref::read_grid_metadata(options.vdb_output_path + ".missing"), morph::IoError);
}
