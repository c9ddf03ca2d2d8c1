// SPDX-License-Identifier: Apache-2.0
#include "legend.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace raytest::detail {

namespace {

using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using Context = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

double font_size(int image_height) {
  return std::clamp(image_height / 45.0, 10.0, 40.0);
}

// Enough significant digits that neighbouring ticks `step` apart print differently.
std::string tick_label(double v, double step) {
  const double magnitude = std::abs(v);
  if (magnitude < 1e-9 * std::max(step, 1e-300)) return "0";
  int digits = 3;
  if (step > 0 && magnitude > step)
    digits = std::clamp(static_cast<int>(std::ceil(std::log10(magnitude / step))) + 2, 3, 12);
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%+.*g", digits, v);
  return buffer;
}

double text_width(cairo_t* cr, const std::string& text) {
  cairo_text_extents_t extents;
  cairo_text_extents(cr, text.c_str(), &extents);
  return extents.x_advance;
}

constexpr int kTicks = 4;

std::vector<std::string> labels_of(const Legend& legend) {
  std::vector<std::string> labels;
  const double step = (legend.range.high - legend.range.low) / kTicks;
  for (int tick = 0; tick <= kTicks; ++tick)
    labels.push_back(tick_label(legend.range.low + step * tick, step));
  return labels;
}

}  // namespace

int legend_width(const Legend& legend, int image_height) {
  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1), &cairo_surface_destroy);
  Context cr(cairo_create(surface.get()), &cairo_destroy);
  cairo_select_font_face(cr.get(), "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  const double size = font_size(image_height);
  cairo_set_font_size(cr.get(), size);
  double widest = 0;
  for (const std::string& label : labels_of(legend)) widest = std::max(widest, text_width(cr.get(), label));
  for (const std::string* caption : {&legend.title, &legend.low_caption, &legend.high_caption})
    widest = std::max(widest, text_width(cr.get(), *caption) - 2.5 * size);
  return static_cast<int>(std::ceil(size * 4.0 + widest + size));
}

void draw_legend(Image& image, const Legend& legend, const std::string& caption) {
  // cairo's RGB24 is one 32-bit word per pixel (xRGB in native order); copy in and out.
  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, image.width, image.height),
                  &cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error("cairo: cannot create a picture surface");
  cairo_surface_flush(surface.get());
  unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  for (int y = 0; y < image.height; ++y) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::size_t>(y) * stride);
    for (int x = 0; x < image.width; ++x) {
      const morph::Color c = image.pixel(x, y);
      row[x] = (std::uint32_t(c[0]) << 16) | (std::uint32_t(c[1]) << 8) | std::uint32_t(c[2]);
    }
  }
  cairo_surface_mark_dirty(surface.get());
  Context cr(cairo_create(surface.get()), &cairo_destroy);
  cairo_t* c = cr.get();
  cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  const double size = font_size(image.height);
  cairo_set_font_size(c, size);

  if (!legend.title.empty()) {
    const double bar_x = legend.panel_x + size;
    const double bar_w = 1.2 * size;
    const double top = image.height * 0.12 + 2 * size, bottom = image.height * 0.88 - size;
    // The bar: one row of the colour map per pixel, high values at the top; no interpolation, so
    // the pixel at the middle is the map's centre colour.
    const int rows = std::max(1, static_cast<int>(std::lround(bottom - top)));
    for (int r = 0; r < rows; ++r) {
      const morph::Color col = map_color(legend.color_map, 1.0 - (r + 0.5) / rows);
      cairo_set_source_rgb(c, col[0] / 255.0, col[1] / 255.0, col[2] / 255.0);
      cairo_rectangle(c, bar_x, std::floor(top) + r, bar_w, 1.0);
      cairo_fill(c);
    }
    cairo_set_source_rgb(c, 0, 0, 0);
    cairo_set_line_width(c, 1.0);
    cairo_rectangle(c, bar_x - 0.5, std::floor(top) - 0.5, bar_w + 1, rows + 1);
    cairo_stroke(c);
    const std::vector<std::string> labels = labels_of(legend);
    for (int tick = 0; tick <= kTicks; ++tick) {
      const double y = std::floor(top) + rows - double(rows) * tick / kTicks;
      cairo_move_to(c, bar_x + bar_w, y);
      cairo_line_to(c, bar_x + bar_w + 0.4 * size, y);
      cairo_stroke(c);
      cairo_move_to(c, bar_x + bar_w + 0.6 * size, y + 0.35 * size);
      cairo_show_text(c, labels[tick].c_str());
    }
    cairo_move_to(c, legend.panel_x + 0.5 * size, image.height * 0.12);
    cairo_show_text(c, legend.title.c_str());
    if (!legend.high_caption.empty()) {
      cairo_move_to(c, bar_x, std::floor(top) - 0.5 * size);
      cairo_show_text(c, legend.high_caption.c_str());
    }
    if (!legend.low_caption.empty()) {
      cairo_move_to(c, bar_x, std::floor(top) + rows + 1.4 * size);
      cairo_show_text(c, legend.low_caption.c_str());
    }
  }
  if (!caption.empty()) {
    cairo_set_source_rgb(c, 0.15, 0.15, 0.15);
    cairo_move_to(c, 0.6 * size, 1.4 * size);
    cairo_show_text(c, caption.c_str());
  }
  if (cairo_status(c) != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(std::string("cairo: ") + cairo_status_to_string(cairo_status(c)));
  cairo_surface_flush(surface.get());
  for (int y = 0; y < image.height; ++y) {
    const auto* row = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::size_t>(y) * stride);
    for (int x = 0; x < image.width; ++x) {
      const std::size_t i = 3 * (static_cast<std::size_t>(y) * image.width + x);
      image.rgb[i] = std::uint8_t(row[x] >> 16);
      image.rgb[i + 1] = std::uint8_t(row[x] >> 8);
      image.rgb[i + 2] = std::uint8_t(row[x]);
    }
  }
}

}  // namespace raytest::detail
