// SPDX-License-Identifier: Apache-2.0
#include <morph/joint_culling.h>
#include <morph/sweep_culling.h>
#include <morph/sweep_polytope.h>
#include <morph/tool_polytope.h>

#include <gtest/gtest.h>

#include <cmath>

#include "morph/tool_shapes_support.h"

namespace {

using Eigen::AlignedBox3d;
using Eigen::Vector3d;

constexpr double kDeviation = 0.004;
constexpr double kOn = 1e-9;  // plane values within this of zero are on the plane

morph::Move line(const Vector3d& from, const Vector3d& to) {
  morph::Move m;
  m.start = from;
  m.end = to;
  m.tool = 1;
  return m;
}

std::vector<bool> joints(const morph::SweepPolytopeBuilder& sweeps, const std::vector<morph::Move>& moves) {
  std::vector<bool> joined(moves.size(), false);
  for (std::size_t i = 1; i < moves.size(); ++i)
    joined[i] = morph::joined_at_joint(sweeps, moves[i - 1], moves[i]);
  return joined;
}

// A raster of three rows over a sloping floor (joints along each row), a step between rows, a
// retrace, a plunge and its retract, and a zero move: every kind of joint and coincidence.
std::vector<morph::Move> small_job() {
  std::vector<morph::Move> moves;
  Vector3d at(1.0, 2.0, 0.5);
  auto to = [&](const Vector3d& next) {
    moves.push_back(line(at, next));
    at = next;
  };
  to(Vector3d(1.0, 2.0, -0.8));  // plunge
  for (int row = 0; row < 3; ++row) {
    const double y = 2.0 + 0.9 * row;
    for (int k = 1; k <= 4; ++k) {
      const double x = row % 2 == 0 ? 1.0 + 2.0 * k : 9.0 - 2.0 * k;
      to(Vector3d(x, y, -0.8 - 0.05 * x + 0.02 * row));
    }
    if (row < 2) to(Vector3d(at.x(), y + 0.9, at.z()));
  }
  const Vector3d back = moves[moves.size() - 2].start;
  to(back);                           // a retrace of the last move
  to(at);                             // and of that
  to(at);                             // a zero move
  to(Vector3d(at.x(), at.y(), 0.5));  // retract
  return moves;
}

// Every vertex of a facet, in order.
std::vector<Vector3d> corners(const morph::ConvexPolytope& p, int facet) {
  std::vector<Vector3d> out;
  for (int v : p.facets[facet].loop) out.push_back(p.vertices[v]);
  return out;
}

// The facet's centroid and the points half way from it to each vertex.
std::vector<Vector3d> samples(const std::vector<Vector3d>& polygon) {
  Vector3d c = Vector3d::Zero();
  for (const Vector3d& v : polygon) c += v;
  c /= static_cast<double>(polygon.size());
  std::vector<Vector3d> out{c};
  for (const Vector3d& v : polygon) out.push_back(0.5 * (c + v));
  return out;
}

// Points spread over the facet: its corners and a grid on each triangle of its fan.
std::vector<Vector3d> spread(const std::vector<Vector3d>& polygon) {
  std::vector<Vector3d> out(polygon);
  constexpr int kSteps = 3;
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; i + j <= kSteps; ++j) {
        const double u = double(i) / kSteps, v = double(j) / kSteps;
        out.push_back(polygon[0] + u * (polygon[k] - polygon[0]) + v * (polygon[k + 1] - polygon[0]));
      }
  return out;
}

// Against brute force on the polytopes themselves, for each facet's part in the stock (all the
// carving keeps): every culled facet has none, or lies there in another sweep (every point
// spread over it, by its halfspaces); no sweep left off a kept facet's cutters reaches into it
// inside the stock; and a cutter's listed planes cut the facet there as all its planes do.
TEST(SweepCulling, CullsOnlyWhatAnotherSweepOrTheStockProvesAndListsEveryCutter) {
  const AlignedBox3d stock(Vector3d(0, 0, -5), Vector3d(10, 10, 0));
  for (const auto& [name, tool] : morph_test::every_tool_shape()) {
    SCOPED_TRACE(name);
    const morph::SweepPolytopeBuilder sweeps(morph::tool_polytope(tool.profile, kDeviation).polytope);
    const std::vector<morph::Move> moves = small_job();
    const morph::SweepCulling culling(sweeps, moves, joints(sweeps, moves), stock);
    std::vector<morph::ConvexPolytope> polytopes;
    std::vector<AlignedBox3d> boxes;
    for (const morph::Move& m : moves) {
      polytopes.push_back(sweeps(m.start, m.end));
      boxes.push_back(polytopes.back().bounds());
    }
    morph::CullingCounts counts;
    for (std::size_t i = 0; i < moves.size(); ++i) {
      const std::vector<morph::KeptFacet> kept = culling.cull(i, counts);
      std::vector<const morph::KeptFacet*> by_facet(polytopes[i].facets.size(), nullptr);
      for (const morph::KeptFacet& k : kept) by_facet.at(k.facet) = &k;
      for (std::size_t f = 0; f < polytopes[i].facets.size(); ++f) {
        const std::vector<Vector3d> polygon = corners(polytopes[i], static_cast<int>(f));
        if (!by_facet[f]) {
          std::vector<Vector3d> in_stock;
          for (const Vector3d& x : spread(polygon))
            if (stock.contains(x)) in_stock.push_back(x);
          bool proven = in_stock.empty();
          for (std::size_t j = 0; j < moves.size() && !proven; ++j) {
            if (j == i) continue;
            proven = true;
            for (const Vector3d& x : in_stock) proven = proven && polytopes[j].plane_value(x) <= kOn;
          }
          EXPECT_TRUE(proven) << "move " << i << " facet " << f << " culled without a reason";
          continue;
        }
        std::vector<bool> cutter(moves.size(), false);
        for (const morph::FacetCutter& c : by_facet[f]->cutters) {
          cutter[c.move] = true;
          const std::vector<morph::Halfspace> planes =
              sweeps.halfspaces(moves[c.move].start, moves[c.move].end);
          for (const Vector3d& x : samples(polygon)) {
            if (!stock.contains(x)) continue;
            double listed = -1e300;
            for (int h : by_facet[f]->planes_of(c))
              listed = std::max(listed, planes[h].normal.dot(x) - planes[h].offset);
            if (listed < -kOn) {
              EXPECT_LE(polytopes[c.move].plane_value(x), kOn);
            }
          }
        }
        AlignedBox3d box;
        for (const Vector3d& v : polygon) box.extend(v);
        for (std::size_t j = 0; j < moves.size(); ++j) {
          if (j == i || cutter[j] || !boxes[j].intersects(box)) continue;
          for (const Vector3d& x : samples(polygon))
            if (stock.contains(x)) {
              EXPECT_GE(polytopes[j].plane_value(x), -kOn)
                  << "move " << i << " facet " << f << " is cut by " << j;
            }
        }
      }
    }
    // The joints decide only caps whose vertices are all off the neighbour's rim (a real margin,
    // not the rounding): a flat mill's and a taper's few cap facets all reach the rim.
    if (name == "flat" || name == "tapered") {
      EXPECT_EQ(counts.by_joint, 0);
    } else {
      EXPECT_GT(counts.by_joint, 0);
    }
    EXPECT_GT(counts.outside_stock, 0);
    EXPECT_GT(counts.by_retrace, 0);
    // Where the facets are small next to the inscribed ball, the closed-form bounds decide some
    // (a flat mill's or a cone's facets are as long as the tool: halfspaces decide those, or,
    // on this small job, nothing but the joints, the retrace and the stock).
    if (name == "sphere" || name == "ballend") {
      EXPECT_GT(counts.by_cluster_bound + counts.by_facet_bound, 0);
    }
    EXPECT_GT(counts.kept, 0);
    EXPECT_EQ(counts.facets, counts.by_joint + counts.outside_stock + counts.by_retrace +
                                 counts.by_cluster_bound + counts.by_facet_bound + counts.by_shared_cap +
                                 counts.by_planes + counts.kept);
  }
}

// Closed forms: one move inside the stock keeps all its facets, uncut; one above it keeps none;
// a move and its retrace keep the first move's facets, and the retrace cuts none of them.
TEST(SweepCulling, OneMoveKeepsItsWholeSurfaceAndARetraceBelongsToTheFirstPass) {
  const AlignedBox3d stock(Vector3d(-20, -20, -20), Vector3d(20, 20, 20));
  const morph::SweepPolytopeBuilder sweeps(
      morph::tool_polytope(morph::ball_tool(1.5875, 10.0).profile, kDeviation).polytope);
  const Vector3d a(0.0, 0.0, -5.0), b(4.0, 3.0, -6.0);
  {
    const std::vector<morph::Move> moves{line(a, b)};
    const morph::SweepCulling culling(sweeps, moves, {false}, stock);
    morph::CullingCounts counts;
    const std::vector<morph::KeptFacet> kept = culling.cull(0, counts);
    EXPECT_EQ(kept.size(), sweeps(a, b).facets.size());
    for (const morph::KeptFacet& k : kept) EXPECT_TRUE(k.cutters.empty());
    const morph::SweepCulling above(sweeps, moves, {false},
                                    AlignedBox3d(Vector3d(-20, -20, -40), Vector3d(20, 20, -30)));
    EXPECT_TRUE(above.cull(0, counts).empty());
  }
  const std::vector<morph::Move> moves{line(a, b), line(b, a)};
  const morph::SweepCulling culling(sweeps, moves, joints(sweeps, moves), stock);
  morph::CullingCounts counts;
  const std::vector<morph::KeptFacet> first = culling.cull(0, counts);
  EXPECT_EQ(first.size(), sweeps(a, b).facets.size());
  for (const morph::KeptFacet& k : first) EXPECT_TRUE(k.cutters.empty());
  EXPECT_TRUE(culling.cull(1, counts).empty());
}

// A V-bit's facets run from its tip to its rim. A shallow pass along a deeper one lies inside it
// in the stock, though its tool reaches above the deeper pass's tool: every facet of the shallow
// pass is culled by its part in the stock, and the deeper pass keeps its own, uncut.
TEST(SweepCulling, AFacetIsJudgedByItsPartInTheStock) {
  const AlignedBox3d stock(Vector3d(0, 0, -2), Vector3d(20, 10, 0));
  const morph::SweepPolytopeBuilder sweeps(
      morph::tool_polytope(morph::conical_tool(3.0, 90.0, 6.0).profile, kDeviation).polytope);
  const std::vector<morph::Move> moves{line(Vector3d(-5, 5, -1.0), Vector3d(25, 5, -1.0)),
                                       line(Vector3d(-5, 5.2, -0.5), Vector3d(25, 5.2, -0.5))};
  // The shallow pass's tool reaches out of the deep one's above the stock.
  const morph::ConvexPolytope deep = sweeps(moves[0].start, moves[0].end);
  const morph::ConvexPolytope shallow = sweeps(moves[1].start, moves[1].end);
  ASSERT_GT(shallow.bounds().max().z(), deep.bounds().max().z() + 0.4);
  const morph::SweepCulling culling(sweeps, moves, {false, false}, stock);
  morph::CullingCounts counts;
  const std::vector<morph::KeptFacet> kept = culling.cull(0, counts);
  EXPECT_FALSE(kept.empty());
  for (const morph::KeptFacet& k : kept) EXPECT_TRUE(k.cutters.empty());
  EXPECT_TRUE(culling.cull(1, counts).empty());
  EXPECT_GT(counts.by_planes + counts.by_facet_bound + counts.by_cluster_bound, 0);
}

}  // namespace
