// SPDX-License-Identifier: Apache-2.0
#pragma once
// The interactive 3D view of report.html: the part coloured by deviation, rotate and zoom
// (three.js OrbitControls), click a point to read its deviation and the move that made it.
// three.js comes from Debian's libjs-three and is inlined, so the report stays one offline file.
#include <morph/mesh.h>
#include <raytest/heatmap.h>

#include <cstddef>
#include <string>
#include <vector>

namespace morphmill {

struct View3d {
  morph::TriangleMesh mesh;            ///< with face tags (move, G-code line) when known
  std::vector<double> values;          ///< signed deviation per vertex, `unit`
  raytest::ScalarRange range;          ///< colour range, centred on zero
  double band_low = 0, band_high = 0;  ///< the tolerance band: gouge below, excess above, `unit`
  std::string unit;
  std::string title;                 ///< e.g. "Generator against the exact surface"
  std::size_t source_triangles = 0;  ///< triangles of the surface measured (the view may show fewer)
  bool decimated = false;            ///< the view shows a decimated copy (view3d_surface.h)
};

/// The HTML block (a <section> with the canvas, legend, read-out, the embedded data and scripts).
/// Reads three.js from `three_dir` (e.g. /usr/share/javascript/three); when it is missing, the
/// block says so instead of showing the view. Throws std::invalid_argument for inconsistent data.
std::string view3d_html(const View3d& view, const std::string& three_dir);

/// Where Debian's libjs-three puts three.js (set at build time).
std::string default_three_dir();

}  // namespace morphmill
