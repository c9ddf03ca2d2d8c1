// SPDX-License-Identifier: Apache-2.0
// Planar job files (docs/planar.md): a stock made of shapes, a disc tool and a trajectory made of
// polylines, arcs, circles, plunges, G-code feed moves below a cutting height, SVG or DXF drawings.
// Every error names the job file and the JSON path, or the drawing and its element.
#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/gcode.h>
#include <morphmill/planar_io.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace morphmill {

namespace {

namespace fs = std::filesystem;
using morph::InputError;
using morph::planar::Curve;
using morph::planar::Loop;
using morph::planar::Origin;
using morph::planar::Vec2;
using nlohmann::json;

class PlanarJobParser {
 public:
  PlanarJobParser(const std::string& file, PlanarJob& job) : file_(file), job_(job) {
    const fs::path parent = fs::path(file).parent_path();
    base_ = parent.empty() ? fs::path(".") : parent;
  }

  [[noreturn]] void fail(const std::string& at, const std::string& what) const {
    throw InputError(file_ + ": " + (at.empty() ? "" : at + ": ") + what);
  }

  double number(const json& v, const std::string& at) const {
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      fail(at, "expected a finite number, got " + v.dump());
    return v.get<double>();
  }
  double positive(const json& v, const std::string& at) const {
    const double x = number(v, at);
    if (!(x > 0.0)) fail(at, fmt::format("must be positive, got {}", x));
    return x;
  }
  Vec2 point(const json& v, const std::string& at) const {
    if (!v.is_array() || v.size() != 2) fail(at, "expected [x, y], got " + v.dump());
    return Vec2(number(v[0], at + "[0]"), number(v[1], at + "[1]"));
  }
  const json& require(const json& object, const std::string& at, const char* key) const {
    if (!object.is_object()) fail(at, "expected an object, got " + object.dump());
    auto it = object.find(key);
    if (it == object.end()) fail(at, std::string("missing required key '") + key + "'");
    return *it;
  }
  std::string resolve(const json& v, const std::string& at) const {
    if (!v.is_string()) fail(at, "expected a file name, got " + v.dump());
    const fs::path p(v.get<std::string>());
    return (p.is_absolute() ? p : base_ / p).string();
  }

  /// Vertices [x, y] or [x, y, bulge]: the bulge belongs to the element leaving the vertex.
  std::vector<Curve> bulged_chain(const json& v, const std::string& at, bool closed) const {
    if (!v.is_array() || v.size() < 2) fail(at, "expected at least two points [x, y] or [x, y, bulge]");
    std::vector<Vec2> points;
    std::vector<double> bulges;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::string where = at + "[" + std::to_string(i) + "]";
      if (!v[i].is_array() || (v[i].size() != 2 && v[i].size() != 3))
        fail(where, "expected [x, y] or [x, y, bulge], got " + v[i].dump());
      points.emplace_back(number(v[i][0], where + "[0]"), number(v[i][1], where + "[1]"));
      bulges.push_back(v[i].size() == 3 ? number(v[i][2], where + "[2]") : 0.0);
    }
    std::vector<Curve> curves;
    const std::size_t n = closed ? points.size() : points.size() - 1;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2& a = points[i];
      const Vec2& b = points[(i + 1) % points.size()];
      curves.push_back(
          morph::planar::make_bulge(a, b, bulges[i], {Origin::Sweep, 0, static_cast<int>(i + 1)}));
    }
    return curves;
  }

  std::vector<Loop> stock_shape(const json& shape, const std::string& at) const {
    if (!shape.is_object() || shape.size() != 1)
      fail(at,
           "expected one of {\"rectangle\": ...}, {\"circle\": ...}, {\"polygon\": ...}, {\"svg\": ...}, "
           "{\"dxf\": ...}");
    const std::string kind = shape.begin().key();
    const json& v = shape.begin().value();
    const std::string where = at + "." + kind;
    if (kind == "rectangle") {
      if (!v.is_array() || v.size() != 4) fail(where, "expected [x0, y0, x1, y1]");
      const double x0 = number(v[0], where), y0 = number(v[1], where), x1 = number(v[2], where),
                   y1 = number(v[3], where);
      if (!(x1 > x0 && y1 > y0)) fail(where, "expected x1 > x0 and y1 > y0");
      Loop loop;
      const Vec2 p[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
      for (int i = 0; i < 4; ++i) loop.curves.push_back(morph::planar::make_segment(p[i], p[(i + 1) % 4]));
      return {loop};
    }
    if (kind == "circle") {
      const Vec2 c = point(require(v, where, "center"), where + ".center");
      const double r = positive(require(v, where, "radius"), where + ".radius");
      Loop loop;
      loop.curves.push_back(morph::planar::make_arc(c, r, 0.0, M_PI));
      loop.curves.push_back(morph::planar::make_arc(c, r, M_PI, M_PI));
      loop.curves[1].start = loop.curves[0].end;
      loop.curves[1].end = loop.curves[0].start;
      return {loop};
    }
    if (kind == "polygon") {
      if (v.is_array() && v.size() < 2) fail(where, "a polygon needs at least two points");
      return {Loop{bulged_chain(v, where, true)}};
    }
    if (kind == "svg" || kind == "dxf") {
      const std::string file = resolve(v, where);
      const PlanarShapes shapes = kind == "svg" ? read_svg_shapes(file) : read_dxf_shapes(file);
      if (!shapes.open.empty()) {
        const Curve& c = shapes.open.front().front();
        throw InputError(
            fmt::format("{}:{}: an open outline ({} elements from ({}, {})) cannot bound the stock", file,
                        c.from.line, shapes.open.front().size(), c.start.x(), c.start.y()));
      }
      if (shapes.closed.empty()) fail(where, file + " holds no closed outline");
      return shapes.closed;
    }
    fail(at, "unknown stock shape '" + kind + "' (rectangle, circle, polygon, svg, dxf)");
  }

  void add_moves(std::vector<Curve> curves) {
    for (Curve& c : curves) {
      c.from.origin = Origin::Sweep;
      c.from.source = static_cast<std::int32_t>(job_.moves.size());
      job_.moves.push_back(c);
    }
  }

  void trajectory_entry(const json& entry, const std::string& at) {
    if (!entry.is_object() || entry.empty())
      fail(at,
           "expected one of {\"polyline\": ...}, {\"arc\": ...}, {\"circle\": ...}, {\"point\": ...}, "
           "{\"gcode\": ...}, {\"svg\": ...}, {\"dxf\": ...}");
    // The entry's kind is its one key besides the options ("cutting_height" of a G-code entry).
    std::string kind;
    for (auto it = entry.begin(); it != entry.end(); ++it)
      if (it.key() != "cutting_height") {
        if (!kind.empty()) fail(at, "expected one entry, got '" + kind + "' and '" + it.key() + "'");
        kind = it.key();
      }
    if (kind.empty()) fail(at, "expected an entry such as {\"polyline\": ...}");
    const json& v = entry[kind];
    const std::string where = at + "." + kind;
    if (kind == "polyline") return add_moves(bulged_chain(v, where, false));
    if (kind == "point") return add_moves({morph::planar::make_segment(point(v, where), point(v, where))});
    if (kind == "arc") {
      const Vec2 c = point(require(v, where, "center"), where + ".center");
      const Vec2 s = point(require(v, where, "start"), where + ".start");
      const double sweep = number(require(v, where, "sweep"), where + ".sweep") * M_PI / 180.0;
      if (sweep == 0.0 || std::abs(sweep) > 2.0 * M_PI)
        fail(where + ".sweep", "must be in [-360, 360] and not 0");
      if ((s - c).norm() == 0.0) fail(where, "the start is the centre");
      Curve arc = morph::planar::make_arc(c, (s - c).norm(), std::atan2(s.y() - c.y(), s.x() - c.x()), sweep);
      arc.start = s;
      return add_moves({arc});
    }
    if (kind == "circle") {
      const Vec2 c = point(require(v, where, "center"), where + ".center");
      const double r = positive(require(v, where, "radius"), where + ".radius");
      return add_moves({morph::planar::make_arc(c, r, 0.0, 2.0 * M_PI)});
    }
    if (kind == "gcode") {
      const std::string file = resolve(v, where);
      const auto height = entry.find("cutting_height");
      if (height == entry.end())
        fail(at, "a G-code trajectory needs 'cutting_height' (feed moves at or below it cut)");
      morph::GcodeOptions options;
      options.job_units = job_.units;
      const morph::GcodeResult program = morph::read_gcode(file, options);
      for (const morph::Warning& w : program.warnings) job_.warnings.push_back(w);
      std::vector<const morph::Move*> moves;
      for (const morph::Move& m : program.path.moves) moves.push_back(&m);
      try {
        return add_moves(morph::planar::planar_trajectory(moves, number(*height, at + ".cutting_height")));
      } catch (const InputError& e) {
        throw InputError(file + ": " + e.what());
      }
    }
    if (kind == "svg" || kind == "dxf") {
      const std::string file = resolve(v, where);
      const PlanarShapes shapes = kind == "svg" ? read_svg_shapes(file) : read_dxf_shapes(file);
      for (const auto& chain : shapes.open) add_moves(chain);
      for (const Loop& loop : shapes.closed) add_moves(loop.curves);
      return;
    }
    fail(at, "unknown trajectory entry '" + kind + "' (polyline, arc, circle, point, gcode, svg, dxf)");
  }

 private:
  std::string file_;
  PlanarJob& job_;
  fs::path base_;
};

}  // namespace

PlanarJob parse_planar_job(const json& root, const std::string& file) {
  PlanarJob job;
  job.file = file;
  PlanarJobParser parser(file, job);
  if (!root.is_object()) parser.fail("", "expected a JSON object");
  if (auto it = root.find("name"); it != root.end() && it->is_string()) job.name = it->get<std::string>();
  if (auto it = root.find("description"); it != root.end() && it->is_string())
    job.description = it->get<std::string>();
  if (auto it = root.find("units"); it != root.end()) {
    const std::string u = it->is_string() ? it->get<std::string>() : "";
    if (u == "mm")
      job.units = morph::Units::Millimetre;
    else if (u == "inch" || u == "in")
      job.units = morph::Units::Inch;
    else
      parser.fail("units", "expected \"mm\" or \"inch\", got " + it->dump());
  }
  const json& tool = parser.require(root, "", "tool");
  if (tool.contains("diameter"))
    job.radius = 0.5 * parser.positive(tool["diameter"], "tool.diameter");
  else
    job.radius = parser.positive(parser.require(tool, "tool", "radius"), "tool.radius");
  if (auto it = root.find("tolerance"); it != root.end()) job.tolerance = parser.positive(*it, "tolerance");

  const json& stock = parser.require(root, "", "stock");
  if (!stock.is_array() || stock.empty()) parser.fail("stock", "expected a non-empty array of shapes");
  std::vector<Loop> loops;
  for (std::size_t i = 0; i < stock.size(); ++i) {
    std::vector<Loop> shape = parser.stock_shape(stock[i], "stock[" + std::to_string(i) + "]");
    for (Loop& loop : shape) {
      for (Curve& c : loop.curves) c.from.origin = Origin::Stock;
      loops.push_back(std::move(loop));
    }
  }
  morph::planar::Box2 extent;
  for (const Loop& loop : loops)
    for (const Curve& c : loop.curves) extent.extend(morph::planar::bounds(c));
  const double gap = 1e-9 * std::max({extent.sizes().maxCoeff(), extent.min().cwiseAbs().maxCoeff(),
                                      extent.max().cwiseAbs().maxCoeff()});
  morph::planar::validate_loops(loops, file + ": stock", gap);
  job.stock = morph::planar::make_region(std::move(loops));

  const json& trajectory = parser.require(root, "", "trajectory");
  if (!trajectory.is_array()) parser.fail("trajectory", "expected an array of entries");
  for (std::size_t i = 0; i < trajectory.size(); ++i)
    parser.trajectory_entry(trajectory[i], "trajectory[" + std::to_string(i) + "]");
  if (job.name.empty()) job.name = fs::path(file).stem().string();
  return job;
}

PlanarJob load_planar_job(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw morph::IoError(path + ": cannot open the planar job file");
  json root;
  try {
    root = json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(path + ": not valid JSON: " + e.what());
  }
  return parse_planar_job(root, path);
}

}  // namespace morphmill
