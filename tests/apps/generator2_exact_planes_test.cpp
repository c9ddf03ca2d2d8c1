// SPDX-License-Identifier: Apache-2.0
// Generator 2 with exact planes on the grid (quantize.h): the bundled tool jobs (ball, APT,
// tapered, bull-nose, engraver) and the slots job give closed, oriented 2-manifolds with no
// intersecting triangle pair by the exact test `erode` runs, and no fallback fires; before the
// grid the silhouette planes met the tool's ring edges only up to rounding and left needles
// 3e-14 mm apart (tool_tapered 6 pairs, tool_bullnose 13, slots 42).
#include <gtest/gtest.h>
#include <morph/erode.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <morphmill/self_intersections.h>

#include <string>

namespace {

void expect_exact_solid(const std::string& name) {
  const morph::Job job = morphmill::load_job(std::string(MORPHMILL_TEST_DATA) + "/jobs/" + name + ".json");
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport t = morph::topology_report(result.mesh);
  EXPECT_TRUE(t.closed_manifold()) << name;
  EXPECT_EQ(t.components, 1u) << name;
  EXPECT_EQ(morphmill::find_self_intersections(result.mesh).pairs, 0u) << name;
  EXPECT_EQ(morph::fallbacks_fired(result.stats), 0u) << name;
}

TEST(Generator2ExactPlanes, ToolJobsHaveNoIntersectingPairs) {
  for (const char* name : {"tool_ball", "tool_apt", "tool_tapered", "tool_bullnose", "tool_engraver"})
    expect_exact_solid(name);
}

TEST(Generator2ExactPlanes, SlotsHasNoIntersectingPairs) {
  expect_exact_solid("slots");
}

}  // namespace
