// SPDX-License-Identifier: Apache-2.0
#pragma once
// The colour legend and captions of a picture, drawn with cairo (real fonts, antialiased text).
#include <raytest/heatmap.h>
#include <raytest/render.h>

#include <string>
#include <vector>

namespace raytest::detail {

struct Legend {
  ColorMap color_map = ColorMap::CoolWarm;
  ScalarRange range;
  std::string title;         ///< e.g. "deviation_exact [mm]"
  std::string low_caption;   ///< under the bar, e.g. "- gouge"
  std::string high_caption;  ///< above the bar, e.g. "+ excess"
  int panel_x = 0;           ///< left edge of the legend panel, pixels
};

/// Width in pixels the legend needs for an image of this height.
int legend_width(const Legend& legend, int image_height);

/// Draws the legend into the panel [panel_x, width) of `image`, and `caption` (may be empty) at
/// the top left of the view. Throws std::runtime_error when cairo fails.
void draw_legend(Image& image, const Legend& legend, const std::string& caption);

}  // namespace raytest::detail
