// SPDX-License-Identifier: Apache-2.0
// Job files (docs/job-format.md). Every error names the job file and the JSON path of the value
// at fault; unknown keys are warnings so that a misspelt optional key is never silently ignored.
#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morph/gcode.h>
#include <morph/shells.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>
#include <morphmill/self_intersections.h>
#include <morphmill/tool_sources.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <set>
#include <sstream>

#include "cli/edit_distance.h"

namespace morphmill {

namespace {

namespace fs = std::filesystem;
using morph::InputError;
using nlohmann::json;

/// Default tolerance: 0.01 mm, expressed in the job's units.
constexpr double kDefaultToleranceMillimetres = 0.01;

std::string join_path(const std::string& at, const std::string& key) {
  return at.empty() ? key : at + "." + key;
}
std::string index_path(const std::string& at, std::size_t i) {
  return at + "[" + std::to_string(i) + "]";
}

/// Shortest decimal text that reads back as `x` (5 rather than 5.0).
std::string text(double x) {
  return fmt::format("{}", x);
}

std::string describe_value(const json& v) {
  std::string text = v.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return std::string(v.type_name()) + " " + text;
}

/// Job files larger than this are refused before parsing (a job of 10^6 polyline points is ~40 MB).
constexpr std::uint64_t kMaxJobFileBytes = std::uint64_t(1) << 30;

/// Deepest nesting of arrays and objects a job file may have; a job needs five levels.
constexpr std::size_t kMaxJsonDepth = 64;

/// Follows nlohmann's parse events to know the JSON path of the value being read, so that an
/// error inside the parser (a number overflowing a double) is named by its path, and refuses
/// nesting past kMaxJsonDepth before anything recursive (dump, destruction) sees it.
class JsonPathTracker {
 public:
  void on(json::parse_event_t event, const json& parsed, const std::string& file) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (frames_.size() >= kMaxJsonDepth)
          throw InputError(file + ": " + path() + ": JSON nested deeper than " +
                           std::to_string(kMaxJsonDepth) + " levels; a job file needs no more than a few");
        frames_.push_back({event == json::parse_event_t::array_start, 0, {}});
        break;
      case json::parse_event_t::key:
        if (!frames_.empty() && parsed.is_string()) frames_.back().key = parsed.get<std::string>();
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!frames_.empty()) frames_.pop_back();
        [[fallthrough]];
      case json::parse_event_t::value:
        if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
        break;
    }
  }

  /// The path of the value being read, such as `paths[2].polyline[7]` ("(top level)" outside any).
  std::string path() const {
    std::string out;
    for (std::size_t i = 0; i < frames_.size(); ++i) {
      if (frames_.size() > 12 && i == 6) {
        out += "...(" + std::to_string(frames_.size() - 11) + " levels)...";
        i = frames_.size() - 5;
      }
      out = frames_[i].array ? index_path(out, frames_[i].index) : join_path(out, frames_[i].key);
    }
    return out.empty() ? "(top level)" : out;
  }

 private:
  struct Frame {
    bool array = false;
    std::size_t index = 0;
    std::string key;
  };
  std::vector<Frame> frames_;
};

/// Parsing context: the job file for messages and relative paths, and the warnings so far.
class JobParser {
 public:
  JobParser(std::string file, std::vector<morph::Warning>& warnings)
      : file_(std::move(file)), warnings_(warnings) {
    const fs::path parent = fs::path(file_).parent_path();
    base_dir_ = parent.empty() ? fs::path(".") : parent;
  }

  [[noreturn]] void fail(const std::string& at, const std::string& what) const {
    throw InputError(file_ + ": " + (at.empty() ? "" : at + ": ") + what);
  }

  void warn(const std::string& at, const std::string& what) const {
    warnings_.push_back({file_, 0, (at.empty() ? "" : at + ": ") + what});
  }

  const std::string& file() const { return file_; }

  /// Warns about keys of `object` not in `known`. Keys starting with '_' are comments.
  void check_keys(const json& object, const std::string& at, std::initializer_list<const char*> known) const {
    for (auto it = object.begin(); it != object.end(); ++it) {
      const std::string& key = it.key();
      if (!key.empty() && key[0] == '_') continue;
      if (std::any_of(known.begin(), known.end(), [&](const char* k) { return key == k; })) continue;
      std::string suggestion;
      std::size_t best = 3;  // suggest only close matches
      for (const char* k : known) {
        const std::size_t d = edit_distance(key, k);
        if (d < best) best = d, suggestion = k;
      }
      warn(join_path(at, key),
           "unknown key, ignored" + (suggestion.empty() ? "" : " (did you mean '" + suggestion + "'?)"));
    }
  }

  const json& object(const json& v, const std::string& at) const {
    if (!v.is_object()) fail(at, "expected an object, got " + describe_value(v));
    return v;
  }

  const json* find(const json& object, const char* key) const {
    auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
  }

  const json& require(const json& object, const std::string& at, const char* key) const {
    if (const json* v = find(object, key)) return *v;
    fail(at, std::string("missing required key '") + key + "'");
  }

  double number(const json& v, const std::string& at) const {
    if (!v.is_number()) fail(at, "expected a number, got " + describe_value(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(at, "expected a finite number");
    return x;
  }

  double positive(const json& v, const std::string& at) const {
    const double x = number(v, at);
    if (!(x > 0)) fail(at, "must be greater than 0, got " + v.dump());
    return x;
  }

  std::string string(const json& v, const std::string& at) const {
    if (!v.is_string()) fail(at, "expected a string, got " + describe_value(v));
    return v.get<std::string>();
  }

  Eigen::Vector3d point(const json& v, const std::string& at) const {
    if (!v.is_array() || v.size() != 3 ||
        !std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); }))
      fail(at, "expected 3 numbers, got " + describe_value(v));
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k) p[k] = number(v[k], index_path(at, k));
    return p;
  }

  /// A tool number: an integer >= 0, as a JSON number or a string of digits.
  int tool_number(const json& v, const std::string& at) const {
    if (v.is_number_integer() || (v.is_number_float() && v.get<double>() == std::floor(v.get<double>()))) {
      const double x = v.get<double>();
      if (x >= 0 && x <= 2147483647.0) return int(x);
    } else if (v.is_string()) {
      const std::string s = v.get<std::string>();
      if (!s.empty() && s.size() <= 9 &&
          std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return std::stoi(s);
    }
    fail(at, "expected a tool number (an integer >= 0), got " + describe_value(v));
  }

  /// "design": "part.stl" or {"path": "part.stl", "band": [-0.02, 0.1]}.
  DesignSpec design(const json& v, const std::string& at) const {
    DesignSpec spec;
    if (v.is_string()) {
      spec.path = referenced_file(v, at, "design");
      return spec;
    }
    object(v, at);
    check_keys(v, at, {"path", "band", "description"});
    spec.path = referenced_file(require(v, at, "path"), join_path(at, "path"), "design");
    if (const json* band = find(v, "band")) {
      const std::string band_at = join_path(at, "band");
      if (!band->is_array() || band->size() != 2)
        fail(band_at, "expected [low, high] with low <= 0 <= high, got " + describe_value(*band));
      spec.low = number((*band)[0], index_path(band_at, 0));
      spec.high = number((*band)[1], index_path(band_at, 1));
      if (spec.low > 0 || spec.high < 0 || (spec.low == 0 && spec.high == 0))
        fail(band_at, "expected [low, high] with low <= 0 <= high (not both 0), got " + band->dump());
    }
    return spec;
  }

  /// A file named in the job, relative to the job file's directory; must exist.
  std::string referenced_file(const json& v, const std::string& at, const char* what) const {
    const std::string name = string(v, at);
    if (name.empty()) fail(at, std::string("empty ") + what + " file name");
    const fs::path resolved = fs::path(name).is_absolute() ? fs::path(name) : base_dir_ / name;
    std::error_code ec;
    if (!fs::exists(resolved, ec))
      fail(at, std::string(what) + " file '" + name + "' not found (looked for '" + resolved.string() + "')");
    if (fs::is_directory(resolved, ec)) fail(at, std::string(what) + " file '" + name + "' is a directory");
    return resolved.lexically_normal().string();
  }

  morph::Stock stock(const json& v, const std::string& at) const {
    object(v, at);
    morph::Stock stock;
    const std::string type = string(require(v, at, "type"), join_path(at, "type"));
    if (type == "box") {
      check_keys(v, at, {"type", "min", "max", "description"});
      const Eigen::Vector3d lo = point(require(v, at, "min"), join_path(at, "min"));
      const Eigen::Vector3d hi = point(require(v, at, "max"), join_path(at, "max"));
      for (int k = 0; k < 3; ++k)
        if (!(lo[k] < hi[k]))
          fail(join_path(at, "max"), std::string("must exceed min in every axis, but ") + "xyz"[k] + " max " +
                                         text(hi[k]) + " <= min " + text(lo[k]));
      stock.type = morph::StockType::Box;
      stock.box = Eigen::AlignedBox3d(lo, hi);
    } else if (type == "cylinder") {
      check_keys(v, at, {"type", "base", "axis", "radius", "height", "description"});
      stock.type = morph::StockType::Cylinder;
      stock.base = point(require(v, at, "base"), join_path(at, "base"));
      if (const json* axis = find(v, "axis")) {
        const Eigen::Vector3d a = point(*axis, join_path(at, "axis"));
        if (!(a.norm() > 0)) fail(join_path(at, "axis"), "must not be the zero vector");
        stock.axis = a.normalized();
      }
      stock.radius = positive(require(v, at, "radius"), join_path(at, "radius"));
      stock.height = positive(require(v, at, "height"), join_path(at, "height"));
    } else if (type == "mesh") {
      check_keys(v, at, {"type", "path", "description"});
      const std::string path_at = join_path(at, "path");
      const std::string path = referenced_file(require(v, at, "path"), path_at, "mesh");
      stock.type = morph::StockType::Mesh;
      stock.mesh_path = path;
      try {
        stock.mesh = read_mesh(path);
      } catch (const morph::InputError& e) {
        fail(path_at, e.what());
      } catch (const morph::IoError& e) {
        fail(path_at, e.what());
      }
      const morph::TopologyReport report = morph::topology_report(stock.mesh);
      if (!report.closed_manifold()) {
        std::ostringstream problems;
        problems << report.boundary_edges << " boundary edges, " << report.non_manifold_edges
                 << " non-manifold edges, " << report.inconsistent_edges << " inconsistently oriented edges, "
                 << report.non_manifold_vertices << " non-manifold vertices";
        fail(path_at, "stock mesh '" + path + "' is not a closed oriented manifold (" + problems.str() +
                          "); run 'morphmill mesh-info' on it");
      }
      if (!(report.volume > 0))
        fail(path_at, "stock mesh '" + path + "' is wound inward (enclosed volume " + text(report.volume) +
                          " <= 0); its faces must wind counter-clockwise seen from outside");
      if (const auto enclosed = morph::find_enclosed_shell(stock.mesh)) {
        const Eigen::Vector3d& p = stock.mesh.vertices[enclosed->vertex];
        fail(path_at, "stock mesh '" + path + "' has " + std::to_string(report.components) +
                          " shells, and the shell of triangle " + std::to_string(enclosed->inner_triangle) +
                          " lies inside or across the shell of triangle " +
                          std::to_string(enclosed->outer_triangle) + " (its vertex " +
                          std::to_string(enclosed->vertex) + " at (" + text(p.x()) + ", " + text(p.y()) +
                          ", " + text(p.z()) +
                          ") is enclosed); nested or overlapping shells would count their common "
                          "volume twice: merge them into one closed surface");
      }
      // A surface crossing itself bounds no solid (the erosion would count the crossed volume with
      // the wrong sign); whether two triangles cross is a sign, so it is decided exactly.
      const SelfIntersections crossings = find_self_intersections(stock.mesh, 3);
      if (crossings.pairs > 0) {
        std::string first;
        for (const auto& [a, b] : crossings.first_pairs)
          first += (first.empty() ? "" : ", ") + std::to_string(a) + " and " + std::to_string(b);
        fail(path_at, "stock mesh '" + path + "' intersects itself: " + std::to_string(crossings.pairs) +
                          " pairs of triangles cross (first: triangles " + first +
                          "); a stock must be a closed surface that does not cross itself ('morphmill "
                          "mesh-info' lists the pairs)");
      }
    } else {
      fail(join_path(at, "type"), "unknown stock type '" + type + "' (expected box, cylinder or mesh)");
    }
    return stock;
  }

  /// A size given as a diameter or as a radius (exactly one of the two keys); returns the radius,
  /// or NaN when neither is given and the size is optional.
  double radius_or_diameter(const json& v, const std::string& at, const char* diameter_key,
                            const char* radius_key, bool required) const {
    const json* d = find(v, diameter_key);
    const json* r = find(v, radius_key);
    if (d && r) fail(at, std::string("give '") + diameter_key + "' or '" + radius_key + "', not both");
    if (d) return 0.5 * positive(*d, join_path(at, diameter_key));
    if (r) return positive(*r, join_path(at, radius_key));
    if (required)
      fail(at, std::string("missing required key '") + diameter_key + "' (or '" + radius_key + "')");
    return std::nan("");
  }

  /// Tools (docs/job-format.md, "tools"): the shape's keys, then the morph constructor, whose
  /// complaints name their field (put after the tool's JSON path here).
  morph::Tool tool(const json& v, const std::string& at, int tool_number) const {
    object(v, at);
    const std::string type_at = join_path(at, "type");
    const std::string type_name = string(require(v, at, "type"), type_at);
    const morph::ToolType type = morph::tool_type_from_string(type_name, file_ + ": " + type_at);
    const bool by_diameter = find(v, "diameter") != nullptr;
    auto number_of = [&](const char* key) { return number(require(v, at, key), join_path(at, key)); };
    auto optional_number = [&](const char* key) {
      const json* x = find(v, key);
      return x ? number(*x, join_path(at, key)) : std::nan("");
    };
    morph::Tool tool;
    try {
      switch (type) {
        case morph::ToolType::Sphere:
          check_keys(v, at, {"type", "diameter", "radius", "length_offset", "description"});
          tool = morph::sphere_tool(radius_or_diameter(v, at, "diameter", "radius", true));
          break;
        case morph::ToolType::BallEnd:
          check_keys(v, at, {"type", "diameter", "radius", "length", "length_offset", "description"});
          tool = morph::ball_tool(radius_or_diameter(v, at, "diameter", "radius", true),
                                  positive(require(v, at, "length"), join_path(at, "length")));
          break;
        case morph::ToolType::Flat:
          check_keys(v, at, {"type", "diameter", "radius", "length", "length_offset", "description"});
          tool = morph::flat_tool(radius_or_diameter(v, at, "diameter", "radius", true), number_of("length"));
          break;
        case morph::ToolType::Bullnose:
          check_keys(
              v, at,
              {"type", "diameter", "radius", "corner_radius", "length", "length_offset", "description"});
          tool = morph::bullnose_tool(radius_or_diameter(v, at, "diameter", "radius", true),
                                      number_of("corner_radius"), number_of("length"));
          break;
        case morph::ToolType::Conical: {
          check_keys(v, at,
                     {"type", "diameter", "radius", "angle", "cone_length", "length", "tip_diameter",
                      "tip_radius", "length_offset", "description"});
          const double radius = radius_or_diameter(v, at, "diameter", "radius", true);
          double tip = radius_or_diameter(v, at, "tip_diameter", "tip_radius", false);
          if (std::isnan(tip)) tip = 0.0;
          const json* angle = find(v, "angle");
          const json* cone = find(v, "cone_length");
          if (angle && cone) fail(at, "give 'angle' or 'cone_length', not both");
          if (!angle && !cone) fail(at, "missing required key 'angle' (or 'cone_length')");
          double included = 0.0, height = 0.0;
          if (angle) {
            included = number(*angle, join_path(at, "angle"));
            height = std::isfinite(included) && included > 0 && included < 180 && tip < radius
                         ? morph::cone_height(radius, included, tip)
                         : 0.0;
          } else {
            height = positive(*cone, join_path(at, "cone_length"));
            if (!(tip < radius))
              fail(join_path(at, "tip_radius"), "must be less than the radius " + text(radius));
            included = morph::cone_angle(radius, height, tip);
          }
          const double length = find(v, "length") ? number_of("length") : height;
          tool = morph::conical_tool(radius, included, length, tip);
          break;
        }
        case morph::ToolType::Tapered:
        case morph::ToolType::TaperedBall: {
          check_keys(v, at,
                     {"type", "tip_diameter", "tip_radius", "diameter", "radius", "angle", "length",
                      "length_offset", "description"});
          const double tip = radius_or_diameter(v, at, "tip_diameter", "tip_radius", true);
          const double length = number_of("length");
          const double top = radius_or_diameter(v, at, "diameter", "radius", false);
          const json* angle = find(v, "angle");
          if (angle && !std::isnan(top))
            fail(at, "give 'angle' (taper per side) or 'diameter' at the top, not both");
          if (!angle && std::isnan(top)) fail(at, "missing required key 'angle' (or 'diameter' at the top)");
          if (type == morph::ToolType::Tapered) {
            double radius = top;
            if (angle) {
              const double a = number(*angle, join_path(at, "angle"));
              if (!(a > 0 && a < 90))
                fail(join_path(at, "angle"),
                     "must be a taper per side between 0 and 90 degrees (exclusive), got " + text(a));
              radius = tip + length * std::tan(a * M_PI / 180.0);
            }
            tool = morph::tapered_tool(tip, radius, length);
          } else {
            if (!std::isnan(top) && !(top > tip))
              fail(join_path(at, by_diameter ? "diameter" : "radius"), "must exceed the tip's");
            const double a =
                angle ? number(*angle, join_path(at, "angle")) : morph::tapered_ball_angle(tip, top, length);
            tool = morph::tapered_ball_tool(tip, a, length);
          }
          break;
        }
        case morph::ToolType::Spheroid:
          check_keys(v, at, {"type", "diameter", "radius", "length", "length_offset", "description"});
          tool = morph::spheroid_tool(radius_or_diameter(v, at, "diameter", "radius", true),
                                      number_of("length"));
          break;
        case morph::ToolType::Apt:
          check_keys(v, at,
                     {"type", "diameter", "corner_radius", "e", "f", "alpha", "beta", "height",
                      "length_offset", "description"});
          tool = morph::apt_tool(number_of("diameter"), number_of("corner_radius"), number_of("alpha"),
                                 number_of("beta"), number_of("height"), optional_number("e"),
                                 optional_number("f"));
          break;
      }
    } catch (const morph::ToolError& e) {
      // The constructors speak in radii; a tool given by diameters hears about its diameter.
      std::string field = e.field(), problem = e.problem();
      if (field == "radius" && by_diameter) field = "diameter", problem += " (as a radius)";
      if (field == "tip_radius" && find(v, "tip_diameter"))
        field = "tip_diameter", problem += " (as a radius)";
      fail(join_path(at, field), problem);
    }
    tool.number = tool_number;
    if (const json* offset = find(v, "length_offset"))
      tool.length_offset = number(*offset, join_path(at, "length_offset"));
    if (const json* d = find(v, "description")) tool.description = string(*d, join_path(at, "description"));
    return tool;
  }

  /// A LinuxCNC tool table (`file`, in `units`, default the job's) whose tools take their shape
  /// from `shape` (every tool) or `shapes` (per tool number): a type name or an object with the
  /// tool keys but the diameter, which the table gives. Z becomes the tool's length offset.
  void tool_table(const json& v, const std::string& at, morph::Units job_units,
                  std::map<int, morph::Tool>& tools) const {
    object(v, at);
    check_keys(v, at, {"file", "units", "shape", "shapes", "description"});
    const std::string file = referenced_file(require(v, at, "file"), join_path(at, "file"), "tool table");
    double scale = 1.0;
    if (const json* u = find(v, "units")) {
      const std::string name = string(*u, join_path(at, "units"));
      if (name != "mm" && name != "inch")
        fail(join_path(at, "units"), "expected \"mm\" or \"inch\", got \"" + name + "\"");
      scale = morph::millimetres_per_unit(name == "inch" ? morph::Units::Inch : morph::Units::Millimetre) /
              morph::millimetres_per_unit(job_units);
    }
    std::map<int, ToolTableRow> rows;
    try {
      rows = read_tool_table(file);
    } catch (const morph::InputError& e) {
      fail(join_path(at, "file"), e.what());
    } catch (const morph::IoError& e) {
      fail(join_path(at, "file"), e.what());
    }
    const json* shape = find(v, "shape");
    const json* shapes = find(v, "shapes");
    if (shapes) {
      object(*shapes, join_path(at, "shapes"));
      for (auto it = shapes->begin(); it != shapes->end(); ++it) {
        const int number = tool_number(json(it.key()), join_path(join_path(at, "shapes"), it.key()));
        if (!rows.count(number))
          fail(join_path(join_path(at, "shapes"), it.key()),
               "tool " + std::to_string(number) + " is not in the tool table '" + file + "'" + listed(rows));
      }
    }
    for (const auto& [number, row] : rows) {
      const std::string row_at = file + ":" + std::to_string(row.line) + " (T" + std::to_string(number) + ")";
      if (tools.count(number))
        fail(join_path(at, "file"),
             row_at + ": tool " + std::to_string(number) + " is also defined in 'tools'");
      const json* given = shapes ? find(*shapes, std::to_string(number).c_str()) : nullptr;
      const std::string shape_at =
          given ? join_path(join_path(at, "shapes"), std::to_string(number)) : join_path(at, "shape");
      if (!given) given = shape;
      if (!given)
        fail(at, row_at +
                     " has no shape: give 'shape' (every tool) or 'shapes' (by tool number); a LinuxCNC "
                     "tool table holds diameters and offsets, not shapes");
      json spec = given->is_string() ? json{{"type", given->get<std::string>()}} : object(*given, shape_at);
      if (spec.contains("diameter") || spec.contains("radius"))
        fail(shape_at, "the tool table gives the diameter; leave 'diameter' and 'radius' out here");
      if (!(row.diameter > 0.0))
        fail(join_path(at, "file"), row_at + ": D must be greater than 0 for a cutting tool");
      const bool apt = spec.value("type", "") == "apt";
      spec[apt ? "diameter" : "radius"] = apt ? scale * row.diameter : 0.5 * scale * row.diameter;
      morph::Tool tool = this->tool(spec, shape_at + " for " + row_at, number);
      tool.length_offset = scale * row.z_offset;
      if (tool.description.empty()) tool.description = row.comment;
      tools[number] = tool;
      warn(at, "T" + std::to_string(number) + " from " + fs::path(file).filename().string() + ": diameter " +
                   text(scale * row.diameter) + ", length offset " + text(tool.length_offset) +
                   ", shape from the job: " + morph::describe(tool));
    }
  }

  /// The controller's set-up a G-code path runs with: its tool table (the job's tools), work
  /// offsets, LinuxCNC var file, whether T alone changes the tool, the block-delete switch.
  void gcode_machine_setup(const json& v, const std::string& at, const std::map<int, morph::Tool>& tools,
                           morph::GcodeOptions& options) const {
    for (const auto& [number, tool] : tools) {
      morph::GcodeTool entry;
      entry.diameter = 2.0 * tool.radius;
      entry.length_offset = tool.length_offset;  // what G43 H<number> applies
      options.tools[number] = entry;
    }
    if (const json* f = find(v, "var_file"))
      options.var_file = referenced_file(*f, join_path(at, "var_file"), "LinuxCNC var");
    if (const json* w = find(v, "work_offsets")) {
      const std::string wat = join_path(at, "work_offsets");
      object(*w, wat);
      static const char* kSystems[] = {"G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"};
      for (auto it = w->begin(); it != w->end(); ++it) {
        const auto system = std::find(std::begin(kSystems), std::end(kSystems), it.key());
        if (system == std::end(kSystems))
          fail(join_path(wat, it.key()), "expected one of G54, G55, G56, G57, G58, G59, G59.1, G59.2, G59.3");
        options.work_offsets[int(system - std::begin(kSystems)) + 1] =
            point(it.value(), join_path(wat, it.key()));
      }
    }
    if (const json* t = find(v, "tool_change_on_t")) {
      if (!t->is_boolean())
        fail(join_path(at, "tool_change_on_t"), "expected true or false, got " + describe_value(*t));
      options.tool_change_on_t = t->get<bool>();
    }
    if (const json* b = find(v, "block_delete")) {
      if (!b->is_boolean())
        fail(join_path(at, "block_delete"), "expected true or false, got " + describe_value(*b));
      options.block_delete = b->get<bool>();
    }
  }

  morph::Path path(const json& v, std::size_t index, const std::map<int, morph::Tool>& tools,
                   morph::Units units) const {
    const std::string at = index_path("paths", index);
    object(v, at);
    check_keys(v, at,
               {"tool", "polyline", "gcode", "name", "description", "feed", "start", "var_file",
                "work_offsets", "tool_change_on_t", "block_delete"});
    morph::Path path;
    if (const json* name = find(v, "name")) path.name = string(*name, join_path(at, "name"));
    if (const json* d = find(v, "description")) string(*d, join_path(at, "description"));

    int tool = 0;
    if (const json* t = find(v, "tool")) {
      tool = tool_number(*t, join_path(at, "tool"));
    } else if (tools.size() == 1) {
      tool = tools.begin()->first;  // one tool: it is the tool of every path
    } else {
      fail(at, "missing required key 'tool' (it may be left out only when the job defines exactly one tool)");
    }
    if (!tools.count(tool))
      fail(join_path(at, "tool"),
           "tool " + std::to_string(tool) + " is not defined in 'tools'" + defined_tools(tools));

    const json* polyline = find(v, "polyline");
    const json* gcode = find(v, "gcode");
    if (polyline && gcode) fail(at, "has both 'polyline' and 'gcode'; a path is one or the other");
    if (!polyline && !gcode) fail(at, "needs a 'polyline' or a 'gcode' key");

    if (polyline) {
      const std::string pat = join_path(at, "polyline");
      for (const char* key : {"start", "var_file", "work_offsets", "tool_change_on_t", "block_delete"})
        if (find(v, key)) warn(join_path(at, key), "only used with 'gcode', ignored");
      double feed = 0.0;
      if (const json* f = find(v, "feed")) feed = positive(*f, join_path(at, "feed"));
      if (!polyline->is_array()) fail(pat, "expected an array of points, got " + describe_value(*polyline));
      if (polyline->empty()) fail(pat, "is empty; a polyline needs at least 2 points");
      if (polyline->size() < 2) fail(pat, "has 1 point; a polyline needs at least 2 points");
      path.source = pat;
      Eigen::Vector3d previous = point((*polyline)[0], index_path(pat, 0));
      for (std::size_t i = 1; i < polyline->size(); ++i) {
        const Eigen::Vector3d p = point((*polyline)[i], index_path(pat, i));
        if (p == previous) {
          warn(index_path(pat, i), "repeats the previous point; no move");
          continue;
        }
        morph::Move move;
        move.kind = morph::MoveKind::Linear;
        move.start = previous;
        move.end = p;
        move.tool = tool;
        move.line = int(i + 1);
        move.feed = feed;
        path.moves.push_back(move);
        previous = p;
      }
    } else {
      const std::string gat = join_path(at, "gcode");
      if (find(v, "feed"))
        warn(join_path(at, "feed"), "only used with 'polyline' (G-code has its own F words), ignored");
      const std::string file = referenced_file(*gcode, gat, "G-code");
      morph::GcodeOptions options;
      options.job_units = units;
      options.initial_tool = tool;
      if (const json* s = find(v, "start")) options.start = point(*s, join_path(at, "start"));
      gcode_machine_setup(v, at, tools, options);
      morph::GcodeResult result;
      try {
        result = morph::read_gcode(file, options);
      } catch (const morph::InputError& e) {
        fail(gat, e.what());
      } catch (const morph::IoError& e) {
        fail(gat, e.what());
      }
      for (int used : result.tools_used)
        if (!tools.count(used))
          fail(gat, "'" + gcode->get<std::string>() + "' selects tool " + std::to_string(used) + " (T" +
                        std::to_string(used) + " M6), which is not defined in 'tools'" +
                        defined_tools(tools));
      for (const morph::Move& m : result.path.moves)
        if (!tools.count(m.tool))
          fail(gat, "'" + gcode->get<std::string>() + "' line " + std::to_string(m.line) +
                        " moves with tool " + std::to_string(m.tool) + ", which is not defined in 'tools'" +
                        defined_tools(tools));
      warnings_.insert(warnings_.end(), result.warnings.begin(), result.warnings.end());
      path.source = result.path.source.empty() ? file : result.path.source;
      path.moves = std::move(result.path.moves);
      if (path.moves.empty()) warn(gat, "'" + gcode->get<std::string>() + "' has no moves");
    }
    return path;
  }

 private:
  static std::string listed(const std::map<int, ToolTableRow>& rows) {
    std::string list;
    for (const auto& [number, row] : rows) list += (list.empty() ? "" : ", ") + std::to_string(number);
    return " (listed: " + list + ")";
  }

  static std::string defined_tools(const std::map<int, morph::Tool>& tools) {
    if (tools.empty()) return " (no tools are defined)";
    std::string list;
    for (const auto& [number, tool] : tools) list += (list.empty() ? "" : ", ") + std::to_string(number);
    return " (defined: " + list + ")";
  }

  std::string file_;
  fs::path base_dir_;
  std::vector<morph::Warning>& warnings_;
};

json vector_json(const Eigen::Vector3d& v) {
  return json::array({v.x(), v.y(), v.z()});
}

json tool_json(const morph::Tool& t) {
  json tool{{"number", t.number},
            {"type", morph::to_string(t.type)},
            {"radius", t.radius},
            {"diameter", 2.0 * t.radius},
            {"shape", morph::describe(t)}};
  if (t.type != morph::ToolType::Sphere) tool["length"] = t.length;
  if (t.type == morph::ToolType::Bullnose || t.type == morph::ToolType::Apt)
    tool["corner_radius"] = t.corner_radius;
  if (t.type == morph::ToolType::Conical || t.type == morph::ToolType::Tapered ||
      t.type == morph::ToolType::TaperedBall)
    tool["angle"] = t.angle;
  if (t.type == morph::ToolType::Conical || t.type == morph::ToolType::Tapered ||
      t.type == morph::ToolType::TaperedBall)
    tool["tip_radius"] = t.tip_radius;
  if (t.type == morph::ToolType::Apt) {
    tool["e"] = t.apt_e;
    tool["f"] = t.apt_f;
    tool["alpha"] = t.apt_alpha;
    tool["beta"] = t.apt_beta;
  }
  if (t.length_offset != 0.0) tool["length_offset"] = t.length_offset;
  if (!t.description.empty()) tool["description"] = t.description;
  if (!t.profile.empty()) tool["profile"] = t.profile.describe();
  return tool;
}

json box_json(const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return nullptr;
  return {{"min", vector_json(box.min())}, {"max", vector_json(box.max())}};
}

}  // namespace

morph::Job parse_job(const nlohmann::json& root, const std::string& file) {
  morph::Job job;
  job.file = file;
  JobParser parser(file, job.warnings);
  parser.object(root, "");
  if (!root.is_object()) parser.fail("", "a job file must hold one JSON object");
  parser.check_keys(
      root, "",
      {"name", "description", "units", "stock", "tools", "tool_table", "paths", "tolerance", "design"});
  if (const json* design = parser.find(root, "design")) parser.design(*design, "design");

  job.name = fs::path(file).stem().string();
  if (const json* name = parser.find(root, "name")) job.name = parser.string(*name, "name");
  if (const json* d = parser.find(root, "description")) job.description = parser.string(*d, "description");

  if (const json* units = parser.find(root, "units")) {
    const std::string u = parser.string(*units, "units");
    if (u == "mm")
      job.units = morph::Units::Millimetre;
    else if (u == "inch")
      job.units = morph::Units::Inch;
    else
      parser.fail("units", "expected \"mm\" or \"inch\", got \"" + u + "\"");
  }

  job.tolerance = kDefaultToleranceMillimetres / morph::millimetres_per_unit(job.units);
  if (const json* t = parser.find(root, "tolerance")) job.tolerance = parser.positive(*t, "tolerance");

  job.stock = parser.stock(parser.require(root, "", "stock"), "stock");

  const json* table = parser.find(root, "tool_table");
  const json* tools = table ? parser.find(root, "tools") : &parser.require(root, "", "tools");
  if (tools) {
    parser.object(*tools, "tools");
    if (tools->empty() && !table) parser.fail("tools", "defines no tools; a job needs at least one");
    for (auto it = tools->begin(); it != tools->end(); ++it) {
      const std::string at = "tools." + it.key();
      const int number = parser.tool_number(json(it.key()), at);
      if (job.tools.count(number)) parser.fail(at, "tool " + std::to_string(number) + " is defined twice");
      job.tools[number] = parser.tool(it.value(), at, number);
    }
  }
  if (table) parser.tool_table(*table, "tool_table", job.units, job.tools);

  const json& paths = parser.require(root, "", "paths");
  if (!paths.is_array()) parser.fail("paths", "expected an array of paths, got " + describe_value(paths));
  if (paths.empty()) parser.fail("paths", "is empty; a job needs at least one path");
  for (std::size_t i = 0; i < paths.size(); ++i)
    job.paths.push_back(parser.path(paths[i], i, job.tools, job.units));
  return job;
}

DesignSpec parse_design(const nlohmann::json& root, const std::string& file) {
  std::vector<morph::Warning> warnings;
  JobParser parser(file, warnings);
  if (!root.is_object()) parser.fail("", "a job file must hold one JSON object");
  const json* design = parser.find(root, "design");
  return design ? parser.design(*design, "design") : DesignSpec{};
}

DesignSpec load_design(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw morph::IoError("cannot open job file '" + path + "': " + std::strerror(errno));
  json root;
  try {
    root = json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(path + ": not valid JSON: " + e.what());
  }
  return parse_design(root, path);
}

morph::Job load_job(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".camotics") return load_camotics_project(path);
  if (extension == ".tpl")
    throw InputError(path +
                     ": a CAMotics TPL program (JavaScript that generates G-code) is not a job; run it "
                     "through CAMotics' 'tplang' and give MorphMill the G-code it writes");
  return parse_job_text(morph::read_regular_file(path, "job file", kMaxJobFileBytes), path);
}

morph::Job parse_job_text(const std::string& text, const std::string& path) {
  return parse_job(parse_json_text(text, path), path);
}

nlohmann::json parse_json_text(const std::string& text, const std::string& path) {
  JsonPathTracker where;
  json root;
  try {
    root = json::parse(text, [&](int, json::parse_event_t event, json& parsed) {
      where.on(event, parsed, path);
      return true;
    });
  } catch (const json::parse_error& e) {
    // Report the position as line and column: nlohmann gives the byte just past the problem.
    const std::size_t byte = std::min<std::size_t>(e.byte == 0 ? 0 : e.byte - 1, text.size());
    const std::size_t line = 1 + std::size_t(std::count(text.begin(), text.begin() + byte, '\n'));
    const std::size_t line_start = text.rfind('\n', byte == 0 ? 0 : byte - 1);
    const std::size_t column = byte - (line_start == std::string::npos ? 0 : line_start + 1) + 1;
    std::string what = e.what();
    const std::size_t colon = what.find("parse error");
    if (colon != std::string::npos) what = what.substr(colon);
    throw InputError(path + ":" + std::to_string(line) + ":" + std::to_string(column) + ": invalid JSON (" +
                     what + ")");
  } catch (const json::exception& e) {
    // A number too large for a double (1e400) and the like: named with the value's JSON path.
    std::string what = e.what();
    const std::size_t bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    throw InputError(path + ": " + where.path() + ": invalid JSON (" + what + ")");
  }
  return root;
}

nlohmann::json describe_job(const morph::Job& job) {
  json out;
  out["name"] = job.name;
  if (!job.description.empty()) out["description"] = job.description;
  out["file"] = job.file;
  out["units"] = morph::to_string(job.units);
  out["tolerance"] = job.tolerance;

  const morph::Stock& s = job.stock;
  json stock{{"type", morph::to_string(s.type)}};
  switch (s.type) {
    case morph::StockType::Box:
      stock["min"] = vector_json(s.box.min());
      stock["max"] = vector_json(s.box.max());
      break;
    case morph::StockType::Cylinder:
      stock["base"] = vector_json(s.base);
      stock["axis"] = vector_json(s.axis);
      stock["radius"] = s.radius;
      stock["height"] = s.height;
      break;
    case morph::StockType::Mesh:
      stock["path"] = s.mesh_path;
      stock["vertices"] = s.mesh.vertices.size();
      stock["triangles"] = s.mesh.triangles.size();
      break;
  }
  stock["bounds"] = box_json(morph::bounds(s));
  stock["volume"] = morph::volume(s);
  out["stock"] = stock;

  json tools = json::array();
  for (const auto& [number, t] : job.tools) tools.push_back(tool_json(t));
  out["tools"] = tools;

  // Moves by kind, lengths and the bounding box of the tool point along the path (arcs sampled
  // with chords within the job tolerance, so the box is exact to that tolerance).
  std::map<std::string, std::size_t> total_by_kind{{"rapid", 0}, {"linear", 0}, {"arc", 0}};
  std::map<std::string, double> length_by_kind{{"rapid", 0.0}, {"linear", 0.0}, {"arc", 0.0}};
  Eigen::AlignedBox3d all_bounds;
  json paths = json::array();
  for (std::size_t i = 0; i < job.paths.size(); ++i) {
    const morph::Path& path = job.paths[i];
    std::map<std::string, std::size_t> by_kind{{"rapid", 0}, {"linear", 0}, {"arc", 0}};
    std::set<int> tools_used;
    double path_length = 0.0;
    Eigen::AlignedBox3d path_bounds;
    for (const morph::Move& m : path.moves) {
      const std::string kind = morph::to_string(m.kind);
      ++by_kind[kind];
      ++total_by_kind[kind];
      const double l = morph::length(m);
      path_length += l;
      length_by_kind[kind] += l;
      tools_used.insert(m.tool);
      path_bounds.extend(m.start);
      path_bounds.extend(m.end);
      if (m.is_arc()) {
        // Chords within the job tolerance, but no finer than a millionth of the radius: the box
        // is then exact to that, and a many-turn arc at a tiny tolerance stays a few million points.
        const double radius = std::max((m.start - m.center).norm(), (m.end - m.center).norm());
        const double chord = std::max(job.tolerance, 1e-6 * radius);
        try {
          for (double t : morph::chord_parameters(m, chord)) path_bounds.extend(morph::point_at(m, t));
        } catch (const morph::LimitError& e) {
          throw morph::LimitError(job.file + ": " + path.source + ": " + e.what());
        }
      }
    }
    all_bounds.extend(path_bounds);
    json p{{"index", i},
           {"source", path.source},
           {"moves", path.moves.size()},
           {"moves_by_kind", by_kind},
           {"length", path_length},
           {"tools", tools_used},
           {"bounds", box_json(path_bounds)}};
    if (!path.name.empty()) p["name"] = path.name;
    paths.push_back(p);
  }
  out["paths"] = paths;
  out["moves"] = {{"total", job.move_count()}, {"by_kind", total_by_kind}};
  double total_length = 0.0;
  for (const auto& [kind, l] : length_by_kind) total_length += l;
  out["path_length"] = {{"total", total_length}, {"by_kind", length_by_kind}};
  out["bounds"] = box_json(all_bounds);
  json warnings = json::array();
  for (const morph::Warning& w : job.warnings)
    warnings.push_back({{"file", w.file}, {"line", w.line}, {"message", w.message}});
  out["warnings"] = warnings;
  return out;
}

}  // namespace morphmill
