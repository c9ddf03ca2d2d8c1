// SPDX-License-Identifier: Apache-2.0
#include "generator/tool_facet_groups.h"

#include <gtest/gtest.h>
#include <morph/sweep_polytope.h>
#include <morph/tool.h>
#include <morph/tool_polytope.h>

#include <random>
#include <set>

namespace {

using Eigen::Vector3d;

// Every facet a group skips has, at every probe point of the ball, a value (as the sweep's own
// halfspaces compute it) below the threshold: the skipping cannot change a test "some value at
// least the threshold". Probes: the ball's centre and points on its sphere.
void expect_skipped_facets_stay_below(const morph::ConvexPolytope& tool, std::mt19937& rng) {
  const morph::ToolFacetGroups groups(tool);
  const morph::SweepPolytopeBuilder builder(tool);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> vertex(0, static_cast<int>(tool.vertices.size()) - 1);
  std::size_t skipped_total = 0, facets_total = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vector3d start(40 * unit(rng), 40 * unit(rng), 5 * unit(rng));
    const double length = trial % 5 == 0 ? 0.0 : 2.0 * std::abs(unit(rng));
    const Vector3d end = start + length * Vector3d(unit(rng), unit(rng), 0.3 * unit(rng));
    const auto [a, b] = builder.degenerate(start, end) ? std::pair{start, start}
                                                       : morph::SweepPolytopeBuilder::ordered(start, end);
    const std::vector<morph::Halfspace> planes = builder.halfspaces(start, end);
    // Centres on and near the sweep's surface (a tool vertex at either end), radius 0 to 0.3.
    const Vector3d centre =
        tool.vertices[vertex(rng)] + (trial % 2 ? a : b) + 0.05 * Vector3d(unit(rng), unit(rng), unit(rng));
    const double radius = trial % 3 == 0 ? 0.0 : 0.3 * std::abs(unit(rng));
    const double threshold = (trial % 4 - 2) * 1e-9;
    std::set<int> reached;
    groups.for_each_reaching(centre, radius, a, b, threshold, [&](int k) {
      EXPECT_TRUE(reached.insert(k).second) << "facet " << k << " twice";
      return true;
    });
    std::vector<Vector3d> probes{centre};
    for (int i = 0; i < 40; ++i) {
      Vector3d d(unit(rng), unit(rng), unit(rng));
      if (d.norm() > 1e-3) probes.push_back(centre + radius * d.normalized());
    }
    for (std::size_t k = 0; k < tool.facets.size(); ++k) {
      ++facets_total;
      if (reached.count(static_cast<int>(k))) continue;
      ++skipped_total;
      for (const Vector3d& x : probes)
        ASSERT_LT(planes[k].normal.dot(x) - planes[k].offset, threshold)
            << "facet " << k << " skipped though it reaches the threshold";
    }
  }
  // With many facets the groups must also skip a good part, or they are only overhead.
  if (tool.facets.size() > 500) {
    EXPECT_GT(skipped_total, facets_total / 4) << tool.facets.size() << " facets";
  }
}

TEST(ToolFacetGroups, SkipOnlyFacetsBelowTheThresholdEverywhereInTheBall) {
  std::mt19937 rng(18);
  for (const morph::Tool& tool : {morph::ball_tool(1.5875, 20.0), morph::flat_tool(3.0, 20.0),
                                  morph::sphere_tool(4.0), morph::tapered_ball_tool(1.0, 0.2, 15.0)})
    expect_skipped_facets_stay_below(morph::tool_polytope(tool.profile, 0.004).polytope, rng);
}

TEST(ToolFacetGroups, EveryFacetInExactlyOneGroup) {
  const morph::ConvexPolytope tool =
      morph::tool_polytope(morph::ball_tool(3.0, 40.0).profile, 0.0004).polytope;
  const morph::ToolFacetGroups groups(tool);
  EXPECT_GT(groups.size(), 100u);
  std::vector<int> seen(tool.facets.size(), 0);
  // A huge threshold below every value: nothing may be skipped.
  groups.for_each_reaching(Vector3d(1, 2, 3), 100.0, Vector3d(0, 0, 0), Vector3d(1, 0, 0), -1e9, [&](int k) {
    ++seen[k];
    return true;
  });
  for (std::size_t k = 0; k < seen.size(); ++k) EXPECT_EQ(seen[k], 1) << "facet " << k;
}

}  // namespace
