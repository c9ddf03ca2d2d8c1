// SPDX-License-Identifier: Apache-2.0
// Generator 2's output after its limit step and rounding (morph: degenerate_collapse.h,
// rounding.h), checked by the exact self-intersection test that `erode` runs (CGAL's exact
// predicates, which live in apps): the generator's reproducers where four or more planes meet
// (a ball's pole inside the stock, retraces, a 179.99° turn) give no intersecting triangle pair,
// and the surface is a closed, oriented 2-manifold.
#include <gtest/gtest.h>
#include <morph/erode.h>
#include <morph/tool.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <morphmill/self_intersections.h>

#include <fstream>
#include <string>

#include "common/test_jobs.h"

namespace {

using Eigen::Vector3d;

morph::Job job_of(const Eigen::AlignedBox3d& box, const morph::Tool& tool,
                  const std::vector<Vector3d>& polyline) {
  return morphmill_test::box_polyline_job(box, tool, polyline, 0.05);
}

void expect_valid_solid(const morph::Job& job, const std::string& what) {
  const morph::TriangleMesh mesh = morph::erode(job).mesh;
  EXPECT_TRUE(morph::topology_report(mesh).closed_manifold()) << what;
  EXPECT_EQ(morphmill::find_self_intersections(mesh).pairs, 0u) << what;
}

TEST(Generator2Rounding, PoleRetraceAndNearReversalHaveNoIntersectingPairs) {
  const morph::Tool ball = morph::ball_tool(1.5, 20.0);
  const Eigen::AlignedBox3d plate(Vector3d(0, 0, 0), Vector3d(40, 30, 3));
  // r2: a ball end slot at part depth (its pole in the stock), there and straight back.
  expect_valid_solid(
      job_of(plate, ball, {Vector3d(20, -5, 1.5), Vector3d(20, 15, 1.5), Vector3d(20, -5, 1.5)}),
      "slot there and back");
  // r6: a plunge into the stock and straight back up.
  const Eigen::AlignedBox3d block(Vector3d(0, 0, 0), Vector3d(40, 30, 10));
  expect_valid_solid(job_of(block, morph::ball_tool(3.0, 40.0),
                            {Vector3d(20, 15, 20), Vector3d(20, 15, 5), Vector3d(20, 15, 20)}),
                     "plunge and retract");
  // r11's shape: a slot turning back 3 µm sideways inside the stock.
  const Eigen::AlignedBox3d slab(Vector3d(0, 0, 0), Vector3d(40, 30, 5));
  expect_valid_solid(job_of(slab, ball, {Vector3d(-5, 15, 3), Vector3d(20, 15, 3), Vector3d(-5, 15.003, 3)}),
                     "179.99 degrees");
}

TEST(Generator2Rounding, SharedReproducersHaveNoIntersectingPairs) {
  // The job files themselves, at their own tolerance (0.01), where they are available.
  for (const char* name : {"r2_blind_there_back_partial", "r6_partial_plunge_retract", "r8_reversal_interior",
                           "r9_sphere_square_twice_reversed", "r10b_only_t1", "r11_near_reversal"}) {
    const std::string path = std::string(MORPHMILL_SHARED_DIR) + "/repro/generator/" + name + ".json";
    if (!std::ifstream(path)) GTEST_SKIP() << "reproducers not found at " << MORPHMILL_SHARED_DIR;
    expect_valid_solid(morphmill::load_job(path), name);
  }
}

}  // namespace
