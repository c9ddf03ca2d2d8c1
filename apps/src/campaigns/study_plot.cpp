// SPDX-License-Identifier: Apache-2.0
// Charts of `morphmill study` through PLplot's cairo PNG driver ("pngcairo", headless).
#include <morph/exceptions.h>
#include <plplot.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <mutex>
#include <string>

#include "campaigns/study.h"

namespace morphmill::study {

namespace {

// PLplot keeps one global plotting state.
std::mutex& plplot_mutex() {
  static std::mutex mutex;
  return mutex;
}

// Palette: 0 background, 1 axes and text, 2.. the series (a colour-blind-safe set).
constexpr int kPalette[][3] = {{255, 255, 255}, {0, 0, 0},       {31, 119, 180}, {214, 39, 40},
                               {44, 160, 44},   {148, 103, 189}, {255, 127, 14}, {140, 86, 75},
                               {227, 119, 194}, {127, 127, 127}};
constexpr int kSeriesColours = 8;
const char* const kMarker = "#(728)";

}  // namespace

void plot_png(const PlotSpec& spec, const std::string& path) {
  // Transform to the axes' coordinates (PLplot's log axes take log10 values) and drop what a
  // log axis cannot show.
  struct Drawn {
    std::vector<PLFLT> x, y;
  };
  std::vector<Drawn> drawn(spec.series.size());
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min, y_min = x_min, y_max = -x_min;
  for (std::size_t s = 0; s < spec.series.size(); ++s) {
    const PlotSeries& series = spec.series[s];
    for (std::size_t i = 0; i < std::min(series.x.size(), series.y.size()); ++i) {
      double x = series.x[i], y = series.y[i];
      if (!std::isfinite(x) || !std::isfinite(y) || (spec.log_x && x <= 0) || (spec.log_y && y <= 0))
        continue;
      if (spec.log_x) x = std::log10(x);
      if (spec.log_y) y = std::log10(y);
      drawn[s].x.push_back(x);
      drawn[s].y.push_back(y);
      x_min = std::min(x_min, x);
      x_max = std::max(x_max, x);
      y_min = std::min(y_min, y);
      y_max = std::max(y_max, y);
    }
  }
  if (!std::isfinite(x_min)) throw morph::InputError(path + ": nothing to plot (no finite, positive points)");
  auto pad = [](double& low, double& high, bool log) {
    const double span = high - low;
    const double margin = span > 0 ? 0.08 * span : (log ? 0.5 : std::max(0.5, 0.1 * std::abs(low)));
    low -= margin;
    high += margin;
  };
  pad(x_min, x_max, spec.log_x);
  pad(y_min, y_max, spec.log_y);
  // Headroom for the legend in the top left corner, so it does not hide the data.
  const auto labelled = std::count_if(spec.series.begin(), spec.series.end(),
                                      [](const PlotSeries& series) { return !series.label.empty(); });
  y_max += (y_max - y_min) * 0.075 * static_cast<double>(labelled);

  std::lock_guard<std::mutex> lock(plplot_mutex());
  // plinit() exits the process for an unknown device: ask for the list first.
  {
    const char* menu_names[64] = {};
    const char* device_names[64] = {};
    const char** menus = menu_names;
    const char** devices = device_names;
    PLINT count = 64;
    plgDevs(&menus, &devices, &count);
    const bool found = std::any_of(devices, devices + count,
                                   [](const char* name) { return name && std::string(name) == "pngcairo"; });
    if (!found)
      throw morph::IoError(path +
                           ": PLplot has no pngcairo device (install the package plplot-driver-cairo)");
  }
  plsdev("pngcairo");
  plsfnam(path.c_str());
  const std::string geometry = std::to_string(spec.width) + "x" + std::to_string(spec.height);
  plsetopt("geometry", geometry.c_str());
  for (int i = 0; i < static_cast<int>(std::size(kPalette)); ++i)
    plscol0(i, kPalette[i][0], kPalette[i][1], kPalette[i][2]);
  plinit();
  plcol0(1);
  plenv(x_min, x_max, y_min, y_max, 0, (spec.log_x ? 10 : 0) + (spec.log_y ? 20 : 0));
  pllab(spec.x_label.c_str(), spec.y_label.c_str(), spec.title.c_str());

  std::vector<PLINT> options, text_colours, line_colours, line_styles, symbol_colours, symbol_numbers;
  std::vector<PLFLT> line_widths, symbol_scales;
  std::vector<const char*> texts, symbols;
  for (std::size_t s = 0; s < spec.series.size(); ++s) {
    const PlotSeries& series = spec.series[s];
    const PLINT colour = 2 + (std::max(1, series.color) - 1) % kSeriesColours;
    const PLINT n = static_cast<PLINT>(drawn[s].x.size());
    plcol0(colour);
    if (series.line && n > 1) {
      pllsty(series.dashed ? 2 : 1);
      plline(n, drawn[s].x.data(), drawn[s].y.data());
      pllsty(1);
    }
    if (series.markers && n > 0) plstring(n, drawn[s].x.data(), drawn[s].y.data(), kMarker);
    if (series.label.empty()) continue;
    options.push_back((series.line ? PL_LEGEND_LINE : 0) | (series.markers ? PL_LEGEND_SYMBOL : 0));
    texts.push_back(series.label.c_str());
    text_colours.push_back(1);
    line_colours.push_back(colour);
    line_styles.push_back(series.dashed ? 2 : 1);
    line_widths.push_back(1.0);
    symbol_colours.push_back(colour);
    symbol_scales.push_back(1.0);
    symbol_numbers.push_back(1);
    symbols.push_back(kMarker);
  }
  if (!texts.empty()) {
    PLFLT legend_width = 0, legend_height = 0;
    plcol0(1);
    pllegend(&legend_width, &legend_height, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX,
             PL_POSITION_INSIDE | PL_POSITION_TOP | PL_POSITION_LEFT, 0.02, 0.02, 0.08, 0, 1, 1, 0, 0,
             static_cast<PLINT>(texts.size()), options.data(), 1.0, 0.7, 2.0, 0.0, text_colours.data(),
             texts.data(), nullptr, nullptr, nullptr, nullptr, line_colours.data(), line_styles.data(),
             line_widths.data(), symbol_colours.data(), symbol_scales.data(), symbol_numbers.data(),
             symbols.data());
  }
  plend();
  std::error_code error;
  if (!std::filesystem::exists(path, error) || std::filesystem::file_size(path, error) == 0)
    throw morph::IoError(path + ": PLplot did not write the picture");
}

}  // namespace morphmill::study
