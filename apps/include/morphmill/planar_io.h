// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file planar_io.h
/// The planar model's files: planar jobs (JSON, docs/planar.md), shapes read from SVG paths and
/// DXF entities, and results written as SVG (exact arcs), DXF (LWPOLYLINE with bulges) or JSON.
/// Errors name the file and the element ("part.dxf:120: SPLINE entities are not supported").
#include <morph/job.h>
#include <morph/planar_dilation.h>
#include <morph/planar_region.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace morphmill {

/// A stock region, a disc tool and a trajectory, in job units.
struct PlanarJob {
  std::string name;
  std::string file;
  std::string description;
  morph::Units units = morph::Units::Millimetre;
  morph::planar::Region stock;
  morph::planar::Trajectory moves;  ///< Origin::Sweep, source = move index, line = input line
  double radius = 0.0;              ///< the disc's radius (> 0)
  double tolerance = 0.01;          ///< for the reference and the 3D comparison, job units
  std::vector<morph::Warning> warnings;
};

/// Reads and validates a planar job. Throws morph::InputError naming the file and the JSON path,
/// or the shape file and its element; morph::IoError if a file cannot be read.
PlanarJob load_planar_job(const std::string& path);
PlanarJob parse_planar_job(const nlohmann::json& json, const std::string& file);

/// Curves read from a drawing: closed outlines as loops, open ones as chains in drawing order.
/// Every curve's from.line is its line in the file (SVG: the element's line).
struct PlanarShapes {
  std::vector<morph::planar::Loop> closed;
  std::vector<std::vector<morph::planar::Curve>> open;
};
/// SVG <path> (M L H V A Z, absolute and relative; circular arcs only), <rect>, <circle>,
/// <polygon>, <polyline>, <line>. The y axis is flipped (SVG draws y downwards).
PlanarShapes read_svg_shapes(const std::string& path);
/// DXF LINE, ARC, CIRCLE and LWPOLYLINE (with bulges) from the ENTITIES section; open LINEs and
/// ARCs that meet end to end are chained, and chains that close become loops.
PlanarShapes read_dxf_shapes(const std::string& path);

/// What a picture or file shows besides the result.
struct PlanarDrawing {
  const morph::planar::Region* result = nullptr;
  const morph::planar::Region* stock = nullptr;
  const morph::planar::Region* dilation = nullptr;
  const morph::planar::Trajectory* moves = nullptr;
  std::string title;
};
/// SVG picture: stock outline, dilation, result (pieces filled), trajectory; arcs stay arcs.
void write_planar_svg(const PlanarDrawing& drawing, const std::string& path);
/// DXF (R12, readable everywhere): every boundary curve as a LINE or an ARC, layer RESULT.
void write_region_dxf(const morph::planar::Region& region, const std::string& path);
/// JSON: loops of curves with provenance, pieces, area and perimeter.
nlohmann::json region_to_json(const morph::planar::Region& region);
/// Writes the result as .svg, .dxf or .json by the extension; throws InputError for another one.
void write_planar_result(const PlanarDrawing& drawing, const std::string& path);

}  // namespace morphmill
