// SPDX-License-Identifier: Apache-2.0
// Pictures users act on: a known gouge shows in its colour at its place, zero deviation has the
// colour map's centre colour, the legend is drawn (cairo text, the bar centred on zero), and a
// close-up frames the place larger.
#include <gtest/gtest.h>
#include <raytest/heatmap.h>
#include <raytest/regions.h>
#include <raytest/render.h>

#include <cmath>

#include "raytest/raytest_support.h"

namespace {

// A 20 x 10 x 1 plate whose top has a gouge of -0.05 within 1.5 of (5, 3); zero elsewhere.
morph::TriangleMesh gouged_plate() {
  morph::TriangleMesh plate =
      raytest_test::box_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(20, 10, 1), 40);
  morph::VertexScalar deviation{"deviation", {}};
  for (const Eigen::Vector3d& v : plate.vertices)
    deviation.values.push_back(v.z() > 0.5 && (v.head<2>() - Eigen::Vector2d(5, 3)).norm() <= 1.5 ? -0.05
                                                                                                  : 0.0);
  plate.scalars.push_back(deviation);
  return plate;
}

raytest::RenderOptions unlit_top_view() {
  raytest::RenderOptions options;
  options.width = 800;
  options.height = 500;
  options.view = raytest::View::Top;
  options.scalar = "deviation";
  options.color_map = raytest::ColorMap::CoolWarm;
  options.range = raytest::ScalarRange{-0.1, 0.1};  // -/+ 2 x a tolerance of 0.05
  options.unit = "mm";
  options.lighting = false;
  return options;
}

morph::Color pixel_at(const raytest::Image& image, const Eigen::Vector2d& p) {
  return image.pixel(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
}

TEST(Picture, KnownGougeHasItsColourAtItsPlaceAndZeroTheCentreColour) {
  const morph::TriangleMesh plate = gouged_plate();
  const raytest::RenderOptions options = unlit_top_view();
  const raytest::Image image = raytest::render_mesh(plate, options);
  const morph::Color centre = raytest::map_color(raytest::ColorMap::CoolWarm, 0.5);
  EXPECT_EQ(raytest::map_value(raytest::ColorMap::CoolWarm, *options.range, 0.0), centre);
  const morph::Color gouge = raytest::map_value(raytest::ColorMap::CoolWarm, *options.range, -0.05);
  EXPECT_GT(gouge[2], gouge[0]);  // blue side
  EXPECT_EQ(pixel_at(image, raytest::project_to_pixel(plate, options, {5, 3, 1})), gouge);
  // Zero deviation, far from the gouge: exactly the centre colour.
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(15, 7, 1), Eigen::Vector3d(10, 8, 1), Eigen::Vector3d(2, 9, 1)})
    EXPECT_EQ(pixel_at(image, raytest::project_to_pixel(plate, options, p)), centre) << p.transpose();
  // Pixels of exactly the gouge colour (all three corners of their triangle in the disc) cover at
  // least the disc shrunk by a triangle's diagonal (0.56); pixels of any shade of blue at most the
  // disc grown by it: pi * (1.5 -/+ 0.56)^2 of the 200 mm^2 plate.
  int gouge_pixels = 0, blue_pixels = 0, plate_pixels = 0;
  const int right = static_cast<int>(raytest::project_to_pixel(plate, options, {20, 5, 1}).x());
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x <= right; ++x) {
      const morph::Color c = image.pixel(x, y);
      if (c == morph::Color{255, 255, 255}) continue;
      ++plate_pixels;
      if (c == gouge) ++gouge_pixels;
      if (c[2] > c[0] + 8) ++blue_pixels;
    }
  const double diagonal = std::hypot(0.5, 0.25);
  EXPECT_GE(double(gouge_pixels) / plate_pixels, M_PI * std::pow(1.5 - diagonal, 2) / 200.0);
  EXPECT_LE(double(gouge_pixels) / plate_pixels, M_PI * 1.5 * 1.5 / 200.0);
  EXPECT_GE(double(blue_pixels) / plate_pixels, M_PI * 1.5 * 1.5 / 200.0);
  EXPECT_LE(double(blue_pixels) / plate_pixels, M_PI * std::pow(1.5 + diagonal, 2) / 200.0);
}

TEST(Picture, LegendBarIsCentredOnZeroWithText) {
  const morph::TriangleMesh plate = gouged_plate();
  raytest::RenderOptions options = unlit_top_view();
  options.low_caption = "- gouge";
  options.high_caption = "+ excess";
  const raytest::Image image = raytest::render_mesh(plate, options);
  // The legend panel starts right of the plate; find the bar as the column of colour-map pixels.
  const int panel = static_cast<int>(raytest::project_to_pixel(plate, options, {20, 5, 1}).x()) + 30;
  const morph::Color top = raytest::map_color(raytest::ColorMap::CoolWarm, 1.0);
  int bar_x = -1, bar_top = -1, bar_bottom = -1;
  for (int x = panel; x < image.width && bar_x < 0; ++x)
    for (int y = 0; y < image.height; ++y) {
      const morph::Color c = image.pixel(x, y);
      if (std::abs(c[0] - top[0]) + std::abs(c[1] - top[1]) + std::abs(c[2] - top[2]) <= 6) {
        bar_x = x + 3;
        break;
      }
    }
  ASSERT_GE(bar_x, 0) << "no colour bar";
  for (int y = 0; y < image.height; ++y) {
    const morph::Color c = image.pixel(bar_x, y);
    const bool coloured = c != morph::Color{255, 255, 255} && c != morph::Color{0, 0, 0} &&
                          std::abs(int(c[0]) - int(c[1])) + std::abs(int(c[1]) - int(c[2])) > 0;
    if (coloured && bar_top < 0) bar_top = y;
    if (coloured) bar_bottom = y;
  }
  ASSERT_GT(bar_bottom - bar_top, 100);
  // The middle row of the bar (value 0) has the centre colour (within a step of the bar's rows).
  const morph::Color middle = image.pixel(bar_x, (bar_top + bar_bottom) / 2);
  const morph::Color centre = raytest::map_color(raytest::ColorMap::CoolWarm, 0.5);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(middle[k], centre[k], 3) << k;
  // Top red (excess), bottom blue (gouge).
  EXPECT_GT(image.pixel(bar_x, bar_top + 2)[0], image.pixel(bar_x, bar_top + 2)[2]);
  EXPECT_GT(image.pixel(bar_x, bar_bottom - 2)[2], image.pixel(bar_x, bar_bottom - 2)[0]);
  // Text: dark antialiased glyph pixels right of the bar (tick labels) and above it (title).
  int label_ink = 0, title_ink = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = panel; x < image.width; ++x) {
      const morph::Color c = image.pixel(x, y);
      if (c[0] > 120 || c[1] > 120 || c[2] > 120) continue;
      if (x > bar_x + 20 && y >= bar_top && y <= bar_bottom) ++label_ink;
      if (y < bar_top - 20) ++title_ink;
    }
  EXPECT_GT(label_ink, 150);
  EXPECT_GT(title_ink, 100);
}

TEST(Picture, CloseUpFramesThePlaceLarger) {
  const morph::TriangleMesh plate = gouged_plate();
  raytest::RenderOptions options = unlit_top_view();
  const morph::Color gouge = raytest::map_value(raytest::ColorMap::CoolWarm, *options.range, -0.05);
  auto gouge_pixels = [&](const raytest::Image& image) {
    int n = 0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) n += image.pixel(x, y) == gouge;
    return n;
  };
  const int whole = gouge_pixels(raytest::render_mesh(plate, options));
  options.focus = Eigen::AlignedBox3d(Eigen::Vector3d(3, 1, 0.5), Eigen::Vector3d(7, 5, 1));
  const raytest::Image close = raytest::render_mesh(plate, options);
  EXPECT_GT(gouge_pixels(close), 10 * whole);
  EXPECT_EQ(pixel_at(close, raytest::project_to_pixel(plate, options, {5, 3, 1})), gouge);
}

// The case: a 2 mm gouge inside one 25 mm triangle. Coloured at the triangles' corners it
// vanishes (every corner is at zero); after subdividing, the picture shows it at its place and about
// its size.
TEST(Picture, GougeSmallerThanATriangleShowsAfterSubdividing) {
  const morph::TriangleMesh plate =
      raytest_test::box_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(25, 25, 1), 1);
  const Eigen::Vector2d centre_of_gouge(9, 14);
  const auto deviation_at = [&](const Eigen::Vector3d& p) {
    return p.z() > 0.5 && (p.head<2>() - centre_of_gouge).norm() <= 1.0 ? -0.05 : 0.0;
  };
  const auto with_deviation = [&](morph::TriangleMesh mesh) {
    morph::VertexScalar deviation{"deviation", {}};
    for (const Eigen::Vector3d& v : mesh.vertices) deviation.values.push_back(deviation_at(v));
    mesh.scalars.push_back(deviation);
    return mesh;
  };
  const raytest::RenderOptions options = unlit_top_view();
  const morph::Color gouge = raytest::map_value(raytest::ColorMap::CoolWarm, *options.range, -0.05);
  const morph::Color centre = raytest::map_color(raytest::ColorMap::CoolWarm, 0.5);
  const Eigen::Vector3d place(centre_of_gouge.x(), centre_of_gouge.y(), 1);

  const morph::TriangleMesh coarse = with_deviation(plate);
  ASSERT_LE(coarse.triangles.size(), 12u);
  EXPECT_EQ(
      pixel_at(raytest::render_mesh(coarse, options), raytest::project_to_pixel(coarse, options, place)),
      centre)
      << "corner colours cannot show a gouge inside a triangle";

  const morph::TriangleMesh fine = with_deviation(raytest::refine_long_edges(plate, 0.25).mesh);
  const raytest::Image image = raytest::render_mesh(fine, options);
  const Eigen::Vector2d at = raytest::project_to_pixel(fine, options, place);
  EXPECT_EQ(pixel_at(image, at), gouge);
  // Gouge-blue pixels (any shade bluer than the centre) cover about the disc and sit within its
  // radius plus one refined triangle's diagonal (0.25 * sqrt 2 mm, where colours blend) and a pixel.
  const double px_per_mm =
      (raytest::project_to_pixel(fine, options, place + Eigen::Vector3d(1, 0, 0)) - at).norm();
  const double radius_px = 1.0 * px_per_mm;
  const int right = static_cast<int>(raytest::project_to_pixel(fine, options, {25, 12.5, 1}).x());
  int blue = 0, outside = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x <= right; ++x) {
      const morph::Color c = image.pixel(x, y);
      if (c == morph::Color{255, 255, 255} || !(c[2] > c[0] + 8)) continue;
      ++blue;
      if ((Eigen::Vector2d(x, y) - at).norm() > radius_px + 0.36 * px_per_mm + 1.5) ++outside;
    }
  EXPECT_EQ(outside, 0);
  EXPECT_GE(blue, M_PI * radius_px * radius_px);
  EXPECT_LE(blue, M_PI * std::pow(radius_px + 0.36 * px_per_mm, 2));
}

}  // namespace
