// SPDX-License-Identifier: Apache-2.0
// Planar results as JSON (loops of curves with provenance, pieces, area, perimeter) and the one
// entry point that writes a result by its file extension.
#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morphmill/planar_io.h>

#include <filesystem>
#include <fstream>

namespace morphmill {

namespace {

using morph::planar::Curve;
using nlohmann::json;

json point(const morph::planar::Vec2& p) {
  return json::array({p.x(), p.y()});
}

json provenance(const morph::planar::Provenance& from) {
  json j;
  switch (from.origin) {
    case morph::planar::Origin::Stock:
      j["kind"] = "stock";
      j["element"] = from.source;
      break;
    case morph::planar::Origin::Sweep:
      j["kind"] = "sweep";
      j["move"] = from.source;
      break;
    case morph::planar::Origin::Offset:
      j["kind"] = "offset";
      j["element"] = from.source;
      break;
  }
  if (from.line > 0) j["line"] = from.line;
  return j;
}

json curve_json(const Curve& c) {
  json j;
  j["type"] = c.is_arc() ? "arc" : "line";
  j["start"] = point(c.start);
  j["end"] = point(c.end);
  if (c.is_arc()) {
    j["center"] = point(c.center);
    j["radius"] = c.radius;
    j["sweep_deg"] = c.sweep * 180.0 / M_PI;
  }
  j["from"] = provenance(c.from);
  return j;
}

}  // namespace

json region_to_json(const morph::planar::Region& region) {
  json j;
  j["area"] = morph::planar::area(region);
  j["perimeter"] = morph::planar::perimeter(region);
  j["pieces"] = json::array();
  for (const auto& piece : region.pieces) {
    double a = morph::planar::signed_area(region.loops[piece.outer]);
    for (const std::size_t h : piece.holes) a += morph::planar::signed_area(region.loops[h]);
    j["pieces"].push_back({{"outer", piece.outer}, {"holes", piece.holes}, {"area", a}});
  }
  j["loops"] = json::array();
  for (const auto& loop : region.loops) {
    json curves = json::array();
    for (const Curve& c : loop.curves) curves.push_back(curve_json(c));
    j["loops"].push_back({{"signed_area", morph::planar::signed_area(loop)}, {"curves", curves}});
  }
  return j;
}

void write_planar_result(const PlanarDrawing& drawing, const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".svg") return write_planar_svg(drawing, path);
  if (!drawing.result) throw std::logic_error("write_planar_result: no result");
  if (ext == ".dxf") return write_region_dxf(*drawing.result, path);
  if (ext == ".json") {
    morph::write_file_atomically(path, region_to_json(*drawing.result).dump(1) + "\n");
    return;
  }
  throw morph::InputError(path + ": unknown output format '" + ext + "' (use .svg, .dxf or .json)");
}

}  // namespace morphmill
