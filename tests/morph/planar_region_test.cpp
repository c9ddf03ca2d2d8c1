// SPDX-License-Identifier: Apache-2.0
// Planar curves and regions: exact areas, lengths, containment and the input checks.
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/planar_region.h>

#include <cmath>

#include "common/planar_shapes.h"

using morph::planar::Curve;
using morph::planar::Loop;
using morph::planar::Vec2;
using namespace morphmill_test;

TEST(PlanarCurve, ArcAreaAndLengthAreClosedForm) {
  const Loop disc = circle({1, 2}, 3.0);
  EXPECT_NEAR(morph::planar::signed_area(disc), 9.0 * M_PI, 1e-12);
  EXPECT_NEAR(morph::planar::perimeter(disc), 6.0 * M_PI, 1e-12);
  // A half disc as a bulge of 1 and its diameter.
  Loop half;
  half.curves.push_back(morph::planar::make_segment({-1, 0}, {1, 0}));
  half.curves.push_back(morph::planar::make_bulge({1, 0}, {-1, 0}, 1.0));
  EXPECT_NEAR(half.curves[1].center.norm(), 0.0, 1e-15);
  EXPECT_NEAR(morph::planar::signed_area(half), M_PI / 2, 1e-12);
  // A negative bulge turns clockwise: the same chord bounds a half disc below, on the right.
  const Curve cw = morph::planar::make_bulge({1, 0}, {-1, 0}, -1.0);
  EXPECT_LT(cw.sweep, 0.0);
  EXPECT_NEAR(morph::planar::point_at(cw, 0.5).y(), -1.0, 1e-12);
}

TEST(PlanarCurve, BoundsIncludeTheArcsExtremes) {
  const Curve arc = morph::planar::make_arc({0, 0}, 2.0, -0.25 * M_PI, 0.5 * M_PI);
  const auto box = morph::planar::bounds(arc);
  EXPECT_NEAR(box.max().x(), 2.0, 1e-15);
  EXPECT_NEAR(box.min().y(), -std::sqrt(2.0), 1e-12);
}

TEST(PlanarRegion, ContainsAndNesting) {
  const auto region = morph::planar::make_region(
      {polygon({{0, 0}, {10, 0}, {10, 10}, {0, 10}}), circle({5, 5}, 2.0), circle({5, 5}, 1.0)});
  // A square with a round hole and an island in the hole: two pieces, one hole, orientations fixed.
  ASSERT_EQ(region.pieces.size(), 2u);
  EXPECT_EQ(morph::planar::hole_count(region), 1u);
  EXPECT_NEAR(morph::planar::area(region), 100.0 - 4.0 * M_PI + M_PI, 1e-12);
  EXPECT_TRUE(morph::planar::contains(region, {1, 1}));
  EXPECT_FALSE(morph::planar::contains(region, {5, 6.5}));
  EXPECT_TRUE(morph::planar::contains(region, {5.5, 5}));
  EXPECT_FALSE(morph::planar::contains(region, {11, 5}));
  // On the circle's height: the ray passes the arcs' top and bottom points consistently.
  EXPECT_TRUE(morph::planar::contains(region, {1, 7}));
  EXPECT_TRUE(morph::planar::contains(region, {1, 3}));
}

TEST(PlanarRegion, OpenLoopIsBadInputNamingTheElement) {
  std::vector<Loop> loops{polygon({{0, 0}, {10, 0}, {10, 10}, {0, 10}})};
  loops[0].curves[2].end = Vec2(1, 10);
  try {
    morph::planar::validate_loops(loops, "part.dxf", 1e-9);
    FAIL() << "expected InputError";
  } catch (const morph::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("part.dxf: loop 0, element 2: the loop is open"), std::string::npos)
        << e.what();
  }
}

TEST(PlanarRegion, SelfIntersectionIsBadInputNamingBothElements) {
  std::vector<Loop> loops{polygon({{0, 0}, {10, 10}, {10, 0}, {0, 10}})};  // a bow tie
  try {
    morph::planar::validate_loops(loops, "bowtie.json", 1e-9);
    FAIL() << "expected InputError";
  } catch (const morph::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bowtie.json: loop 0, element 0 meets loop 0, element 2 at (5, 5)"),
              std::string::npos)
        << e.what();
  }
  // Two loops touching at a point are rejected too; nested loops are fine.
  std::vector<Loop> touching{polygon({{0, 0}, {1, 0}, {1, 1}, {0, 1}}),
                             polygon({{1, 1}, {2, 1}, {2, 2}, {1, 2}})};
  EXPECT_THROW(morph::planar::validate_loops(touching, "t", 1e-9), morph::InputError);
  std::vector<Loop> nested{polygon({{0, 0}, {4, 0}, {4, 4}, {0, 4}}), circle({2, 2}, 1.0)};
  EXPECT_NO_THROW(morph::planar::validate_loops(nested, "n", 1e-9));
}

TEST(PlanarRegion, ZeroLengthElementIsBadInput) {
  std::vector<Loop> loops{polygon({{0, 0}, {1, 0}, {1, 0}, {1, 1}})};
  EXPECT_THROW(morph::planar::validate_loops(loops, "z", 1e-9), morph::InputError);
}
