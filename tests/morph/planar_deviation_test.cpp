// SPDX-License-Identifier: Apache-2.0
// The planar deviation against closed forms: offset squares and circles.
#include <gtest/gtest.h>
#include <morph/planar_deviation.h>

#include <cmath>

#include "common/planar_shapes.h"

using namespace morphmill_test;

TEST(PlanarDeviation, ConcentricCirclesAreTheirRadiusDifferenceApart) {
  const auto small = morph::planar::make_region({circle({0, 0}, 2.0)});
  const auto large = morph::planar::make_region({circle({0, 0}, 2.5)});
  const auto d = morph::planar::planar_deviation(small, large);
  EXPECT_NEAR(d.a_to_b.max_inside, 0.5, 1e-12);  // the small circle lies inside the large region
  EXPECT_EQ(d.a_to_b.max_outside, 0.0);
  EXPECT_NEAR(d.b_to_a.max_outside, 0.5, 1e-12);
  EXPECT_NEAR(d.a_to_b.mean_abs, 0.5, 1e-12);
  EXPECT_NEAR(d.hausdorff(), 0.5, 1e-12);
}

TEST(PlanarDeviation, SquareAboutACircleFindsTheMaximaBetweenSamples) {
  // A circle of radius 1 inside a square of side 2: the square's corners are sqrt(2) - 1 outside the
  // disc; the circle's points at 45 degrees are 1 - 1/sqrt(2) inside the square.
  const auto disc = morph::planar::make_region({circle({0, 0}, 1.0)});
  const auto square = rectangle(-1, -1, 1, 1);
  morph::planar::DeviationOptions coarse;
  coarse.spacing = 0.3;  // samples miss the extremes; the refinement finds them
  const auto d = morph::planar::planar_deviation(square, disc, coarse);
  EXPECT_NEAR(d.a_to_b.max_outside, std::sqrt(2.0) - 1.0, 1e-9);
  EXPECT_NEAR(d.b_to_a.max_inside, 1.0 - 1.0 / std::sqrt(2.0), 1e-9);
}
