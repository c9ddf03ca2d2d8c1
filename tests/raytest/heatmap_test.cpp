// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <raytest/heatmap.h>

#include <cmath>

namespace {

TEST(Heatmap, ColourMapEndsAndMiddle) {
  EXPECT_EQ(raytest::map_color(raytest::ColorMap::Viridis, 0.0), (morph::Color{68, 1, 84}));
  EXPECT_EQ(raytest::map_color(raytest::ColorMap::Viridis, 1.0), (morph::Color{253, 231, 37}));
  EXPECT_EQ(raytest::map_color(raytest::ColorMap::Viridis, 0.5), (morph::Color{33, 145, 140}));
  EXPECT_EQ(raytest::map_color(raytest::ColorMap::CoolWarm, 0.0), (morph::Color{59, 76, 192}));
  EXPECT_EQ(raytest::map_color(raytest::ColorMap::CoolWarm, 0.5), (morph::Color{221, 221, 221}));
  EXPECT_EQ(raytest::map_color(raytest::ColorMap::CoolWarm, 1.0), (morph::Color{180, 4, 38}));
  // Clamped outside [0, 1].
  EXPECT_EQ(raytest::map_color(raytest::ColorMap::Viridis, -3.0),
            raytest::map_color(raytest::ColorMap::Viridis, 0.0));
  EXPECT_EQ(raytest::map_color(raytest::ColorMap::CoolWarm, 7.0),
            raytest::map_color(raytest::ColorMap::CoolWarm, 1.0));
}

TEST(Heatmap, ViridisGetsBrighterMonotonically) {
  double previous = -1;
  for (int i = 0; i <= 100; ++i) {
    const morph::Color c = raytest::map_color(raytest::ColorMap::Viridis, i / 100.0);
    const double luma = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    EXPECT_GE(luma, previous - 1e-9) << i;
    previous = luma;
  }
}

TEST(Heatmap, RangesAndValues) {
  const std::vector<double> values = {-0.2, 0.5, std::numeric_limits<double>::quiet_NaN(), 0.1};
  const raytest::ScalarRange plain = raytest::auto_range(values, false);
  EXPECT_EQ(plain.low, -0.2);
  EXPECT_EQ(plain.high, 0.5);
  const raytest::ScalarRange symmetric = raytest::auto_range(values, true);
  EXPECT_EQ(symmetric.low, -0.5);
  EXPECT_EQ(symmetric.high, 0.5);
  EXPECT_EQ(raytest::map_value(raytest::ColorMap::CoolWarm, symmetric, -0.5), (morph::Color{59, 76, 192}));
  EXPECT_EQ(raytest::map_value(raytest::ColorMap::CoolWarm, symmetric, 0.5), (morph::Color{180, 4, 38}));
  EXPECT_EQ(raytest::map_value(raytest::ColorMap::CoolWarm, symmetric, 0.0), (morph::Color{221, 221, 221}));
  EXPECT_EQ(raytest::map_value(raytest::ColorMap::Viridis, {2, 2}, 2.0),
            raytest::map_color(raytest::ColorMap::Viridis, 0.5));
}

TEST(Heatmap, ApplyStoresScalarAndColours) {
  morph::TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  raytest::apply_heatmap(mesh, "deviation", {0.0, 1.0, 2.0}, raytest::ColorMap::Viridis, {0, 2});
  ASSERT_NE(mesh.scalar("deviation"), nullptr);
  EXPECT_EQ(mesh.scalar("deviation")->values[2], 2.0);
  ASSERT_EQ(mesh.colors.size(), 3u);
  EXPECT_EQ(mesh.colors[0], (morph::Color{68, 1, 84}));
  EXPECT_EQ(mesh.colors[2], (morph::Color{253, 231, 37}));
  raytest::apply_heatmap(mesh, "deviation", {2.0, 2.0, 2.0}, raytest::ColorMap::Viridis, {0, 2});
  EXPECT_EQ(mesh.scalars.size(), 1u);  // replaced, not duplicated
  EXPECT_EQ(mesh.colors[0], (morph::Color{253, 231, 37}));
  EXPECT_THROW(raytest::apply_heatmap(mesh, "x", {1.0}, raytest::ColorMap::Viridis, {0, 1}),
               morph::InputError);
}

}  // namespace
