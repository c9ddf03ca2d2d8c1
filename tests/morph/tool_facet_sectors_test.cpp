// SPDX-License-Identifier: Apache-2.0
#include "generator/tool_facet_sectors.h"

#include <gtest/gtest.h>
#include <morph/aabb_tree.h>
#include <morph/tool.h>
#include <morph/tool_polytope.h>

#include <random>
#include <vector>

namespace {

using Eigen::AlignedBox3d;
using Eigen::Vector3d;

std::vector<AlignedBox3d> facet_boxes(const morph::ConvexPolytope& tool) {
  std::vector<AlignedBox3d> boxes;
  for (const morph::PolytopeFacet& f : tool.facets) {
    AlignedBox3d box;
    for (int v : f.loop) box.extend(tool.vertices[static_cast<std::size_t>(v)]);
    boxes.push_back(box);
  }
  return boxes;
}

// Every facet whose box meets the query is listed, and listed once; and for small queries the
// listing is much shorter than all facets, or it would save nothing over a scan.
void expect_every_meeting_box_listed(const std::vector<AlignedBox3d>& boxes, std::mt19937& rng,
                                     bool expect_tight) {
  const morph::ToolFacetSectors sectors(boxes);
  AlignedBox3d all;
  for (const AlignedBox3d& b : boxes) all.extend(b);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<std::size_t> facet(0, boxes.size() - 1);
  std::size_t listed = 0, meeting = 0, small_queries = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    // Small boxes about facet corners (some on the axis), and boxes of any size anywhere.
    AlignedBox3d query;
    if (trial % 4 != 3) {
      const AlignedBox3d& near = boxes[facet(rng)];
      const Vector3d corner = trial % 2 ? near.min() : near.max();
      const double size = trial % 3 == 0 ? 0.0 : 0.2 * unit(rng) * all.diagonal().norm() / 10;
      const Vector3d offset(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
      query = AlignedBox3d(corner + size * offset, corner + size * offset);
      query.extend(corner + size * Vector3d(unit(rng), unit(rng), unit(rng)));
      if (trial % 11 == 0) query.extend(Vector3d(0, 0, corner.z()));  // reaching the axis
    } else {
      const Vector3d p = all.min() + all.diagonal().cwiseProduct(Vector3d(unit(rng), unit(rng), unit(rng)));
      const Vector3d q = all.min() + all.diagonal().cwiseProduct(Vector3d(unit(rng), unit(rng), unit(rng)));
      query = AlignedBox3d(p.cwiseMin(q), p.cwiseMax(q));
    }
    std::vector<int> seen(boxes.size(), 0);
    sectors.for_each_candidate(query, [&](std::uint32_t k) { ++seen[k]; });
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      ASSERT_LE(seen[k], 1) << "facet " << k << " listed twice";
      const bool meets = morph::boxes_meet(boxes[k], query);
      if (meets) {
        ASSERT_EQ(seen[k], 1) << "facet " << k << " meets the query box but was not listed";
      }
      if (trial % 4 != 3) {
        listed += static_cast<std::size_t>(seen[k]);
        meeting += meets;
      }
    }
    small_queries += trial % 4 != 3;
  }
  // Where most facets are in rings, a small query lists under a quarter of them on average.
  if (expect_tight && 2 * sectors.everywhere() < boxes.size()) {
    EXPECT_LT(4 * listed, boxes.size() * small_queries) << listed << " listed, " << meeting << " meeting";
  }
}

TEST(ToolFacetSectors, ListEveryFacetWhoseBoxMeetsTheQuery) {
  std::mt19937 rng(18);
  for (const morph::Tool& tool :
       {morph::ball_tool(1.5875, 25.4), morph::flat_tool(3.0, 20.0), morph::sphere_tool(4.0),
        morph::tapered_ball_tool(1.0, 0.2, 15.0), morph::conical_tool(3.0, 90.0, 10.0),
        morph::conical_tool(3.0, 60.0, 12.0, 0.5), morph::bullnose_tool(5.0, 1.0, 20.0),
        morph::spheroid_tool(2.0, 6.0)}) {
    const morph::ConvexPolytope polytope = morph::tool_polytope(tool.profile, 0.004).polytope;
    SCOPED_TRACE(morph::describe(tool));
    expect_every_meeting_box_listed(facet_boxes(polytope), rng, true);
  }
}

// Nothing assumes a tool of revolution: a polytope off the axis, and one with boxes of every size.
TEST(ToolFacetSectors, HoldForAnyBoxes) {
  std::mt19937 rng(7);
  const morph::ConvexPolytope ball = morph::tool_polytope(morph::ball_tool(2.0, 10.0).profile, 0.01).polytope;
  std::vector<AlignedBox3d> moved = facet_boxes(ball);
  for (AlignedBox3d& b : moved) b.translate(Vector3d(5.0, -3.0, 1.0));
  expect_every_meeting_box_listed(moved, rng, false);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<AlignedBox3d> random;
  for (int k = 0; k < 300; ++k) {
    const Vector3d p(unit(rng), unit(rng), unit(rng)), q(unit(rng), unit(rng), unit(rng));
    random.emplace_back(p.cwiseMin(q), p.cwiseMax(q));
  }
  expect_every_meeting_box_listed(random, rng, false);
}

TEST(ToolFacetSectors, SideFacetsOfABallEndFallIntoRingsAndSectors) {
  const morph::ToolPolytope tool = morph::tool_polytope(morph::ball_tool(1.5875, 25.4).profile, 0.004);
  const morph::ToolFacetSectors sectors(facet_boxes(tool.polytope));
  EXPECT_EQ(sectors.cells(), tool.sectors);
  // A side facet's box reaches its own sector and at most one either side, but in the few rings
  // about the pole, where a sector is narrower than the facet's box.
  std::size_t narrow = 0;
  for (std::size_t r = 0; r < sectors.rings(); ++r) narrow += sectors.ring_span(r) <= 3;
  EXPECT_GE(narrow + 4, sectors.rings());
  EXPECT_GE(sectors.rings(), 10u);
  // The flat top, the pole's N-gon and the ring about it at most.
  EXPECT_LE(sectors.everywhere(), 2u + static_cast<std::size_t>(tool.sectors));
  EXPECT_GE(sectors.rings(), tool.meridian.size() - 3);
}

}  // namespace
