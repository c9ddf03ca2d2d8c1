// SPDX-License-Identifier: Apache-2.0
// The planar erosion against hand-computed closed forms and built-in degenerate cases.
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/planar_erosion.h>

#include <cmath>

#include "common/planar_shapes.h"

using morph::planar::Curve;
using morph::planar::Origin;
using morph::planar::Region;
using morph::planar::Trajectory;
using morph::planar::Vec2;
using namespace morphmill_test;

namespace {

constexpr double kExact = 1e-9;  // "exact up to rounding" for areas and lengths of order 100

/// Every loop is closed and consecutive curves share their ends exactly.
void expect_closed(const Region& region) {
  for (const auto& loop : region.loops) {
    ASSERT_FALSE(loop.curves.empty());
    for (std::size_t i = 0; i < loop.curves.size(); ++i)
      EXPECT_EQ(loop.curves[i].end, loop.curves[(i + 1) % loop.curves.size()].start);
  }
}

}  // namespace

TEST(PlanarErosion, DiscPassEndingInsideARectangle) {
  // A slot from outside to the middle: removes a 5 x 2 rectangle and a half disc.
  const Region stock = rectangle(0, 0, 10, 4);
  const auto r = morph::planar::erode(stock, polyline({{-5, 2}, {5, 2}}), 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 40.0 - 10.0 - M_PI / 2, kExact);
  EXPECT_NEAR(morph::planar::perimeter(r.region), 36.0 + M_PI, kExact);
  EXPECT_EQ(r.region.pieces.size(), 1u);
  EXPECT_EQ(morph::planar::hole_count(r.region), 0u);
}

TEST(PlanarErosion, DiscPassAcrossARectangleSplitsIt) {
  const Region stock = rectangle(0, 0, 10, 4);
  const auto r = morph::planar::erode(stock, polyline({{-5, 2}, {15, 2}}), 1.0);
  expect_closed(r.region);
  ASSERT_EQ(r.region.pieces.size(), 2u);
  EXPECT_NEAR(morph::planar::area(r.region), 20.0, kExact);
  EXPECT_NEAR(morph::planar::signed_area(r.region.loops[r.region.pieces[0].outer]), 10.0, kExact);
  EXPECT_NEAR(morph::planar::perimeter(r.region), 44.0, kExact);
}

TEST(PlanarErosion, CirclePocketIsADiscHole) {
  // Concentric passes (radii 1 and 2.5, tool radius 1.5) and a plunge clear a disc of radius 4.
  const Region stock = rectangle(0, 0, 10, 10);
  Trajectory moves{circle_move({5, 5}, 2.5, 0), circle_move({5, 5}, 1.0, 1)};
  moves.push_back(morph::planar::make_segment({5, 5}, {5, 5}, {Origin::Sweep, 2, 0}));
  const auto r = morph::planar::erode(stock, moves, 1.5);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 100.0 - 16.0 * M_PI, kExact);
  EXPECT_NEAR(morph::planar::perimeter(r.region), 40.0 + 8.0 * M_PI, kExact);
  ASSERT_EQ(r.region.pieces.size(), 1u);
  EXPECT_EQ(r.region.pieces[0].holes.size(), 1u);
  // The hole is bounded by the outermost pass's offset arc only.
  for (const Curve& c : r.region.loops[r.region.pieces[0].holes[0]].curves) {
    EXPECT_EQ(c.from.origin, Origin::Sweep);
    EXPECT_EQ(c.from.source, 0);
    EXPECT_NEAR(c.radius, 4.0, 1e-12);
  }
}

TEST(PlanarErosion, AnnulusLeavesAnIsland) {
  const Region stock = rectangle(0, 0, 10, 10);
  const auto r = morph::planar::erode(stock, {circle_move({5, 5}, 3.0, 0)}, 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 100.0 - 12.0 * M_PI, kExact);
  EXPECT_EQ(r.region.pieces.size(), 2u);
  EXPECT_EQ(morph::planar::hole_count(r.region), 1u);
}

TEST(PlanarErosion, LShapedSlot) {
  // Two strips 2 wide overlapping in a unit square, half discs at the ends, a quarter disc outside the turn.
  const Region stock = rectangle(0, 0, 10, 10);
  const auto r = morph::planar::erode(stock, polyline({{2, 8}, {2, 2}, {8, 2}}), 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 100.0 - 23.0 - 1.25 * M_PI, kExact);
  // The hole: outer sides x = 1 and y = 1 (6 each), inner sides x = 3 and y = 3 (5 each), two half
  // circles and a quarter circle.
  EXPECT_NEAR(morph::planar::perimeter(r.region), 40.0 + 22.0 + 2.5 * M_PI, kExact);
  EXPECT_EQ(r.region.pieces.size(), 1u);
  EXPECT_EQ(morph::planar::hole_count(r.region), 1u);
}

TEST(PlanarErosion, RetracedMovesCountOnce) {
  const Region stock = rectangle(0, 0, 10, 10);
  const auto r = morph::planar::erode(stock, polyline({{3, 5}, {7, 5}, {3, 5}, {7, 5}}), 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 100.0 - 8.0 - M_PI, kExact);
  EXPECT_NEAR(morph::planar::perimeter(r.region), 48.0 + 2.0 * M_PI, kExact);
  EXPECT_EQ(morph::planar::hole_count(r.region), 1u);
  EXPECT_GT(r.stats.coincident_copies, 0u);
  // The first move wins the ties.
  for (const Curve& c : r.region.loops[r.region.pieces[0].holes[0]].curves) EXPECT_EQ(c.from.source, 0);
}

TEST(PlanarErosion, TangentPassesLeaveNoWallBetweenThem) {
  // Passes 2r apart: their dilations touch along y = 4, which is not part of the result.
  const Region stock = rectangle(0, 0, 10, 10);
  Trajectory moves = polyline({{2, 3}, {8, 3}});
  moves.push_back(morph::planar::make_segment({2, 5}, {8, 5}, {Origin::Sweep, 1, 2}));
  const auto r = morph::planar::erode(stock, moves, 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 100.0 - 24.0 - 2.0 * M_PI, kExact);
  EXPECT_NEAR(morph::planar::perimeter(r.region), 40.0 + 12.0 + 4.0 * M_PI, kExact);
  EXPECT_EQ(r.region.pieces.size(), 1u);
  EXPECT_EQ(morph::planar::hole_count(r.region), 1u);
}

TEST(PlanarErosion, PassTouchingAStockEdgeFromOutsideChangesNothing) {
  const Region stock = rectangle(0, 0, 10, 10);
  const auto r = morph::planar::erode(stock, polyline({{2, -1}, {8, -1}}), 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 100.0, kExact);
  EXPECT_NEAR(morph::planar::perimeter(r.region), 40.0, kExact);
  ASSERT_EQ(r.region.pieces.size(), 1u);
  // The edge is kept once, as the stock's (the stock wins ties).
  for (const Curve& c : r.region.loops[0].curves) EXPECT_EQ(c.from.origin, Origin::Stock);
}

TEST(PlanarErosion, PassAlongAStockEdge) {
  // The tool centre on the edge: half a stadium is removed.
  const Region stock = rectangle(0, 0, 10, 10);
  const auto r = morph::planar::erode(stock, polyline({{2, 0}, {8, 0}}), 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 100.0 - 6.0 - M_PI / 2, kExact);
  EXPECT_NEAR(morph::planar::perimeter(r.region), 38.0 + M_PI, kExact);
  EXPECT_EQ(r.region.pieces.size(), 1u);
  // A pass whose dilation's side lies on the edge from inside: the edge goes where the pass went.
  const auto inside = morph::planar::erode(stock, polyline({{2, 1}, {8, 1}}), 1.0);
  expect_closed(inside.region);
  EXPECT_NEAR(morph::planar::area(inside.region), 100.0 - 12.0 - M_PI, kExact);
  EXPECT_NEAR(morph::planar::perimeter(inside.region), 40.0 - 6.0 + 6.0 + 2.0 * M_PI, kExact);
}

TEST(PlanarErosion, ZeroLengthMovesArePlunges) {
  const Region stock = rectangle(0, 0, 10, 10);
  const auto r = morph::planar::erode(stock, polyline({{5, 5}, {5, 5}}), 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 100.0 - M_PI, kExact);
  // A zero-length move inside a polyline changes nothing.
  const auto slot = morph::planar::erode(stock, polyline({{3, 5}, {5, 5}, {5, 5}, {7, 5}}), 1.0);
  expect_closed(slot.region);
  EXPECT_NEAR(morph::planar::area(slot.region), 100.0 - 8.0 - M_PI, kExact);
  EXPECT_NEAR(morph::planar::perimeter(slot.region), 48.0 + 2.0 * M_PI, kExact);
}

TEST(PlanarErosion, DiscLargerThanTheStockLeavesNothing) {
  const Region stock = rectangle(0, 0, 1, 1);
  const auto r = morph::planar::erode(stock, polyline({{0.5, 0.5}, {0.5, 0.5}}), 5.0);
  EXPECT_TRUE(r.region.loops.empty());
  EXPECT_EQ(morph::planar::area(r.region), 0.0);
}

TEST(PlanarErosion, NoMovesLeaveTheStock) {
  const Region stock = rectangle(0, 0, 10, 4);
  const auto r = morph::planar::erode(stock, {}, 1.0);
  EXPECT_NEAR(morph::planar::area(r.region), 40.0, kExact);
  EXPECT_EQ(r.region.pieces.size(), 1u);
}

TEST(PlanarErosion, NonPositiveRadiusIsBadInput) {
  const Region stock = rectangle(0, 0, 10, 4);
  EXPECT_THROW(morph::planar::erode(stock, polyline({{0, 0}, {1, 1}}), 0.0), morph::InputError);
  EXPECT_THROW(morph::planar::erode(stock, polyline({{0, 0}, {1, 1}}), -1.0), morph::InputError);
}

TEST(PlanarErosion, CrossingTrajectoriesMakeFourPartitions) {
  // Figure 13: two passes crossing the object cut it into four pieces.
  const Region stock = rectangle(0, 0, 10, 10);
  Trajectory moves = polyline({{-1, 5}, {11, 5}});
  moves.push_back(morph::planar::make_segment({5, -1}, {5, 11}, {Origin::Sweep, 1, 2}));
  const auto r = morph::planar::erode(stock, moves, 1.0);
  expect_closed(r.region);
  ASSERT_EQ(r.region.pieces.size(), 4u);
  for (const auto& piece : r.region.pieces)
    EXPECT_NEAR(morph::planar::signed_area(r.region.loops[piece.outer]), 16.0, kExact);
}

TEST(PlanarErosion, ArcMovesGiveOffsetArcs) {
  // A half-turn arc of radius 3 about (5, 0) from (8, 0) to (2, 0), tool 1, on the stock [0,10]x[0,10]:
  // removes half an annulus (radii 2 and 4), which cuts off the half disc inside it; the half discs at
  // the move's ends lie below y = 0, outside.
  const Region stock = rectangle(0, 0, 10, 10);
  const Trajectory moves{morph::planar::make_arc({5, 0}, 3.0, 0.0, M_PI, {Origin::Sweep, 0, 1})};
  const auto r = morph::planar::erode(stock, moves, 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 100.0 - 0.5 * M_PI * (16.0 - 4.0), kExact);
  EXPECT_NEAR(morph::planar::perimeter(r.region), 40.0 - 4.0 + M_PI * (4.0 + 2.0), kExact);
  ASSERT_EQ(r.region.pieces.size(), 2u);
  EXPECT_NEAR(morph::planar::signed_area(r.region.loops[r.region.pieces[1].outer]), 2.0 * M_PI, kExact);
}

TEST(PlanarErosion, DilationOfAPolyline) {
  const auto r = morph::planar::dilate(polyline({{2, 8}, {2, 2}, {8, 2}}), 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 23.0 + 1.25 * M_PI, kExact);
  EXPECT_EQ(r.region.pieces.size(), 1u);
}

TEST(PlanarErosion, ClassicalErosionOfARectangleAndAnLShape) {
  const auto rect = morph::planar::classical_erosion(rectangle(0, 0, 10, 4), 1.0);
  expect_closed(rect.region);
  EXPECT_NEAR(morph::planar::area(rect.region), 16.0, kExact);
  EXPECT_NEAR(morph::planar::perimeter(rect.region), 20.0, kExact);
  // At the L's reflex corner the contour is an arc about the corner.
  const Region l =
      morph::planar::make_region({polygon({{0, 0}, {10, 0}, {10, 5}, {5, 5}, {5, 10}, {0, 10}})});
  const auto r = morph::planar::classical_erosion(l, 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 40.0 - M_PI / 4, kExact);
  EXPECT_NEAR(morph::planar::perimeter(r.region), 8 + 3 + 4 + 4 + 3 + 8 + M_PI / 2, kExact);
  for (const auto& loop : r.region.loops)
    for (const Curve& c : loop.curves) EXPECT_EQ(c.from.origin, Origin::Offset);
  // A disc shrinks to a disc; a stock narrower than the disc vanishes.
  const auto disc = morph::planar::classical_erosion(morph::planar::make_region({circle({0, 0}, 5.0)}), 1.0);
  EXPECT_NEAR(morph::planar::area(disc.region), 16.0 * M_PI, kExact);
  EXPECT_TRUE(morph::planar::classical_erosion(rectangle(0, 0, 10, 1.5), 1.0).region.loops.empty());
}

TEST(PlanarErosion, ResultDoesNotDependOnThreads) {
  const Region stock = rectangle(0, 0, 10, 10);
  std::vector<Vec2> zigzag;
  for (int i = 0; i <= 20; ++i) zigzag.emplace_back(i % 2 ? 9.0 : 1.0, 0.45 * i + 0.3);
  morph::planar::PlanarOptions sequential;
  sequential.policy = morph::ExecutionPolicy::Sequential;
  const auto a = morph::planar::erode(stock, polyline(zigzag), 0.6);
  const auto b = morph::planar::erode(stock, polyline(zigzag), 0.6, sequential);
  ASSERT_EQ(a.region.loops.size(), b.region.loops.size());
  for (std::size_t i = 0; i < a.region.loops.size(); ++i) {
    ASSERT_EQ(a.region.loops[i].curves.size(), b.region.loops[i].curves.size());
    for (std::size_t k = 0; k < a.region.loops[i].curves.size(); ++k)
      EXPECT_EQ(a.region.loops[i].curves[k].start, b.region.loops[i].curves[k].start);
  }
}

TEST(PlanarErosion, PlungeThenAPassFromThePlungePoint) {
  // The plunge's circle and the half circle behind the pass's start coincide on one side: the first
  // G-code feed move after a plunge. Found on data/jobs/pocket.nc.
  const Region stock = rectangle(0, 0, 10, 10);
  const auto r = morph::planar::erode(stock, polyline({{5, 5}, {5, 5}, {8, 5}}), 1.0);
  expect_closed(r.region);
  EXPECT_NEAR(morph::planar::area(r.region), 100.0 - 6.0 - M_PI, kExact);
  EXPECT_NEAR(morph::planar::perimeter(r.region), 46.0 + 2.0 * M_PI, kExact);
  // A full-turn arc move starting where a plunge was.
  Trajectory moves = polyline({{8, 5}, {8, 5}});
  moves.push_back(circle_move({5, 5}, 3.0, 1));
  const auto ring = morph::planar::erode(stock, moves, 1.0);
  expect_closed(ring.region);
  EXPECT_NEAR(morph::planar::area(ring.region), 100.0 - 12.0 * M_PI, kExact);
}
