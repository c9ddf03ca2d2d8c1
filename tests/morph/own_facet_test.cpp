// SPDX-License-Identifier: Apache-2.0
// A sweep facet within its own polytope (generator/own_facet.h): with every plane of the sweep
// exact, the planes through the facet's vertices bound it alone; the piece is the one that every
// plane of the sweep leaves, for every tool shape and every kind of motion.
#include "generator/own_facet.h"
#include "generator/tool_facet_groups.h"

#include <morph/quantize.h>
#include <morph/stock_polytope.h>
#include <morph/tool.h>
#include <morph/tool_polytope.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace {

using Eigen::Vector3d;

std::vector<std::pair<std::uint64_t, int>> sorted_edges(const morph::ConvexPiece& piece) {
  std::vector<std::pair<std::uint64_t, int>> edges;
  for (const morph::ExactPlane& e : piece.edges) edges.emplace_back(e.rank, e.direction);
  std::sort(edges.begin(), edges.end());
  return edges;
}

TEST(OwnFacet, AnExactSweepsFacetIsBoundedByThePlanesThroughItsVerticesAlone) {
  const double tolerance = 0.1;
  const std::vector<morph::Tool> tools = {morph::sphere_tool(1.5),
                                          morph::ball_tool(1.5, 6.0),
                                          morph::flat_tool(1.5, 6.0),
                                          morph::bullnose_tool(1.5, 0.5, 6.0),
                                          morph::conical_tool(2.0, 90.0, 6.0),
                                          morph::tapered_ball_tool(0.75, 10.0, 6.0)};
  const Vector3d start(10, 10, 2);
  // Level along an axis and diagonally, a ramp, a plunge, a move in a general 3D direction, and
  // none at all.
  const std::vector<Vector3d> motions = {Vector3d(3, 0, 0),          Vector3d(2, 2, 0),
                                         Vector3d(2, 1, -0.5),       Vector3d(0, 0, -2.5),
                                         Vector3d(1.25, -0.75, 1.5), Vector3d(0, 0, 0)};
  const morph::StockPolytope stock =
      morph::box_stock_polytope(Eigen::AlignedBox3d(Vector3d(0, 0, -10), Vector3d(20, 20, 3)));
  int facets_checked = 0, cut_by_stock = 0;
  for (std::size_t t = 0; t < tools.size(); ++t) {
    const morph::SweepPolytopeBuilder builder(
        morph::tool_polytope(tools[t].profile, 0.4 * tolerance).polytope);
    const morph::ToolFacetGroups groups(builder.tool());
    std::vector<std::vector<int>> members;
    for (std::size_t g = 0; g < groups.size(); ++g) members.push_back(groups.members(g));
    const morph::ToolIncidence incidence = morph::tool_incidence(builder);
    const int grid = morph::grid_exponent_for(0.4 * tolerance);
    for (const Vector3d& motion : motions) {
      const Vector3d from = morph::snap_to_grid(start, grid), to = morph::snap_to_grid(start + motion, grid);
      ASSERT_TRUE(builder.exact(from, to));
      morph::OwnPlanes own = morph::own_planes(builder, groups, members, incidence, from, to, 7);
      ASSERT_TRUE(own.exact);
      // Every plane of the sweep, made at once: the planes own_facet() makes one at a time are these.
      const std::vector<morph::ExactPlane> all = morph::sweep_planes(builder.halfspaces(from, to), 7);
      ASSERT_EQ(own.plane_count(), all.size());
      morph::OwnFacetScratch scratch;
      for (std::size_t f = 0; f < all.size(); ++f) {
        const auto facet = static_cast<int>(f);
        const morph::ConvexPiece piece =
            morph::own_facet(own, facet, morph::facet_points(builder, own, facet), stock, scratch);
        // Every other plane of the sweep, in decreasing rank as the first loop clips.
        std::vector<morph::ExactPlane> others;
        for (std::size_t k = 0; k < all.size(); ++k)
          if (k != f) others.push_back(all[k]);
        std::reverse(others.begin(), others.end());
        const morph::ConvexPiece whole = morph::intersect(morph::piece_in_stock(all[f], stock), others);
        const std::string what = "tool " + std::to_string(t) + ", motion (" + std::to_string(motion.x()) +
                                 ", " + std::to_string(motion.y()) + ", " + std::to_string(motion.z()) +
                                 "), plane " + std::to_string(f);
        ASSERT_EQ(piece.empty(), whole.empty()) << what;
        if (piece.empty()) continue;
        EXPECT_EQ(piece.support.rank, whole.support.rank) << what;
        EXPECT_EQ(piece.support.normal, whole.support.normal) << what;
        EXPECT_EQ(piece.support.offset, whole.support.offset) << what;
        EXPECT_EQ(sorted_edges(piece), sorted_edges(whole)) << what;
        ++facets_checked;
        for (const morph::ExactPlane& e : piece.edges)
          cut_by_stock += e.rank < morph::sweep_rank(0, 0) ? 1 : 0;
      }
    }
  }
  // The facets were there to compare, and the stock's top cut some of them.
  EXPECT_GT(facets_checked, 1000);
  EXPECT_GT(cut_by_stock, 0);
}

}  // namespace
