// SPDX-License-Identifier: Apache-2.0
// The bundled jobs (data/jobs/*.json), eroded as `morphmill erode` does: each a closed manifold of
// the pieces it is built to leave, within its tolerance of the exact surface.
#include <gtest/gtest.h>
#include <morph/erode.h>
#include <morph/sweep_distance.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace {

struct BundledJob {
  std::string name;
  std::size_t pieces;
};

std::ostream& operator<<(std::ostream& out, const BundledJob& job) {
  return out << job.name;
}

class BundledJobs : public ::testing::TestWithParam<BundledJob> {};

/// Largest |f| of the exact erosion field over the mesh's vertices and triangle centroids.
double largest_field_error(const morph::TriangleMesh& mesh, const morph::ErosionField& field) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, mesh.triangles.size()), 0.0,
      [&](const tbb::blocked_range<std::size_t>& range, double worst) {
        for (std::size_t t = range.begin(); t != range.end(); ++t) {
          const auto& tri = mesh.triangles[t];
          const Eigen::Vector3d centroid =
              (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
          worst = std::max(
              {worst, std::abs(field.value(centroid)), std::abs(field.value(mesh.vertices[tri[0]]))});
        }
        return worst;
      },
      [](double a, double b) { return std::max(a, b); });
}

TEST_P(BundledJobs, ErodeToAClosedManifoldOfTheKnownPiecesWithinTolerance) {
  const morph::Job job =
      morphmill::load_job(std::string(MORPHMILL_TEST_DATA) + "/jobs/" + GetParam().name + ".json");
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold())
      << topology.boundary_edges << " open, " << topology.non_manifold_edges << " non-manifold edges";
  EXPECT_EQ(topology.components, GetParam().pieces);
  EXPECT_LE(largest_field_error(result.mesh, morph::ErosionField(job)), job.tolerance);
}

INSTANTIATE_TEST_SUITE_P(Jobs, BundledJobs,
                         ::testing::Values(BundledJob{"single_slot", 1}, BundledJob{"through_slots", 3},
                                           BundledJob{"leave_reenter", 1}, BundledJob{"cylinder_groove", 1},
                                           BundledJob{"mesh_stock", 1}, BundledJob{"slots", 1},
                                           BundledJob{"helix_pocket", 1}, BundledJob{"crossing_rose", 1},
                                           BundledJob{"chips", 1}),
                         [](const ::testing::TestParamInfo<BundledJob>& info) { return info.param.name; });

// data/jobs/comb.json by generator 2: eleven ball-end slots through a 60 x 30 x 5 plate from its
// edge y = 0 to y = 20, with the ball below the plate, so each removes a stadium prism of the
// plate (the shank's section: 2r x 20 and a half disc at the slot's end), plunging and
// retracting beside the plate or at a slot's end. One piece, twelve teeth.
TEST(BundledComb, GeneratorTwoLeavesOnePieceOfTheStadiumPrismsVolume) {
  const morph::Job job = morphmill::load_job(std::string(MORPHMILL_TEST_DATA) + "/jobs/comb.json");
  constexpr double length = 60, width = 30, thickness = 5, radius = 1.5, slot_end = 20;
  constexpr int slots = 11;
  ASSERT_EQ(job.stock.box.sizes(), Eigen::Vector3d(length, width, thickness));
  ASSERT_EQ(job.tools.at(1).radius, radius);
  const morph::ErodeResult result = morph::erode(job, morph::ErodeOptions{});
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold())
      << topology.boundary_edges << " open, " << topology.non_manifold_edges << " non-manifold edges";
  EXPECT_EQ(topology.components, 1u);
  const double slot_section = 2 * radius * slot_end + M_PI * radius * radius / 2;
  const double exact = length * width * thickness - slots * thickness * slot_section;
  // The slots' walls, each within the tolerance of the exact wall, bound the volume's error.
  const double walls = slots * thickness * (2 * slot_end + M_PI * radius);
  EXPECT_NEAR(morph::enclosed_volume(result.mesh), exact, job.tolerance * walls);
  EXPECT_LE(largest_field_error(result.mesh, morph::ErosionField(job)), job.tolerance);
}

}  // namespace
