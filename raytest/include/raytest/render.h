// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file render.h
/// Pictures of a mesh by casting rays at it (Embree): headlight + ambient shading, optionally
/// colour-mapped by a vertex scalar, with a colour bar and a labelled scale.
#include <morph/mesh.h>
#include <raytest/heatmap.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace raytest {

/// Standard views, auto-framed on the mesh bounds. Iso looks from (+1, -1, +1) towards the
/// centre with +z up; Top looks down -z with +y up; Front looks along +y with +z up.
enum class View { Iso, Top, Front };

struct RenderOptions {
  int width = 800;   ///< pixels
  int height = 600;  ///< pixels
  View view = View::Iso;
  std::string scalar;  ///< name of a vertex scalar to colour by; empty: plain grey (or the mesh colours)
  ColorMap color_map = ColorMap::Viridis;
  std::optional<ScalarRange> range;  ///< fixed range; default: auto_range(values, symmetric)
  bool symmetric = false;
  std::string unit;  ///< label appended to the scale title (e.g. "mm")
  morph::Color background{255, 255, 255};
};

/// An 8-bit RGB image, rows top to bottom.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3
  morph::Color pixel(int x, int y) const {
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * width + x);
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

/// Renders `mesh`. Throws morph::InputError for a bad size or an unknown scalar name.
Image render_mesh(const morph::TriangleMesh& mesh, const RenderOptions& options);

/// Writes `image` as PNG. Throws morph::IoError naming the file on failure.
void write_png(const Image& image, const std::string& path);

/// Parses "iso", "top", "front"; throws morph::InputError otherwise.
View parse_view(const std::string& name);

}  // namespace raytest
