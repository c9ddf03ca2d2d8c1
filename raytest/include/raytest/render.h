// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file render.h
/// Pictures of a mesh by casting rays at it (Embree): headlight + ambient shading, optionally
/// colour-mapped by a vertex scalar (the value interpolated at each pixel's hit point, then
/// mapped: colour per sample, so a feature a few pixels wide keeps its colour), with a colour bar
/// whose text (ticks, title with units, captions) cairo draws.
#include <morph/mesh.h>

#include <raytest/heatmap.h>
#include <Eigen/Geometry>

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
  /// Frame this box (job units) instead of the whole mesh: a close-up. Geometry between the camera
  /// and the box is cut away, so walls in front do not hide the place; behind it, it still shows.
  std::optional<Eigen::AlignedBox3d> focus;
  /// Shade by the surface's angle to the light. Off, every pixel of the mesh has exactly its
  /// colour-map colour (for checks and for reading colours off the picture).
  bool lighting = true;
  std::string caption;       ///< written at the top left (e.g. "iso view"); empty: none
  std::string low_caption;   ///< under the colour bar (e.g. "- gouge"); empty: none
  std::string high_caption;  ///< above the colour bar (e.g. "+ excess"); empty: none
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

/// Where a point lands in a picture rendered with `options` (same mesh, same size): pixel column
/// and row (may lie outside the image). For tests and for marking places on pictures.
Eigen::Vector2d project_to_pixel(const morph::TriangleMesh& mesh, const RenderOptions& options,
                                 const Eigen::Vector3d& point);

/// Writes `image` as PNG. Throws morph::IoError naming the file on failure.
void write_png(const Image& image, const std::string& path);

/// Parses "iso", "top", "front"; throws morph::InputError otherwise.
View parse_view(const std::string& name);

}  // namespace raytest
