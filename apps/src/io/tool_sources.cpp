// SPDX-License-Identifier: Apache-2.0
// CAMotics projects and LinuxCNC tool tables (docs/camotics.md, docs/job-format.md). CAMotics'
// tool geometry (its ToolSweep) and automatic workpiece (its Workpiece::update) are matched as
// they are described in ../shared/camotics/README.md and CAMotics' documentation.
#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/gcode.h>
#include <morph/sweep_distance.h>
#include <morphmill/tool_sources.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

namespace morphmill {

namespace {

namespace fs = std::filesystem;
using morph::InputError;
using nlohmann::json;

/// CAMotics keeps workpiece bounds in millimetres whatever the project's display units.
constexpr double kCamoticsMinimumThicknessMillimetres = 2.0;

class ProjectReader {
 public:
  ProjectReader(std::string file, std::vector<morph::Warning>& warnings)
      : file_(std::move(file)), warnings_(warnings) {}

  [[noreturn]] void fail(const std::string& at, const std::string& what) const {
    throw InputError(file_ + ": " + (at.empty() ? "" : at + ": ") + what);
  }
  void warn(const std::string& at, const std::string& what) const {
    warnings_.push_back({file_, 0, (at.empty() ? "" : at + ": ") + what});
  }
  void check_keys(const json& object, const std::string& at, std::initializer_list<const char*> known) const {
    for (auto it = object.begin(); it != object.end(); ++it)
      if (std::none_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; }))
        warn(at.empty() ? it.key() : at + "." + it.key(), "unknown key, ignored");
  }
  const json& object(const json& v, const std::string& at) const {
    if (!v.is_object()) fail(at, "expected an object, got " + std::string(v.type_name()));
    return v;
  }
  const json& require(const json& v, const std::string& at, const char* key) const {
    auto it = v.find(key);
    if (it == v.end()) fail(at, std::string("missing required key '") + key + "'");
    return *it;
  }
  double number(const json& v, const std::string& at) const {
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      fail(at, "expected a finite number, got " + std::string(v.type_name()) + " " + v.dump());
    return v.get<double>();
  }
  std::string string(const json& v, const std::string& at) const {
    if (!v.is_string()) fail(at, "expected a string, got " + std::string(v.type_name()) + " " + v.dump());
    return v.get<std::string>();
  }
  /// "metric" -> mm, "imperial" -> inch (CAMotics' names).
  morph::Units units(const json& object, const std::string& at) const {
    auto it = object.find("units");
    if (it == object.end()) return morph::Units::Millimetre;
    const std::string u = string(*it, at + (at.empty() ? "" : ".") + "units");
    if (u == "metric") return morph::Units::Millimetre;
    if (u == "imperial") return morph::Units::Inch;
    fail(at + (at.empty() ? "" : ".") + "units", "expected \"metric\" or \"imperial\", got \"" + u + "\"");
  }
  Eigen::Vector3d point(const json& v, const std::string& at) const {
    if (!v.is_array() || v.size() != 3) fail(at, "expected 3 numbers, got " + v.dump());
    return Eigen::Vector3d(number(v[0], at + "[0]"), number(v[1], at + "[1]"), number(v[2], at + "[2]"));
  }

  /// One CAMotics tool, its sizes converted from its own units into the job's.
  morph::Tool tool(const json& v, const std::string& at, int number_in_table, morph::Units job_units) const {
    object(v, at);
    check_keys(v, at, {"units", "shape", "length", "diameter", "snub_diameter", "description", "number"});
    const double scale = morph::millimetres_per_unit(units(v, at)) / morph::millimetres_per_unit(job_units);
    const std::string shape = string(require(v, at, "shape"), at + ".shape");
    auto size = [&](const char* key) { return scale * number(require(v, at, key), at + "." + key); };
    morph::Tool tool;
    try {
      const double radius = 0.5 * size("diameter"), length = size("length");
      if (shape == "cylindrical") {
        tool = morph::flat_tool(radius, length);
      } else if (shape == "ballnose") {
        // A ball whose lowest point is the tip plus a cylinder from its centre up to R + L.
        tool = morph::ball_tool(radius, length);
      } else if (shape == "conical") {
        // Radius 0 at the tip growing linearly to R at L; nothing above.
        if (!(radius > 0.0 && length > 0.0))
          throw morph::ToolError(radius > 0.0 ? "length" : "radius", "must be greater than 0");
        tool = morph::conical_tool(radius, morph::cone_angle(radius, length), length);
      } else if (shape == "snubnose") {
        tool = morph::tapered_tool(0.5 * size("snub_diameter"), radius, length);
      } else if (shape == "spheroid") {
        tool = morph::spheroid_tool(radius, length);
      } else {
        fail(at + ".shape", "unknown CAMotics tool shape '" + shape +
                                "' (expected cylindrical, ballnose, conical, snubnose or spheroid)");
      }
    } catch (const morph::ToolError& e) {
      std::string field = e.field();
      if (field == "radius") field = "diameter";
      if (field == "tip_radius") field = "snub_diameter";
      if (field == "angle") field = "length";
      fail(at + "." + field, e.problem() + (scale != 1.0 || field.find("diameter") != std::string::npos
                                                ? " (after conversion to the job's units and radii)"
                                                : ""));
    }
    tool.number = number_in_table;
    if (auto d = v.find("description"); d != v.end() && d->is_string())
      tool.description = d->get<std::string>();
    return tool;
  }

 private:
  std::string file_;
  std::vector<morph::Warning>& warnings_;
};

// CAMotics' automatic workpiece: the union of the tool's bounds over every cutting (non-rapid)
// move, its top set to z = 0, at least 2 mm thick, grown by margin percent of its size on every
// side but the top.
Eigen::AlignedBox3d automatic_workpiece(const morph::Job& job, double margin_percent) {
  Eigen::AlignedBox3d bounds;
  for (const morph::Move* move : job.moves()) {
    if (move->kind == morph::MoveKind::Rapid) continue;
    const morph::Tool& tool = job.tool_of(*move);
    const morph::ToolExtent e = morph::tool_extent(tool);
    std::vector<double> ts{0.0, 1.0};
    if (move->is_arc()) ts = morph::chord_parameters(*move, 1e-6 * std::max(1.0, tool.radius));
    for (double t : ts) {
      const Eigen::Vector3d p = morph::point_at(*move, t);
      bounds.extend(p + Eigen::Vector3d(e.radius, e.radius, e.above));
      bounds.extend(p - Eigen::Vector3d(e.radius, e.radius, e.below));
    }
  }
  if (bounds.isEmpty()) return bounds;
  Eigen::Vector3d lo = bounds.min(), hi = bounds.max();
  hi.z() = 0.0;
  const double minimum = kCamoticsMinimumThicknessMillimetres / morph::millimetres_per_unit(job.units);
  if (hi.z() - lo.z() < minimum) lo.z() = std::min(lo.z(), bounds.min().z() - minimum);
  const Eigen::Vector3d margin = (hi - lo) * margin_percent / 100.0;
  lo -= margin;
  hi += Eigen::Vector3d(margin.x(), margin.y(), 0.0);
  return Eigen::AlignedBox3d(lo, hi);
}

}  // namespace

morph::Job parse_camotics_project(const json& project, const std::string& file) {
  morph::Job job;
  job.file = file;
  ProjectReader reader(file, job.warnings);
  reader.object(project, "");
  reader.check_keys(project, "", {"units", "resolution-mode", "resolution", "tools", "workpiece", "files"});
  job.name = fs::path(file).stem().string();
  job.units = reader.units(project, "");
  job.tolerance = 0.01 / morph::millimetres_per_unit(job.units);
  job.description = "CAMotics project " + fs::path(file).filename().string();

  const json& tools = reader.object(reader.require(project, "", "tools"), "tools");
  if (tools.empty()) reader.fail("tools", "defines no tools; a project needs at least one");
  for (auto it = tools.begin(); it != tools.end(); ++it) {
    const std::string at = "tools." + it.key();
    const std::string& key = it.key();
    if (key.empty() || key.size() > 9 ||
        !std::all_of(key.begin(), key.end(), [](char c) { return c >= '0' && c <= '9'; }))
      reader.fail(at, "expected a tool number (an integer >= 0) as the key");
    const int number = std::stoi(key);
    job.tools[number] = reader.tool(it.value(), at, number, job.units);
  }

  const fs::path base = fs::path(file).parent_path().empty() ? fs::path(".") : fs::path(file).parent_path();
  const json& files = reader.require(project, "", "files");
  if (!files.is_array() || files.empty()) reader.fail("files", "expected a non-empty array of G-code files");
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::string at = "files[" + std::to_string(i) + "]";
    const std::string name = reader.string(files[i], at);
    std::string extension = fs::path(name).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (extension == ".tpl")
      reader.fail(
          at,
          "'" + name +
              "' is a CAMotics TPL program (JavaScript that generates G-code); MorphMill reads G-code only: "
              "run it through CAMotics' 'tplang' and list the G-code it writes");
    const fs::path resolved = fs::path(name).is_absolute() ? fs::path(name) : base / name;
    std::error_code ec;
    if (!fs::is_regular_file(resolved, ec))
      reader.fail(at, "G-code file '" + name + "' not found (looked for '" + resolved.string() + "')");
    morph::GcodeOptions options;
    options.job_units = job.units;
    options.initial_tool = job.tools.begin()->first;
    // Every program starts with the tool the previous one left in the spindle.
    if (!job.paths.empty() && !job.paths.back().moves.empty())
      options.initial_tool = job.paths.back().moves.back().tool;
    morph::GcodeResult result;
    try {
      result = morph::read_gcode(resolved.lexically_normal().string(), options);
    } catch (const InputError& e) {
      reader.fail(at, e.what());
    } catch (const morph::IoError& e) {
      reader.fail(at, e.what());
    }
    for (const morph::Move& m : result.path.moves)
      if (!job.tools.count(m.tool))
        reader.fail(at, "'" + name + "' line " + std::to_string(m.line) + " moves with tool " +
                            std::to_string(m.tool) + ", which the project's tool table does not define");
    job.warnings.insert(job.warnings.end(), result.warnings.begin(), result.warnings.end());
    morph::Path path;
    path.source = result.path.source.empty() ? resolved.lexically_normal().string() : result.path.source;
    path.name = name;
    path.moves = std::move(result.path.moves);
    if (path.moves.empty()) reader.warn(at, "'" + name + "' has no moves");
    job.paths.push_back(std::move(path));
  }

  const json& workpiece = reader.object(reader.require(project, "", "workpiece"), "workpiece");
  reader.check_keys(workpiece, "workpiece", {"automatic", "margin", "bounds"});
  bool automatic = false;
  if (auto a = workpiece.find("automatic"); a != workpiece.end()) {
    if (!a->is_boolean()) reader.fail("workpiece.automatic", "expected true or false");
    automatic = a->get<bool>();
  }
  const double to_job = 1.0 / morph::millimetres_per_unit(job.units);
  Eigen::AlignedBox3d box;
  if (automatic) {
    double margin = 5.0;
    if (auto m = workpiece.find("margin"); m != workpiece.end())
      margin = reader.number(*m, "workpiece.margin");
    if (!(margin >= 0.0)) reader.fail("workpiece.margin", "must not be negative (a percentage of the size)");
    box = automatic_workpiece(job, margin);
    if (box.isEmpty())
      reader.fail("workpiece.automatic", "the programs have no cutting moves to size the workpiece by");
  } else {
    const json& bounds = reader.object(reader.require(workpiece, "workpiece", "bounds"), "workpiece.bounds");
    const Eigen::Vector3d lo =
        to_job * reader.point(reader.require(bounds, "workpiece.bounds", "min"), "workpiece.bounds.min");
    const Eigen::Vector3d hi =
        to_job * reader.point(reader.require(bounds, "workpiece.bounds", "max"), "workpiece.bounds.max");
    for (int k = 0; k < 3; ++k)
      if (!(lo[k] < hi[k]))
        reader.fail("workpiece.bounds.max",
                    std::string("must exceed min in every axis, but ") + "xyz"[k] + " does not");
    box = Eigen::AlignedBox3d(lo, hi);
  }
  job.stock.type = morph::StockType::Box;
  job.stock.box = box;
  return job;
}

morph::Job load_camotics_project(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw morph::IoError("cannot open CAMotics project '" + path + "': " + std::strerror(errno));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    throw InputError(path + ": invalid JSON in the CAMotics project (" + std::string(e.what()) +
                     "); only JSON projects (.camotics) are read, not CAMotics' older XML ones");
  }
  return parse_camotics_project(root, path);
}

std::map<int, ToolTableRow> read_tool_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw morph::IoError("cannot open tool table '" + path + "': " + std::strerror(errno));
  std::map<int, ToolTableRow> rows;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    auto fail = [&](const std::string& what) {
      throw InputError(path + ":" + std::to_string(line) + ": " + what);
    };
    ToolTableRow row;
    row.line = line;
    const std::size_t semicolon = text.find(';');
    if (semicolon != std::string::npos) {
      row.comment = text.substr(semicolon + 1);
      row.comment.erase(0, row.comment.find_first_not_of(" \t"));
      row.comment.erase(row.comment.find_last_not_of(" \t\r") + 1);
      text.erase(semicolon);
    }
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;  // blank, or a comment only
    std::istringstream words(text);
    std::string word;
    bool has_t = false, has_d = false;
    while (words >> word) {
      const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(word[0])));
      if (std::string("TPDXYZABCUVWIJQ").find(letter) == std::string::npos)
        fail("unknown word '" + word +
             "' (a tool table line holds T, P, D, X Y Z A B C U V W, I J Q and a ;comment)");
      const std::string digits = word.substr(1);
      char* end = nullptr;
      errno = 0;
      const double value = std::strtod(digits.c_str(), &end);
      if (digits.empty() || end != digits.c_str() + digits.size() || errno == ERANGE || !std::isfinite(value))
        fail("'" + word + "': the letter " + std::string(1, letter) + " needs a number");
      if (letter == 'T') {
        if (value < 0 || value != std::floor(value) || value > 2147483647.0)
          fail("T" + digits + ": a tool number must be an integer >= 0");
        row.number = static_cast<int>(value);
        has_t = true;
      } else if (letter == 'D') {
        if (!(value >= 0.0)) fail("D" + digits + ": the diameter must not be negative");
        row.diameter = value;
        has_d = true;
      } else if (letter == 'Z') {
        row.z_offset = value;
      }
    }
    if (!has_t) fail("no T word (each line of a tool table describes one tool: T1 P1 D6.0 Z+25 ;comment)");
    if (!has_d) fail("T" + std::to_string(row.number) + " has no D word (diameter)");
    if (rows.count(row.number))
      fail("T" + std::to_string(row.number) + " is listed twice (first at line " +
           std::to_string(rows.at(row.number).line) + ")");
    rows[row.number] = row;
  }
  if (rows.empty()) throw InputError(path + ": the tool table lists no tools");
  return rows;
}

}  // namespace morphmill
