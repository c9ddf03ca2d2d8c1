// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <raytest/render.h>
#include <stb/stb_image.h>

#include <cstdio>
#include <filesystem>

#include "raytest/raytest_support.h"

namespace {

bool is_background(const morph::Color& c) {
  return c == morph::Color{255, 255, 255};
}

TEST(Render, TopViewOfASquarePlateFillsTheMiddle) {
  // A flat 2 x 1 plate seen from the top, 200 x 100: framed with a margin, so the centre is
  // covered and the corners are background.
  const morph::TriangleMesh plate =
      raytest_test::box_mesh(Eigen::Vector3d(-1, -0.5, 0), Eigen::Vector3d(1, 0.5, 0.01), 1);
  raytest::RenderOptions options;
  options.width = 200;
  options.height = 100;
  options.view = raytest::View::Top;
  const raytest::Image image = raytest::render_mesh(plate, options);
  ASSERT_EQ(image.width, 200);
  ASSERT_EQ(image.height, 100);
  EXPECT_FALSE(is_background(image.pixel(100, 50)));
  EXPECT_FALSE(is_background(image.pixel(20, 50)));  // plate spans ~ 89% of the width
  EXPECT_TRUE(is_background(image.pixel(2, 2)));
  EXPECT_TRUE(is_background(image.pixel(197, 97)));
  // No scalar and no colours: shaded grey, never brighter than the base grey 200.
  const morph::Color centre = image.pixel(100, 50);
  EXPECT_EQ(centre[0], centre[1]);
  EXPECT_EQ(centre[1], centre[2]);
  EXPECT_GT(centre[0], 100);
  EXPECT_LE(centre[0], 200);
}

TEST(Render, ScalarColoursAndColourBarInThePng) {
  morph::TriangleMesh sphere = raytest_test::uv_sphere(1.0, 24, 48);
  morph::VertexScalar height{"height", {}};
  for (const Eigen::Vector3d& v : sphere.vertices) height.values.push_back(v.z());
  sphere.scalars.push_back(height);
  raytest::RenderOptions options;
  options.width = 320;
  options.height = 240;
  options.view = raytest::View::Front;
  options.scalar = "height";
  options.color_map = raytest::ColorMap::CoolWarm;
  options.unit = "mm";
  const raytest::Image image = raytest::render_mesh(sphere, options);
  const std::string path = (std::filesystem::temp_directory_path() / "raytest_render_test.png").string();
  std::remove(path.c_str());
  raytest::write_png(image, path);
  ASSERT_TRUE(std::filesystem::exists(path));
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 320);
  EXPECT_EQ(h, 240);
  const auto at = [&](int x, int y) {
    const unsigned char* p = data + 3 * (y * w + x);
    return morph::Color{p[0], p[1], p[2]};
  };
  // The sphere sits left of the colour bar: its top (z = +1) is red-ish, its bottom blue-ish.
  int sphere_pixels = 0, reddish_top = 0, bluish_bottom = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < 3 * w / 4; ++x) {
      const morph::Color c = at(x, y);
      if (is_background(c)) continue;
      ++sphere_pixels;
      if (y < h / 3 && c[0] > c[2]) ++reddish_top;
      if (y > 2 * h / 3 && c[2] > c[0]) ++bluish_bottom;
    }
  EXPECT_GT(sphere_pixels, 10000);
  EXPECT_GT(reddish_top, 1000);
  EXPECT_GT(bluish_bottom, 1000);
  EXPECT_TRUE(is_background(at(2, 2)));
  // Colour bar and labels right of the sphere (the view is framed in the left part, the sphere
  // ends before 3/4 of the width): red at the top of the bar, blue at its bottom, black ink.
  int red_top = 0, blue_bottom = 0, ink_pixels = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 3 * w / 4; x < w; ++x) {
      const morph::Color c = at(x, y);
      if (y < h / 2 && c[0] > c[2] + 40) ++red_top;
      if (y >= h / 2 && c[2] > c[0] + 40) ++blue_bottom;
      if (c == morph::Color{0, 0, 0}) ++ink_pixels;
    }
  EXPECT_GT(red_top, 100);
  EXPECT_GT(blue_bottom, 100);
  EXPECT_GT(ink_pixels, 100);
  stbi_image_free(data);
}

TEST(Render, RejectsUnknownScalarAndBadSize) {
  const morph::TriangleMesh cube =
      raytest_test::box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 1);
  raytest::RenderOptions options;
  options.scalar = "nope";
  EXPECT_THROW(raytest::render_mesh(cube, options), morph::InputError);
  options.scalar.clear();
  options.width = 0;
  EXPECT_THROW(raytest::render_mesh(cube, options), morph::InputError);
  EXPECT_THROW(raytest::parse_view("side"), morph::InputError);
  EXPECT_EQ(raytest::parse_view("front"), raytest::View::Front);
}

TEST(Render, WritePngFailsWithIoErrorForABadPath) {
  raytest::Image image;
  image.width = image.height = 4;
  image.rgb.assign(48, 0);
  EXPECT_THROW(raytest::write_png(image, "/nonexistent-dir/x.png"), morph::IoError);
}

}  // namespace
