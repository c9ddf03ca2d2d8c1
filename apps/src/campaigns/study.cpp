// SPDX-License-Identifier: Apache-2.0
#include "campaigns/study.h"

#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morph/parallel.h>
#include <morph/sweep_distance.h>
#include <morphmill/job_io.h>
#include <raytest/heatmap.h>
#include <raytest/render.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "cli/memory_cap.h"
#include "cli/stop_signals.h"
#include "verify/html.h"
#include "verify/verify.h"

namespace morphmill::study {

namespace fs = std::filesystem;

namespace {

/// A reader (or a kill) sees the old file or the new one, never a part.
void write_text(const fs::path& path, const std::string& text) {
  morph::write_file_atomically(path.string(), text);
}

// --- study file parsing ------------------------------------------------------------------------

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw morph::InputError(file_ + ": " + where + ": " + what);
  }
  void only_keys(const nlohmann::json& object, const std::string& where,
                 const std::set<std::string>& keys) const {
    if (!object.is_object()) fail(where, "expected an object");
    for (const auto& [key, value] : object.items())
      if (!keys.count(key)) fail(where.empty() ? key : where + "." + key, "unknown key");
  }
  double positive(const nlohmann::json& value, const std::string& where) const {
    if (!value.is_number() || !(value.get<double>() > 0) || !std::isfinite(value.get<double>()))
      fail(where, "expected a positive number");
    return value.get<double>();
  }
  double non_negative(const nlohmann::json& value, const std::string& where) const {
    if (!value.is_number() || !(value.get<double>() >= 0) || !std::isfinite(value.get<double>()))
      fail(where, "expected a number >= 0");
    return value.get<double>();
  }
  std::vector<double> positives(const nlohmann::json& value, const std::string& where) const {
    if (!value.is_array() || value.empty()) fail(where, "expected a non-empty array of positive numbers");
    std::vector<double> list;
    for (std::size_t i = 0; i < value.size(); ++i)
      list.push_back(positive(value[i], where + "[" + std::to_string(i) + "]"));
    return list;
  }
  Eigen::Vector3d point(const nlohmann::json& value, const std::string& where) const {
    if (!value.is_array() || value.size() != 3) fail(where, "expected 3 numbers");
    Eigen::Vector3d p;
    for (int i = 0; i < 3; ++i) {
      if (!value[i].is_number()) fail(where, "expected 3 numbers");
      p[i] = value[i].get<double>();
    }
    return p;
  }
  std::string text(const nlohmann::json& value, const std::string& where) const {
    if (!value.is_string()) fail(where, "expected a string");
    return value.get<std::string>();
  }

 private:
  std::string file_;
};

ZigzagSpec parse_zigzag(const Reader& reader, const nlohmann::json& j, const std::string& where) {
  reader.only_keys(j, where, {"name", "stock", "tool", "area", "depth", "step_over", "tolerance"});
  ZigzagSpec z;
  z.name = reader.text(j.value("name", nlohmann::json()), where + ".name");
  const auto& stock = j.value("stock", nlohmann::json());
  reader.only_keys(stock, where + ".stock", {"min", "max"});
  z.stock_min = reader.point(stock.value("min", nlohmann::json()), where + ".stock.min");
  z.stock_max = reader.point(stock.value("max", nlohmann::json()), where + ".stock.max");
  const auto& tool = j.value("tool", nlohmann::json());
  reader.only_keys(tool, where + ".tool", {"type", "radius", "length"});
  z.tool_type = reader.text(tool.value("type", nlohmann::json()), where + ".tool.type");
  z.tool_radius = reader.positive(tool.value("radius", nlohmann::json()), where + ".tool.radius");
  z.tool_length = tool.contains("length") ? reader.non_negative(tool["length"], where + ".tool.length") : 0.0;
  const auto& area = j.value("area", nlohmann::json());
  if (!area.is_array() || area.size() != 4 ||
      !std::all_of(area.begin(), area.end(), [](auto& v) { return v.is_number(); }))
    reader.fail(where + ".area", "expected [x0, y0, x1, y1]");
  z.x0 = area[0];
  z.y0 = area[1];
  z.x1 = area[2];
  z.y1 = area[3];
  z.depth = reader.positive(j.value("depth", nlohmann::json()), where + ".depth");
  z.step_over = reader.positive(j.value("step_over", nlohmann::json()), where + ".step_over");
  if (j.contains("tolerance")) z.tolerance = reader.positive(j["tolerance"], where + ".tolerance");
  return z;
}

// --- evaluation ----------------------------------------------------------------------------------

double smallest_radius(const morph::Job& job) {
  double radius = std::numeric_limits<double>::infinity();
  for (const auto& [number, tool] : job.tools) radius = std::min(radius, tool.radius);
  return std::isfinite(radius) ? radius : 1.0;
}

std::string slug(const std::string& text) {
  std::string out;
  for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' ? c : '_';
  return out;
}

std::string number(double value) {
  return fmt::format("{:.6g}", value);
}

/// What one setting evaluates to (shared by every sweep that hits the same setting).
struct SettingKey {
  std::size_t job = 0;
  double tolerance = 0, voxel = 0, radius_scale = 1, step_over = 0;
  bool operator<(const SettingKey& o) const {
    return std::tie(job, tolerance, voxel, radius_scale, step_over) <
           std::tie(o.job, o.tolerance, o.voxel, o.radius_scale, o.step_over);
  }
};

void render_heatmap(morph::TriangleMesh mesh, const std::vector<double>& values, const std::string& unit,
                    const StudySpec& spec, const fs::path& png) {
  const raytest::ScalarRange range = raytest::auto_range(values, true);
  raytest::apply_heatmap(mesh, "deviation_exact", values, raytest::ColorMap::CoolWarm, range);
  raytest::RenderOptions render;
  render.width = spec.image_width;
  render.height = spec.image_height;
  render.scalar = "deviation_exact";
  render.color_map = raytest::ColorMap::CoolWarm;
  render.range = range;
  render.unit = unit;
  raytest::write_png(raytest::render_mesh(mesh, render), png.string());
}

std::string tools_text(const morph::Job& job) {
  std::string text;
  for (const auto& [number, tool] : job.tools)
    text += (text.empty() ? "" : "; ") + fmt::format("T{} {}", number, morph::describe(tool));
  return text;
}

void evaluate_setting(const morph::Job& job, const SettingKey& key, const StudySpec& spec,
                      const fs::path& out_dir, const std::string& picture_stem, StudyRow& row) {
  EvaluateOptions options;
  options.voxel_size = key.voxel;
  options.tolerance = key.tolerance;
  options.face_samples = spec.face_samples;
  options.seed = spec.seed;
  options.per_stage_peak_memory = true;
  // A setting whose tolerance is far too fine is refused with its estimate, not killed by the kernel.
  options.generator_memory_cap_bytes = memory_cap_bytes(default_memory_cap_gib());
  const Evaluation evaluation = evaluate_job(job, options);
  const VerifyOutcome& o = evaluation.outcome;
  row.tolerance = o.tolerance;
  row.voxel_size = o.voxel_size;
  row.tool_radius = smallest_radius(job);
  row.tools = tools_text(job);
  for (const auto& stage : o.stages) {
    if (stage.name == "generator (morph)") {
      row.generator_seconds = stage.seconds;
      row.generator_peak_mib = stage.peak_rss_mib;
    } else if (stage.name == "reference (OpenVDB)") {
      row.reference_seconds = stage.seconds;
      row.reference_peak_mib = stage.peak_rss_mib;
    }
  }
  row.generator_triangles = o.morph_triangles;
  row.generator_pieces = o.morph_pieces.size();
  row.generator_max_error = std::max(o.morph_to_exact.stats.max_abs, o.exact_to_morph.max_abs);
  row.generator_mean_error = o.morph_to_exact.stats.mean_abs;
  row.generator_rms_error = o.morph_to_exact.stats.rms;
  row.reference_grid_mib = static_cast<double>(evaluation.reference_stats.memory_bytes) / 1048576.0;
  row.reference_active_voxels = o.reference_active_voxels;
  row.reference_pieces = o.reference_pieces.size();
  row.reference_max_error = o.reference_to_exact.stats.max_abs;
  row.reference_mean_error = o.reference_to_exact.stats.mean_abs;
  row.reference_rms_error = o.reference_to_exact.stats.rms;
  row.agreement = std::max(o.morph_to_reference.stats.max_abs, o.reference_to_morph.stats.max_abs);
  row.verdict = o.verdict();
  if (spec.heatmaps) {
    const morph::ErosionField field(job);
    const std::string unit = morph::to_string(job.units);
    for (const auto& [side, mesh] :
         {std::pair<std::string, const morph::TriangleMesh*>{"generator", &evaluation.morph_mesh},
          {"reference", &evaluation.reference_mesh}}) {
      if (mesh->empty()) continue;
      std::vector<double> values(mesh->vertex_count());
      morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, values.size(),
                            [&](std::size_t i) { values[i] = field.value(mesh->vertices[i]); });
      const std::string name = "heatmaps/" + picture_stem + "_" + side + ".png";
      render_heatmap(*mesh, values, unit, spec, out_dir / name);
      row.pictures.push_back(name);
    }
  }
}

morph::Job scaled_tools(morph::Job job, double scale) {
  for (auto& [number, tool] : job.tools) {
    if (tool.type == morph::ToolType::Sphere)
      tool = morph::sphere_tool(tool.radius * scale);
    else if (tool.type == morph::ToolType::BallEnd)
      tool = morph::ball_tool(tool.radius * scale, tool.length);
    else
      throw morph::InputError("a tool-radius study scales sphere and ballend tools only; tool " +
                              std::to_string(number) + " is " + morph::describe(tool));
    tool.number = number;
  }
  job.name += fmt::format(" (tool radius x{})", scale);
  return job;
}

// --- output ----------------------------------------------------------------------------------------

const char* const kCsvHeader =
    "job,parameter,value,tolerance,voxel_size,tool_radius,step_over,generator_seconds,generator_peak_mib,"
    "generator_triangles,generator_pieces,generator_max_error,generator_mean_error,generator_rms_error,"
    "reference_seconds,reference_peak_mib,reference_grid_mib,reference_active_voxels,reference_pieces,"
    "reference_max_error,reference_mean_error,reference_rms_error,agreement,verdict,error,tools,generator_"
    "skipped";

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

nlohmann::json row_to_json(const StudyRow& r) {
  return {{"job", r.job},
          {"parameter", to_string(r.parameter)},
          {"value", r.value},
          {"tolerance", r.tolerance},
          {"voxel_size", r.voxel_size},
          {"tool_radius", r.tool_radius},
          {"step_over", r.step_over ? nlohmann::json(*r.step_over) : nlohmann::json()},
          {"tools", r.tools},
          {"generator_skipped", r.generator_skipped},
          {"generator", r.generator_skipped.empty() ? nlohmann::json{{"seconds", r.generator_seconds},
                                                                     {"peak_mib", r.generator_peak_mib},
                                                                     {"triangles", r.generator_triangles},
                                                                     {"pieces", r.generator_pieces},
                                                                     {"max_error", r.generator_max_error},
                                                                     {"mean_error", r.generator_mean_error},
                                                                     {"rms_error", r.generator_rms_error}}
                                                    : nlohmann::json()},
          {"reference",
           {{"seconds", r.reference_seconds},
            {"peak_mib", r.reference_peak_mib},
            {"grid_mib", r.reference_grid_mib},
            {"active_voxels", r.reference_active_voxels},
            {"pieces", r.reference_pieces},
            {"max_error", r.reference_max_error},
            {"mean_error", r.reference_mean_error},
            {"rms_error", r.reference_rms_error}}},
          {"agreement", r.generator_skipped.empty() ? nlohmann::json(r.agreement) : nlohmann::json()},
          {"verdict", r.verdict},
          {"pictures", r.pictures},
          {"error", r.error}};
}

/// The evaluated part of a row (what row_to_json wrote); job, parameter and value are the caller's.
StudyRow row_from_json(const nlohmann::json& j) {
  StudyRow r;
  r.tolerance = j.at("tolerance").get<double>();
  r.voxel_size = j.at("voxel_size").get<double>();
  r.tool_radius = j.at("tool_radius").get<double>();
  if (j.at("step_over").is_number()) r.step_over = j["step_over"].get<double>();
  r.tools = j.value("tools", std::string());
  r.generator_skipped = j.value("generator_skipped", std::string());
  if (r.generator_skipped.empty()) {
    const auto& g = j.at("generator");
    r.generator_seconds = g.at("seconds").get<double>();
    r.generator_peak_mib = g.at("peak_mib").get<double>();
    r.generator_triangles = g.at("triangles").get<std::size_t>();
    r.generator_pieces = g.at("pieces").get<std::size_t>();
    r.generator_max_error = g.at("max_error").get<double>();
    r.generator_mean_error = g.at("mean_error").get<double>();
    r.generator_rms_error = g.at("rms_error").get<double>();
  }
  const auto& f = j.at("reference");
  r.reference_seconds = f.at("seconds").get<double>();
  r.reference_peak_mib = f.at("peak_mib").get<double>();
  r.reference_grid_mib = f.at("grid_mib").get<double>();
  r.reference_active_voxels = f.at("active_voxels").get<std::size_t>();
  r.reference_pieces = f.at("pieces").get<std::size_t>();
  r.reference_max_error = f.at("max_error").get<double>();
  r.reference_mean_error = f.at("mean_error").get<double>();
  r.reference_rms_error = f.at("rms_error").get<double>();
  if (j.at("agreement").is_number()) r.agreement = j["agreement"].get<double>();
  r.verdict = j.at("verdict").get<bool>();
  r.pictures = j.at("pictures").get<std::vector<std::string>>();
  r.error = j.at("error").get<std::string>();
  return r;
}

/// Everything that decides a setting's row, as text: an evaluated setting is kept under it.
std::string setting_identity(const std::string& job_name, const SettingKey& key, const StudySpec& spec) {
  return fmt::format(
      "job {} tolerance {:.17g} voxel {:.17g} radius_scale {:.17g} step_over {:.17g} samples {} "
      "seed {} heatmaps {} image {}x{}",
      job_name, key.tolerance, key.voxel, key.radius_scale, key.step_over, spec.face_samples, spec.seed,
      spec.heatmaps, spec.image_width, spec.image_height);
}

/// settings/setting_<FNV-1a of the identity>.json
fs::path setting_file(const fs::path& dir, const std::string& identity) {
  std::uint64_t hash = 1469598103934665603ull;
  for (unsigned char c : identity) hash = (hash ^ c) * 1099511628211ull;
  return dir / "settings" / fmt::format("setting_{:016x}.json", hash);
}

std::optional<StudyRow> kept_row(const fs::path& file, const std::string& identity) {
  std::error_code error;
  if (!fs::exists(file, error)) return std::nullopt;
  try {
    std::ifstream in(file);
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.at("identity").get<std::string>() != identity) return std::nullopt;
    return row_from_json(j.at("row"));
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;  // unreadable: evaluate it again
  }
}

std::vector<const StudyRow*> rows_of(const StudyResult& result, const std::string& job, Parameter parameter) {
  std::vector<const StudyRow*> rows;
  for (const auto& row : result.rows)
    if (row.job == job && row.parameter == parameter && row.error.empty()) rows.push_back(&row);
  return rows;
}

std::vector<std::string> job_names(const StudyResult& result) {
  std::vector<std::string> names;
  for (const auto& row : result.rows)
    if (std::find(names.begin(), names.end(), row.job) == names.end()) names.push_back(row.job);
  return names;
}

const StudyResult::Convergence* find_fit(const StudyResult& result, const std::string& job,
                                         const std::string& measure) {
  for (const auto& c : result.convergence)
    if (c.job == job && c.measure == measure) return &c;
  return nullptr;
}

std::vector<std::pair<std::string, std::string>> make_plots(const StudyResult& result, const fs::path& dir) {
  std::vector<std::pair<std::string, std::string>> plots;  // title, file
  const auto jobs = job_names(result);
  const std::string unit = "job units";
  auto try_plot = [&](const PlotSpec& spec, const std::string& file) {
    bool any = false;
    for (const auto& s : spec.series) any = any || !s.x.empty();
    if (!any) return;
    plot_png(spec, (dir / file).string());
    plots.emplace_back(spec.title, file);
  };
  {
    PlotSpec spec;
    spec.title = "Error against the exact surface vs reference voxel size";
    spec.x_label = "voxel size (" + unit + ")";
    spec.y_label = "max / mean |deviation| (" + unit + ")";
    int colour = 1;
    for (const auto& job : jobs) {
      const auto rows = rows_of(result, job, Parameter::VoxelSize);
      if (rows.empty()) continue;
      PlotSeries mean, max, generator;
      for (const auto* r : rows) {
        mean.x.push_back(r->voxel_size);
        mean.y.push_back(r->reference_mean_error);
        max.x.push_back(r->voxel_size);
        max.y.push_back(r->reference_max_error);
        if (!r->generator_skipped.empty()) continue;
        generator.x.push_back(r->voxel_size);
        generator.y.push_back(r->generator_max_error);
      }
      const auto* fit_mean = find_fit(result, job, "mean");
      const auto* fit_max = find_fit(result, job, "max");
      mean.label = fmt::format("{}: reference mean (order {})", job,
                               fit_mean ? fmt::format("{:.2f}", fit_mean->fit.order) : "-");
      max.label = fmt::format("{}: reference max (order {})", job,
                              fit_max ? fmt::format("{:.2f}", fit_max->fit.order) : "-");
      generator.label = fmt::format("{}: generator max (tolerance {})", job, number(rows.front()->tolerance));
      mean.color = colour;
      max.color = colour;
      max.dashed = true;
      generator.color = colour + 1;
      generator.markers = false;
      generator.dashed = true;
      spec.series.push_back(mean);
      spec.series.push_back(max);
      if (!generator.x.empty()) spec.series.push_back(generator);
      colour += 2;
    }
    try_plot(spec, "error_vs_voxel.png");
  }
  auto accuracy_chart = [&](const std::string& title, const std::string& y_label, const std::string& file,
                            double StudyRow::*generator_y, double StudyRow::*reference_y) {
    PlotSpec spec;
    spec.title = title;
    spec.x_label = "max |deviation| from the exact surface (" + unit + ")";
    spec.y_label = y_label;
    int colour = 1;
    for (const auto& job : jobs) {
      PlotSeries generator, reference;
      generator.label = job + ": generator (tolerance sweep)";
      reference.label = job + ": reference (voxel sweep)";
      for (const auto* r : rows_of(result, job, Parameter::Tolerance)) {
        if (!r->generator_skipped.empty()) continue;
        generator.x.push_back(r->generator_max_error);
        generator.y.push_back(r->*generator_y);
      }
      for (const auto* r : rows_of(result, job, Parameter::VoxelSize)) {
        reference.x.push_back(r->reference_max_error);
        reference.y.push_back(r->*reference_y);
      }
      generator.color = colour;
      reference.color = colour + 1;
      reference.dashed = true;
      if (!generator.x.empty()) spec.series.push_back(generator);
      if (!reference.x.empty()) spec.series.push_back(reference);
      colour += 2;
    }
    try_plot(spec, file);
  };
  accuracy_chart("Time vs accuracy", "seconds", "time_vs_accuracy.png", &StudyRow::generator_seconds,
                 &StudyRow::reference_seconds);
  accuracy_chart("Peak memory vs accuracy", "peak resident memory during the stage (MiB)",
                 "memory_vs_accuracy.png", &StudyRow::generator_peak_mib, &StudyRow::reference_peak_mib);
  for (const Parameter parameter : {Parameter::ToolRadiusScale, Parameter::StepOver}) {
    PlotSpec spec;
    spec.title = std::string("Error vs ") + to_string(parameter);
    spec.x_label = parameter == Parameter::StepOver ? "step-over (" + unit + ")" : "tool radius scale";
    spec.y_label = "max |deviation| from the exact surface (" + unit + ")";
    spec.log_x = false;
    int colour = 1;
    for (const auto& job : jobs) {
      PlotSeries generator, reference;
      generator.label = job + ": generator";
      reference.label = job + ": reference";
      for (const auto* r : rows_of(result, job, parameter)) {
        if (r->generator_skipped.empty()) {
          generator.x.push_back(r->value);
          generator.y.push_back(r->generator_max_error);
        }
        reference.x.push_back(r->value);
        reference.y.push_back(r->reference_max_error);
      }
      generator.color = colour;
      reference.color = colour + 1;
      reference.dashed = true;
      if (!generator.x.empty()) spec.series.push_back(generator);
      if (!reference.x.empty()) spec.series.push_back(reference);
      colour += 2;
    }
    try_plot(spec, std::string("error_vs_") + to_string(parameter) + ".png");
  }
  return plots;
}

std::string html_table(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::string>>& rows) {
  std::ostringstream out;
  out << "<table>\n<tr>";
  for (const auto& h : header) out << "<th>" << html_escape(h) << "</th>";
  out << "</tr>\n";
  for (const auto& row : rows) {
    out << "<tr>";
    for (const auto& cell : row) out << "<td>" << html_escape(cell) << "</td>";
    out << "</tr>\n";
  }
  out << "</table>\n";
  return out.str();
}

void write_html(const StudyResult& result, const std::vector<std::pair<std::string, std::string>>& plots,
                const fs::path& dir) {
  std::ostringstream page;
  const StudySpec& spec = result.spec;
  page << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>MorphMill study: "
       << html_escape(spec.name) << "</title>\n<style>\n"
       << "body{font-family:sans-serif;margin:2em;max-width:1300px;color:#222}\n"
       << "table{border-collapse:collapse;margin-bottom:1em;font-size:.9em}td,th{border:1px solid #bbb;"
          "padding:3px 6px;text-align:right}th{background:#eee}td:first-child{text-align:left}\n"
       << "figure{display:inline-block;margin:0 1em 1em 0;vertical-align:top}figcaption{text-align:center;"
          "max-width:480px}\n</style></head>\n<body>\n<h1>MorphMill study: "
       << html_escape(spec.name) << "</h1>\n<p>" << html_escape(spec.description) << "</p>\n";
  page << "<h3>Convergence</h3>\n<p>Least-squares slope of log(error) against log(parameter): the "
          "order.</p>\n";
  std::vector<std::vector<std::string>> fits;
  for (const auto& c : result.convergence)
    fits.push_back({c.job, c.tools, c.measure, fmt::format("{:.3f}", c.fit.order),
                    fmt::format("{:.4g}", c.fit.constant), fmt::format("{:.4f}", c.fit.r_squared),
                    std::to_string(c.fit.points)});
  page << html_table({"job", "tools", "error measure", "order", "constant", "R^2", "points"}, fits);
  page << "<h3>Plots</h3>\n";
  for (const auto& [title, file] : plots)
    page << "<figure><img alt=\"" << html_escape(title) << "\" src=\"data:image/png;base64,"
         << base64(read_file_bytes(dir / file)) << "\"><figcaption>" << html_escape(title)
         << "</figcaption></figure>\n";
  page << "<h3>Table</h3>\n";
  std::vector<std::vector<std::string>> rows;
  for (const auto& r : result.rows) {
    const bool ran = r.generator_skipped.empty();  // else: the reference alone, its verdict
    rows.push_back(
        {r.job, to_string(r.parameter), number(r.value), number(r.tolerance), number(r.voxel_size),
         number(r.tool_radius), r.step_over ? number(*r.step_over) : "-",
         ran ? fmt::format("{:.2f}", r.generator_seconds) : "not run",
         ran ? number(r.generator_max_error) : "-", fmt::format("{:.2f}", r.reference_seconds),
         number(r.reference_max_error), number(r.reference_mean_error), ran ? number(r.agreement) : "-",
         ran ? fmt::format("{:.0f}", r.generator_peak_mib) : "-", fmt::format("{:.0f}", r.reference_peak_mib),
         !r.error.empty() ? r.error
                          : std::string(r.verdict ? "holds" : "FAILS") + (ran ? "" : " (reference alone)")});
  }
  page << html_table(
      {"job", "parameter", "value", "tolerance", "voxel", "tool radius", "step-over", "generator s",
       "generator max err", "reference s", "reference max err", "reference mean err", "generator-reference",
       "generator MiB", "reference MiB", "verdict"},
      rows);
  page << "<h3>Heatmaps</h3>\n<p>Signed distance of each surface's vertices to the exact surface (blue "
          "inside, red "
          "outside).</p>\n";
  for (const auto& r : result.rows)
    for (const auto& file : r.pictures)
      page << "<figure><img alt=\"" << html_escape(file) << "\" src=\"data:image/png;base64,"
           << base64(read_file_bytes(dir / file)) << "\"><figcaption>" << html_escape(r.job) << ", "
           << to_string(r.parameter) << " = " << number(r.value) << ", "
           << (file.find("_generator.png") != std::string::npos ? "generator" : "reference")
           << "</figcaption></figure>\n";
  page << "<script>window.addEventListener('load',function(){var i=document.images,n=0;"
          "for(var k=0;k<i.length;k++){if(i[k].complete&&i[k].naturalWidth>0)n++;}"
          "document.body.setAttribute('data-images-loaded',n+'/'+i.length);});</script>\n</body></html>\n";
  write_text(dir / "report.html", page.str());
}

}  // namespace

const char* to_string(Parameter parameter) {
  switch (parameter) {
    case Parameter::VoxelSize:
      return "voxel_size";
    case Parameter::Tolerance:
      return "tolerance";
    case Parameter::ToolRadiusScale:
      return "tool_radius_scale";
    case Parameter::StepOver:
      return "step_over";
  }
  return "?";
}

morph::Job make_zigzag_job(const ZigzagSpec& spec) {
  const std::string where = "zigzag job '" + spec.name + "'";
  if (!(spec.step_over > 0) || !(spec.tool_radius > 0) || !(spec.depth > 0))
    throw morph::InputError(where + ": step_over, tool radius and depth must be positive");
  if (!(spec.x1 > spec.x0) || !(spec.y1 > spec.y0)) throw morph::InputError(where + ": empty area");
  if (!(spec.stock_max.array() > spec.stock_min.array()).all())
    throw morph::InputError(where + ": empty stock");
  morph::Job job;
  job.name = spec.name;
  job.tolerance = spec.tolerance;
  job.stock.type = morph::StockType::Box;
  job.stock.box = Eigen::AlignedBox3d(spec.stock_min, spec.stock_max);
  const morph::ToolType type = morph::tool_type_from_string(spec.tool_type, where + ": tool.type");
  morph::Tool tool;
  try {
    if (type == morph::ToolType::Sphere)
      tool = morph::sphere_tool(spec.tool_radius);
    else if (type == morph::ToolType::BallEnd)
      tool = morph::ball_tool(spec.tool_radius, spec.tool_length);
    else if (type == morph::ToolType::Flat)
      tool = morph::flat_tool(spec.tool_radius, spec.tool_length);
    else
      throw morph::InputError(where + ": tool.type: a zigzag takes a sphere, ballend or flat tool, got '" +
                              spec.tool_type + "' (give other shapes in a job file)");
  } catch (const morph::ToolError& e) {
    throw morph::InputError(where + ": tool." + e.what());
  }
  tool.number = 1;
  job.tools[1] = tool;
  const double lowest = spec.stock_max.z() - spec.depth;
  const double z = tool.type == morph::ToolType::Sphere ? lowest + tool.radius : lowest;
  morph::Path path;
  path.source = spec.name + " zigzag";
  std::vector<Eigen::Vector3d> points;
  const int passes = static_cast<int>(std::floor((spec.y1 - spec.y0) / spec.step_over + 1e-9)) + 1;
  for (int i = 0; i < passes; ++i) {
    const double y = spec.y0 + i * spec.step_over;
    const bool forward = i % 2 == 0;
    points.emplace_back(forward ? spec.x0 : spec.x1, y, z);
    points.emplace_back(forward ? spec.x1 : spec.x0, y, z);
  }
  for (std::size_t i = 1; i < points.size(); ++i) {
    morph::Move move;
    move.kind = morph::MoveKind::Linear;
    move.start = points[i - 1];
    move.end = points[i];
    move.tool = 1;
    move.line = static_cast<int>(i + 1);
    path.moves.push_back(move);
  }
  job.paths.push_back(path);
  return job;
}

StudySpec parse_study(const nlohmann::json& json, const std::string& file) {
  const Reader reader(file);
  reader.only_keys(json, "",
                   {"name", "description", "jobs", "zigzag_jobs", "sweep", "baseline", "samples", "seed",
                    "heatmaps", "image_size"});
  StudySpec spec;
  spec.file = file;
  spec.name = json.contains("name") ? reader.text(json["name"], "name") : fs::path(file).stem().string();
  if (json.contains("description")) spec.description = reader.text(json["description"], "description");
  if (json.contains("jobs")) {
    if (!json["jobs"].is_array()) reader.fail("jobs", "expected an array of job file paths");
    for (std::size_t i = 0; i < json["jobs"].size(); ++i) {
      const std::string path = reader.text(json["jobs"][i], "jobs[" + std::to_string(i) + "]");
      spec.job_paths.push_back((fs::path(file).parent_path() / path).lexically_normal().string());
    }
  }
  if (json.contains("zigzag_jobs")) {
    if (!json["zigzag_jobs"].is_array()) reader.fail("zigzag_jobs", "expected an array");
    for (std::size_t i = 0; i < json["zigzag_jobs"].size(); ++i)
      spec.zigzags.push_back(
          parse_zigzag(reader, json["zigzag_jobs"][i], "zigzag_jobs[" + std::to_string(i) + "]"));
  }
  if (spec.job_paths.empty() && spec.zigzags.empty()) reader.fail("jobs", "the study names no job");
  const auto& sweep = json.value("sweep", nlohmann::json::object());
  reader.only_keys(
      sweep, "sweep",
      {"voxel_size", "voxel_size_relative_to_tool_radius", "tolerance", "tool_radius_scale", "step_over"});
  if (sweep.contains("voxel_size"))
    spec.voxel_sizes = reader.positives(sweep["voxel_size"], "sweep.voxel_size");
  if (sweep.contains("voxel_size_relative_to_tool_radius")) {
    if (!sweep["voxel_size_relative_to_tool_radius"].is_boolean())
      reader.fail("sweep.voxel_size_relative_to_tool_radius", "expected true or false");
    spec.voxel_relative_to_tool_radius = sweep["voxel_size_relative_to_tool_radius"].get<bool>();
  }
  if (sweep.contains("tolerance")) spec.tolerances = reader.positives(sweep["tolerance"], "sweep.tolerance");
  if (sweep.contains("tool_radius_scale"))
    spec.tool_radius_scales = reader.positives(sweep["tool_radius_scale"], "sweep.tool_radius_scale");
  if (sweep.contains("step_over")) spec.step_overs = reader.positives(sweep["step_over"], "sweep.step_over");
  if (spec.voxel_sizes.empty() && spec.tolerances.empty() && spec.tool_radius_scales.empty() &&
      spec.step_overs.empty())
    reader.fail("sweep", "nothing to sweep");
  if (!spec.step_overs.empty() && spec.zigzags.empty())
    reader.fail("sweep.step_over", "the step-over sweep needs zigzag_jobs");
  const auto& baseline = json.value("baseline", nlohmann::json::object());
  reader.only_keys(baseline, "baseline", {"voxel_size", "tolerance"});
  if (baseline.contains("voxel_size"))
    spec.baseline_voxel = reader.non_negative(baseline["voxel_size"], "baseline.voxel_size");
  if (baseline.contains("tolerance"))
    spec.baseline_tolerance = reader.non_negative(baseline["tolerance"], "baseline.tolerance");
  if (json.contains("samples"))
    spec.face_samples = static_cast<std::size_t>(reader.non_negative(json["samples"], "samples"));
  if (json.contains("seed")) {
    if (!json["seed"].is_number_unsigned()) reader.fail("seed", "expected a whole number >= 0");
    spec.seed = json["seed"].get<std::uint64_t>();
  }
  if (json.contains("heatmaps")) {
    if (!json["heatmaps"].is_boolean()) reader.fail("heatmaps", "expected true or false");
    spec.heatmaps = json["heatmaps"].get<bool>();
  }
  if (json.contains("image_size")) {
    const auto size = reader.positives(json["image_size"], "image_size");
    if (size.size() != 2) reader.fail("image_size", "expected [width, height]");
    spec.image_width = static_cast<int>(size[0]);
    spec.image_height = static_cast<int>(size[1]);
  }
  return spec;
}

StudySpec load_study(const std::string& path) {
  std::string text;
  try {
    text = read_file_bytes(path);
  } catch (const morph::IoError&) {
    throw morph::IoError(path + ": cannot read the study file");
  }
  return parse_study(parse_json_text(text, path), path);
}

PowerFit fit_power_law(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<double> lx, ly;
  for (std::size_t i = 0; i < std::min(x.size(), y.size()); ++i)
    if (x[i] > 0 && y[i] > 0 && std::isfinite(x[i]) && std::isfinite(y[i])) {
      lx.push_back(std::log(x[i]));
      ly.push_back(std::log(y[i]));
    }
  if (lx.size() < 2) throw morph::InputError("fit_power_law: needs at least two positive (x, y) pairs");
  const double n = static_cast<double>(lx.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < lx.size(); ++i) {
    mx += lx[i] / n;
    my += ly[i] / n;
  }
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < lx.size(); ++i) {
    sxx += (lx[i] - mx) * (lx[i] - mx);
    sxy += (lx[i] - mx) * (ly[i] - my);
    syy += (ly[i] - my) * (ly[i] - my);
  }
  if (!(sxx > 0)) throw morph::InputError("fit_power_law: every x is the same");
  PowerFit fit;
  fit.order = sxy / sxx;
  fit.constant = std::exp(my - fit.order * mx);
  fit.r_squared = syy > 0 ? (sxy * sxy) / (sxx * syy) : 1.0;
  fit.points = lx.size();
  return fit;
}

std::string rows_to_csv(const std::vector<StudyRow>& rows) {
  std::ostringstream csv;
  csv << kCsvHeader << '\n';
  for (const auto& r : rows) {
    csv << csv_field(r.job) << ',' << to_string(r.parameter) << ',' << number(r.value) << ','
        << number(r.tolerance) << ',' << number(r.voxel_size) << ',' << number(r.tool_radius) << ','
        << (r.step_over ? number(*r.step_over) : "") << ',';
    if (r.generator_skipped.empty())
      csv << number(r.generator_seconds) << ',' << number(r.generator_peak_mib) << ','
          << r.generator_triangles << ',' << r.generator_pieces << ',' << number(r.generator_max_error) << ','
          << number(r.generator_mean_error) << ',' << number(r.generator_rms_error) << ',';
    else
      csv << ",,,,,,,";  // not run: empty, never a zero that reads as a measurement
    csv << number(r.reference_seconds) << ',' << number(r.reference_peak_mib) << ','
        << number(r.reference_grid_mib) << ',' << r.reference_active_voxels << ',' << r.reference_pieces
        << ',' << number(r.reference_max_error) << ',' << number(r.reference_mean_error) << ','
        << number(r.reference_rms_error) << ',' << (r.generator_skipped.empty() ? number(r.agreement) : "")
        << ',' << (r.verdict ? "true" : "false") << ',' << csv_field(r.error) << ',' << csv_field(r.tools)
        << ',' << csv_field(r.generator_skipped) << '\n';
  }
  return csv.str();
}

nlohmann::json result_to_json(const StudyResult& result) {
  nlohmann::json j;
  j["name"] = result.spec.name;
  j["description"] = result.spec.description;
  j["complete"] = result.complete();
  j["stopped"] = result.stopped;
  j["settings"] = result.settings;
  j["settings_evaluated"] = result.evaluated;
  j["convergence"] = nlohmann::json::array();
  for (const auto& c : result.convergence)
    j["convergence"].push_back({{"job", c.job},
                                {"tools", c.tools},
                                {"measure", c.measure},
                                {"order", c.fit.order},
                                {"constant", c.fit.constant},
                                {"r_squared", c.fit.r_squared},
                                {"points", c.fit.points}});
  j["rows"] = nlohmann::json::array();
  for (const auto& r : result.rows) j["rows"].push_back(row_to_json(r));
  j["files"] = result.files;
  return j;
}

StudyResult run_study(const StudyOptions& options) {
  StudyResult result;
  result.spec = load_study(options.study_path);
  const StudySpec& spec = result.spec;
  // Every job is loaded before anything long runs, so a bad one fails at once.
  struct StudyJob {
    morph::Job job;
    std::optional<ZigzagSpec> zigzag;
  };
  std::vector<StudyJob> jobs;
  for (const auto& path : spec.job_paths) jobs.push_back({load_job(path), std::nullopt});
  for (const auto& z : spec.zigzags) jobs.push_back({make_zigzag_job(z), z});
  const fs::path dir(options.out_dir);
  std::error_code error;
  fs::create_directories(dir / "heatmaps", error);
  if (error)
    throw morph::IoError(options.out_dir + ": cannot create the output directory: " + error.message());
  // The old verdict goes first, so a run stopped or killed from here on never leaves it standing.
  fs::remove(dir / "study.json", error);
  if (!options.resume) fs::remove_all(dir / "settings", error);
  fs::create_directories(dir / "settings", error);
  if (error)
    throw morph::IoError(options.out_dir + ": cannot prepare the output directory: " + error.message());

  // The settings: one parameter at a time, the others at their baseline.
  struct Setting {
    std::size_t job;
    Parameter parameter;
    double value;
    SettingKey key;
  };
  std::vector<Setting> settings;
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    const double radius = smallest_radius(jobs[j].job);
    const double unit_of_voxel = spec.voxel_relative_to_tool_radius ? radius : 1.0;
    SettingKey base;
    base.job = j;
    base.tolerance = spec.baseline_tolerance > 0 ? spec.baseline_tolerance : jobs[j].job.tolerance;
    base.voxel = spec.baseline_voxel > 0 ? spec.baseline_voxel * unit_of_voxel : auto_voxel_size(jobs[j].job);
    base.step_over = jobs[j].zigzag ? jobs[j].zigzag->step_over : 0.0;
    for (double v : spec.voxel_sizes) {
      SettingKey key = base;
      key.voxel = v * unit_of_voxel;
      settings.push_back({j, Parameter::VoxelSize, v, key});
    }
    for (double t : spec.tolerances) {
      SettingKey key = base;
      key.tolerance = t;
      settings.push_back({j, Parameter::Tolerance, t, key});
    }
    for (double s : spec.tool_radius_scales) {
      SettingKey key = base;
      key.radius_scale = s;
      settings.push_back({j, Parameter::ToolRadiusScale, s, key});
    }
    if (jobs[j].zigzag)
      for (double s : spec.step_overs) {
        SettingKey key = base;
        key.step_over = s;
        settings.push_back({j, Parameter::StepOver, s, key});
      }
  }

  if (options.progress) options.progress->begin("study: settings", settings.size());
  std::map<SettingKey, StudyRow> done;  // a setting reached by two sweeps is evaluated once
  std::set<SettingKey> distinct;
  for (const auto& setting : settings) distinct.insert(setting.key);
  result.settings = distinct.size();
  for (const auto& setting : settings) {
    const StudyJob& source = jobs[setting.job];
    auto found = done.find(setting.key);
    const std::string identity = setting_identity(source.job.name, setting.key, spec);
    const fs::path kept_file = setting_file(dir, identity);
    if (found == done.end()) {
      if (auto kept = kept_row(kept_file, identity)) found = done.emplace(setting.key, *kept).first;
    }
    if (found == done.end()) {
      if (options.stop_signal && options.stop_signal->load() != 0) {
        result.stopped = std::string("interrupted by ") + signal_name(options.stop_signal->load());
        break;
      }
      StudyRow row;
      morph::Job job = source.job;
      if (setting.key.radius_scale != 1.0) job = scaled_tools(job, setting.key.radius_scale);
      if (source.zigzag) {
        ZigzagSpec zigzag = *source.zigzag;
        zigzag.step_over = setting.key.step_over;
        zigzag.tool_radius *= setting.key.radius_scale;
        job = make_zigzag_job(zigzag);
        row.step_over = zigzag.step_over;
      }
      const std::string stem =
          slug(fmt::format("{}_{}_{}", source.job.name, to_string(setting.parameter), number(setting.value)));
      try {
        evaluate_setting(job, setting.key, spec, dir, stem, row);
      } catch (const morph::InputError&) {
        throw;  // bad input stays bad for every setting
      } catch (const std::exception& e) {
        row.error = e.what();  // e.g. a voxel size too fine for the memory cap: keep the other settings
      }
      write_text(kept_file, nlohmann::json{{"identity", identity}, {"row", row_to_json(row)}}.dump(2) + "\n");
      found = done.emplace(setting.key, row).first;
    }
    StudyRow row = found->second;
    row.job = source.job.name;
    row.parameter = setting.parameter;
    row.value = setting.value;
    result.rows.push_back(row);
    if (options.progress) options.progress->advance(1);
  }
  if (options.progress) options.progress->end();
  result.evaluated = done.size();

  for (const auto& job : job_names(result)) {
    const auto voxel_rows = rows_of(result, job, Parameter::VoxelSize);
    std::vector<double> voxel, mean, rms, max;
    std::string tools;
    for (const auto& r : result.rows)
      if (r.job == job && !r.tools.empty()) tools = r.tools;
    for (const auto* r : voxel_rows) {
      voxel.push_back(r->voxel_size);
      mean.push_back(r->reference_mean_error);
      rms.push_back(r->reference_rms_error);
      max.push_back(r->reference_max_error);
    }
    // A fit needs two distinct positive points; without them the measure has no order to report.
    auto add_fit = [&](const std::string& measure, const std::vector<double>& x,
                       const std::vector<double>& y) {
      try {
        result.convergence.push_back({job, measure, tools, fit_power_law(x, y)});
      } catch (const morph::InputError&) {
      }
    };
    add_fit("mean", voxel, mean);
    add_fit("rms", voxel, rms);
    add_fit("max", voxel, max);
    std::vector<double> tolerance, generator;
    for (const auto* r : rows_of(result, job, Parameter::Tolerance)) {
      if (!r->generator_skipped.empty()) continue;
      tolerance.push_back(r->tolerance);
      generator.push_back(r->generator_max_error);
    }
    add_fit("generator max vs tolerance", tolerance, generator);
  }

  write_text(dir / "study.csv", rows_to_csv(result.rows));
  result.files.push_back("study.csv");
  if (!result.complete()) {
    // Stopped: the table of what ran; plots and the report wait for the whole study (--resume).
    result.files.push_back("study.json");
    write_text(dir / "study.json", result_to_json(result).dump(2) + "\n");
    return result;
  }
  const auto plots = make_plots(result, dir);
  for (const auto& [title, file] : plots) result.files.push_back(file);
  for (const auto& row : result.rows)
    for (const auto& picture : row.pictures)
      if (std::find(result.files.begin(), result.files.end(), picture) == result.files.end())
        result.files.push_back(picture);
  write_html(result, plots, dir);
  result.files.push_back("report.html");
  result.files.push_back("study.json");
  write_text(dir / "study.json", result_to_json(result).dump(2) + "\n");
  return result;
}

}  // namespace morphmill::study
