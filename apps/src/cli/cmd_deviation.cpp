// SPDX-License-Identifier: Apache-2.0
// morphmill deviation / render: the Embree measurement (raytest) on mesh files.
#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morphmill/mesh_io.h>
#include <raytest/deviation.h>
#include <raytest/deviation_memory.h>
#include <raytest/heatmap.h>
#include <raytest/render.h>
#include <raytest/surface_query.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/cli_conventions.h"
#include "cli/commands.h"
#include "cli/memory_cap.h"
#include "cli/terminal_progress.h"
#include "io/deviation_files.h"
#include "io/provenance.h"
#include "verify/verify.h"  // stats_to_json

namespace morphmill {

namespace {

// Wall-clock seconds since construction.
class Stopwatch {
 public:
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// Most samples --samples and --edge-samples take per mesh.
constexpr std::size_t kMaxDeviationSamples = 20000000;

std::pair<int, int> parse_size(const std::string& text) {
  const std::size_t x = text.find_first_of("xX");
  try {
    if (x != std::string::npos) {
      std::size_t used_w = 0, used_h = 0;
      const int w = std::stoi(text.substr(0, x), &used_w);
      const int h = std::stoi(text.substr(x + 1), &used_h);
      if (used_w == x && used_h == text.size() - x - 1 && w > 0 && h > 0) return {w, h};
    }
  } catch (const std::exception&) {
  }
  throw morph::InputError("--size: expected WIDTHxHEIGHT in pixels (e.g. 1200x900), got '" + text + "'");
}

std::optional<raytest::ScalarRange> parse_range(const std::vector<double>& range) {
  if (range.empty()) return std::nullopt;
  if (range.size() != 2 || !(range[0] < range[1]) || !std::isfinite(range[0]) || !std::isfinite(range[1]))
    throw morph::InputError("--range: expected LOW,HIGH with LOW < HIGH");
  return raytest::ScalarRange{range[0], range[1]};
}

const char* mode_name(raytest::DeviationMode mode) {
  switch (mode) {
    case raytest::DeviationMode::Unsigned:
      return "unsigned";
    case raytest::DeviationMode::Signed:
      return "signed";
    case raytest::DeviationMode::Ray:
      return "ray";
  }
  return "?";
}

std::string tag_label(const morph::FaceTag& tag) {
  std::string label = morph::to_string(tag.kind);
  if (tag.kind == morph::PatchKind::StockFace || tag.kind == morph::PatchKind::CutSurface)
    label += fmt::format(" stock face {}", tag.source);
  else if (tag.source >= 0)
    label += fmt::format(" move {}", tag.source);
  if (tag.line > 0) label += fmt::format(" (G-code line {})", tag.line);
  return label;
}

void print_stats(const std::string& title, const raytest::DeviationStats& s) {
  fmt::print("{}: {} samples", title, s.count);
  if (s.misses > 0) fmt::print(", {} misses", s.misses);
  fmt::print("\n  min {:.9g}  max {:.9g}  max|d| {:.9g}\n", s.min, s.max, s.max_abs);
  fmt::print("  mean {:.9g}  mean|d| {:.9g}  RMS {:.9g}\n", s.mean, s.mean_abs, s.rms);
  fmt::print("  |d| percentiles: 50% {:.6g}  90% {:.6g}  99% {:.6g}  99.9% {:.6g}\n", s.p50, s.p90, s.p99,
             s.p999);
  if (s.tolerance > 0) {
    fmt::print("  within tolerance {:.6g}: {:.4f}%\n", s.tolerance, 100.0 * s.share_within_tolerance);
    if (s.min < 0)
      fmt::print("  signed: below -{0:.6g} (gouge) {1:.4f}%, above +{0:.6g} (excess) {2:.4f}%\n", s.tolerance,
                 100.0 * s.share_gouge, 100.0 * s.share_excess);
  }
}

void print_groups(const std::vector<raytest::GroupStats>& groups) {
  if (groups.empty()) return;
  fmt::print("  worst by provenance:\n");
  for (const raytest::GroupStats& g : groups)
    fmt::print("    {:<40} max|d| {:.6g}  mean {:.6g}  ({} samples)\n", tag_label(g.tag), g.stats.max_abs,
               g.stats.mean, g.stats.count);
}

nlohmann::json one_sided_to_json(const raytest::OneSidedDeviation& d) {
  nlohmann::json j;
  j["stats"] = stats_to_json(d.stats);
  j["worst_groups"] = nlohmann::json::array();
  for (const raytest::GroupStats& g : d.groups)
    j["worst_groups"].push_back({{"patch_kind", morph::to_string(g.tag.kind)},
                                 {"source", g.tag.source},
                                 {"line", g.tag.line},
                                 {"stats", stats_to_json(g.stats)}});
  return j;
}

struct DeviationArgs {
  std::string a_path, b_path;
  std::size_t face_samples = 100000;
  std::size_t edge_samples = 0;
  bool no_vertices = false;
  bool one_sided = false;
  bool signed_mode = false;
  bool ray_mode = false;
  double max_distance = std::numeric_limits<double>::infinity();
  double tolerance = 0.0;
  std::size_t bins = 20;
  std::size_t groups = 10;
  std::uint64_t seed = 1;
  std::vector<double> range;
  bool symmetric = false;
  std::string heatmap_path, vtp_path, png_path, json_path;
  CLI::Option* json_option = nullptr;
  std::string units = "mesh units";
  std::string view = "iso";
  std::string size = "1200x900";
  double memory_cap_gib = 8.0;
};

/// Resident memory of the morphmill process before any mesh is read (code, libraries, TBB).
constexpr double kProcessBytes = 45.0 * (1 << 20);

/// The estimate of what measuring A against B will hold (raytest::estimate_deviation_memory plus
/// the process), checked against --memory-cap before anything is indexed or sampled. Reading the
/// meshes came first; the readers bound that by the files' lengths.
double check_deviation_memory(const DeviationArgs& args, const morph::TriangleMesh& a,
                              const morph::TriangleMesh& b, const raytest::SamplingOptions& sampling,
                              std::size_t picture_pixels) {
  raytest::DeviationWork work;
  work.a = &a;
  work.b = &b;
  work.sampling = sampling;
  work.two_sided = !args.one_sided;
  work.vertex_values = !args.heatmap_path.empty() || !args.vtp_path.empty();
  work.picture_pixels = picture_pixels;
  const raytest::DeviationMemory m = raytest::estimate_deviation_memory(work);
  const double total = kProcessBytes + m.total();
  const std::size_t cap = memory_cap_bytes(args.memory_cap_gib);
  if (total > double(cap))
    throw morph::LimitError(fmt::format(
        "deviation of {} against {}: needs about {} ({} triangles, {} samples: meshes {}, indexes {}, "
        "samples {}, pictures {}), over the memory cap of {} (--memory-cap): lower --samples or "
        "--edge-samples, add --no-vertices or --one-sided, leave out --png, or raise the cap",
        args.a_path, args.b_path, describe_bytes(total), a.triangle_count() + b.triangle_count(),
        raytest::sample_count(a, sampling) + (args.one_sided ? 0 : raytest::sample_count(b, sampling)),
        describe_bytes(m.meshes), describe_bytes(m.indexes), describe_bytes(m.samples),
        describe_bytes(m.pictures), describe_bytes(double(cap))));
  return total;
}

void run_deviation(const DeviationArgs& args) {
  if (args.signed_mode && args.ray_mode)
    throw morph::InputError("deviation: choose one of --signed and --ray");
  if (args.no_vertices && args.face_samples == 0 && args.edge_samples == 0)
    throw morph::InputError("deviation: no samples (--no-vertices with --samples 0 and --edge-samples 0)");
  const std::optional<raytest::ScalarRange> fixed_range = parse_range(args.range);
  const std::pair<int, int> size = parse_size(args.size);
  const raytest::View view = raytest::parse_view(args.view);

  // Each stage of a large comparison can take minutes: say which one runs and when it ends.
  TerminalProgress progress;
  const auto stage = [&progress](const std::string& name, auto&& work) {
    progress.begin(name, 1);
    auto result = work();
    progress.advance(1);
    progress.end();
    return result;
  };
  const Stopwatch total;
  morph::TriangleMesh a = stage("reading " + args.a_path, [&] { return read_mesh(args.a_path); });
  morph::TriangleMesh b = stage("reading " + args.b_path, [&] { return read_mesh(args.b_path); });
  const double load_seconds = total.seconds();

  raytest::DeviationOptions options;
  options.sampling.vertices = !args.no_vertices;
  options.sampling.edge_samples = args.edge_samples;
  options.sampling.face_samples = args.face_samples;
  options.sampling.seed = args.seed;
  options.mode = args.ray_mode      ? raytest::DeviationMode::Ray
                 : args.signed_mode ? raytest::DeviationMode::Signed
                                    : raytest::DeviationMode::Unsigned;
  options.max_distance = args.max_distance;
  options.stats.tolerance = args.tolerance;
  options.stats.histogram_bins = args.bins;
  options.worst_groups = args.groups;
  options.progress = &progress;
  const double estimated_bytes =
      check_deviation_memory(args, a, b, options.sampling,
                             args.png_path.empty() ? 0 : std::size_t(size.first) * std::size_t(size.second));

  const Stopwatch measuring;
  progress.begin("indexing " + args.b_path, 1);
  const raytest::SurfaceQuery query_b(std::move(b));
  progress.end();
  std::optional<raytest::SurfaceQuery> query_a;
  raytest::TwoSidedDeviation result;
  if (args.one_sided) {
    result.a_to_b =
        stage("measuring A -> B", [&] { return raytest::measure_one_sided(a, query_b, options); });
    result.hausdorff = result.a_to_b.stats.max_abs;
  } else {
    progress.begin("indexing " + args.a_path, 1);
    query_a.emplace(a);
    progress.end();
    result =
        stage("measuring A <-> B", [&] { return raytest::measure_two_sided(*query_a, query_b, options); });
  }
  const double measure_seconds = measuring.seconds();

  const bool json_wanted = args.json_option->count() > 0;
  if (!json_wanted || !is_standard_output(args.json_path)) {  // else standard output holds the JSON alone
    fmt::print("deviation of {} against {} ({} mode)\n", args.a_path, args.b_path, mode_name(options.mode));
    if (options.mode != raytest::DeviationMode::Unsigned) fmt::print("sign: {}\n", raytest::kSignConvention);
    print_stats("A -> B", result.a_to_b.stats);
    print_groups(result.a_to_b.groups);
    if (!args.one_sided) {
      print_stats("B -> A", result.b_to_a.stats);
      print_groups(result.b_to_a.groups);
      fmt::print("Hausdorff distance (two-sided): {:.9g}\n", result.hausdorff);
    }
    fmt::print("time: loading {:.3f} s, measuring {:.3f} s\n", load_seconds, measure_seconds);
    fmt::print("memory: estimated {} up front\n", describe_bytes(estimated_bytes));
  }

  // Hashing the inputs costs a fraction of loading them; done only when files are written.
  std::optional<Provenance> provenance;
  if (!args.heatmap_path.empty() || !args.vtp_path.empty() || json_wanted)
    provenance =
        make_provenance({args.a_path, args.b_path},
                        {{"command", "deviation"},
                         {"mode", mode_name(options.mode)},
                         {"one_sided", args.one_sided},
                         {"vertices", options.sampling.vertices},
                         {"samples", args.face_samples},
                         {"edge_samples", args.edge_samples},
                         {"seed", args.seed},
                         {"tolerance", args.tolerance},
                         {"max_distance", std::isfinite(args.max_distance) ? nlohmann::json(args.max_distance)
                                                                           : nlohmann::json(nullptr)}},
                        args.units);

  double picture_seconds = 0;
  if (!args.heatmap_path.empty() || !args.vtp_path.empty() || !args.png_path.empty()) {
    const Stopwatch picturing;
    const std::vector<double> values =
        raytest::vertex_deviation(a, query_b, options.mode, options.max_distance);
    const bool signed_values = options.mode != raytest::DeviationMode::Unsigned;
    const raytest::ColorMap map = signed_values ? raytest::ColorMap::CoolWarm : raytest::ColorMap::Viridis;
    const raytest::ScalarRange range =
        fixed_range ? *fixed_range : raytest::auto_range(values, args.symmetric || signed_values);
    raytest::apply_heatmap(a, "deviation", values, map, range);
    if (!args.heatmap_path.empty()) write_deviation_ply(a, "deviation", args.heatmap_path, *provenance);
    if (!args.vtp_path.empty()) write_deviation_vtp(a, "deviation", args.vtp_path, *provenance);
    if (!args.png_path.empty()) {
      raytest::RenderOptions render;
      render.width = size.first;
      render.height = size.second;
      render.view = view;
      render.scalar = "deviation";
      render.color_map = map;
      render.range = range;
      raytest::write_png(raytest::render_mesh(a, render), args.png_path);
    }
    picture_seconds = picturing.seconds();
  }

  if (json_wanted) {
    nlohmann::json j;
    j["format"] = "morphmill-deviation";
    j["format_version"] = 1;  // docs/summary-schema.md
    j["provenance"] = to_json(*provenance);
    j["units"] = args.units;
    j["a"] = args.a_path;
    j["b"] = args.b_path;
    j["mode"] = mode_name(options.mode);
    if (options.mode != raytest::DeviationMode::Unsigned) j["sign_convention"] = raytest::kSignConvention;
    j["sampling"] = {{"vertices", options.sampling.vertices},
                     {"edge_samples", options.sampling.edge_samples},
                     {"face_samples", options.sampling.face_samples},
                     {"seed", options.sampling.seed}};
    if (std::isfinite(options.max_distance)) j["max_distance"] = options.max_distance;
    j["a_to_b"] = one_sided_to_json(result.a_to_b);
    if (!args.one_sided) {
      j["b_to_a"] = one_sided_to_json(result.b_to_a);
      j["hausdorff"] = result.hausdorff;
    }
    j["seconds"] = {{"loading", load_seconds}, {"measuring", measure_seconds}, {"pictures", picture_seconds}};
    j["estimated_bytes"] = estimated_bytes;
    write_json(j, args.json_path);
  }
}

struct RenderArgs {
  std::string mesh_path, out_path;
  std::string scalar;
  std::string view = "iso";
  std::string size = "1200x900";
  std::string map = "auto";
  std::vector<double> range;
  bool symmetric = false;
  std::string unit;
};

void run_render(const RenderArgs& args) {
  const std::pair<int, int> size = parse_size(args.size);
  raytest::RenderOptions options;
  options.width = size.first;
  options.height = size.second;
  options.view = raytest::parse_view(args.view);
  options.scalar = args.scalar;
  options.range = parse_range(args.range);
  options.symmetric = args.symmetric;
  options.unit = args.unit;
  const morph::TriangleMesh mesh = read_mesh(args.mesh_path);
  if (args.map == "viridis") {
    options.color_map = raytest::ColorMap::Viridis;
  } else if (args.map == "coolwarm") {
    options.color_map = raytest::ColorMap::CoolWarm;
  } else if (args.map == "auto") {
    // Diverging map for values of both signs, sequential otherwise.
    const morph::VertexScalar* scalar = args.scalar.empty() ? nullptr : mesh.scalar(args.scalar);
    bool negative = false, positive = false;
    if (scalar)
      for (double v : scalar->values) {
        negative |= v < 0;
        positive |= v > 0;
      }
    options.color_map =
        (negative && positive) || args.symmetric ? raytest::ColorMap::CoolWarm : raytest::ColorMap::Viridis;
  } else {
    throw morph::InputError("--map: expected auto, viridis or coolwarm, got '" + args.map + "'");
  }
  raytest::write_png(raytest::render_mesh(mesh, options), args.out_path);
}

}  // namespace

void register_deviation_commands(CLI::App& app) {
  auto deviation_args = std::make_shared<DeviationArgs>();
  CLI::App* deviation = app.add_subcommand(
      "deviation",
      "Measure how far mesh A lies from mesh B (and B from A): Metro-style samples on vertices, edges and "
      "faces,\n"
      "exact closest points (Embree search, double-precision refinement), statistics, Hausdorff distance,\n"
      "worst provenance groups, heatmap PLY and picture. Distances are in the meshes' units.");
  deviation->add_option("A", deviation_args->a_path, "measured mesh (PLY, STL, OBJ)")->required();
  deviation->add_option("B", deviation_args->b_path, "reference mesh (PLY, STL, OBJ)")->required();
  // Each sample holds its position, normal and result on both sides: a few hundred bytes, so the
  // bound keeps a run within a few GiB and a negative or mistyped count from wrapping around.
  deviation->add_option("--samples", deviation_args->face_samples, "area-uniform face samples on each mesh")
      ->capture_default_str()
      ->check(CLI::Range(0.0, double(kMaxDeviationSamples)));
  deviation
      ->add_option("--edge-samples", deviation_args->edge_samples, "samples along the edges of each mesh")
      ->capture_default_str()
      ->check(CLI::Range(0.0, double(kMaxDeviationSamples)));
  deviation->add_flag("--no-vertices", deviation_args->no_vertices, "do not sample the vertices");
  deviation->add_flag("--one-sided", deviation_args->one_sided, "measure A -> B only");
  auto* signed_flag = deviation->add_flag("--signed", deviation_args->signed_mode,
                                          "signed distances: + outside B, - inside (B must be closed)");
  deviation
      ->add_flag("--ray", deviation_args->ray_mode,
                 "ray mode: first hit along the sample normal, both ways, within --max-distance")
      ->excludes(signed_flag);
  deviation
      ->add_option("--max-distance", deviation_args->max_distance,
                   "farther samples count as misses (mesh units, > 0)")
      ->check(CLI::PositiveNumber);
  deviation->add_option("--tolerance", deviation_args->tolerance, "report the share of |d| <= tolerance")
      ->capture_default_str();
  deviation->add_option("--bins", deviation_args->bins, "histogram bins")->capture_default_str();
  deviation->add_option("--groups", deviation_args->groups, "worst provenance groups to list")
      ->capture_default_str();
  deviation->add_option("--seed", deviation_args->seed, "random seed of the samples")->capture_default_str();
  deviation->add_option("--heatmap", deviation_args->heatmap_path,
                        "write A with its per-vertex deviation to this PLY (vertex 'quality' for MeshLab, "
                        "'scalar_deviation' for CloudCompare, colours; provenance in the header)");
  deviation->add_option(
      "--vtp", deviation_args->vtp_path,
      "write A with its deviation as point and cell data to this VTK PolyData file (ParaView)");
  deviation
      ->add_option("--units", deviation_args->units,
                   "length unit of the meshes, recorded in the written files (e.g. mm)")
      ->capture_default_str();
  deviation->add_option("--png", deviation_args->png_path, "write a picture of the heatmap to this PNG");
  deviation->add_option("--view", deviation_args->view, "picture view: iso, top, front")
      ->capture_default_str();
  deviation->add_option("--size", deviation_args->size, "picture size WIDTHxHEIGHT")->capture_default_str();
  deviation_args->json_option = add_json_option(*deviation, deviation_args->json_path, "the statistics");
  auto* range_option = deviation->add_option("--range", deviation_args->range, "fixed colour range LOW,HIGH")
                           ->delimiter(',')
                           ->expected(2);
  deviation->add_flag("--symmetric", deviation_args->symmetric, "colour range symmetric about zero")
      ->excludes(range_option);
  add_memory_cap_option(deviation, deviation_args->memory_cap_gib);
  deviation->callback([deviation_args] { run_deviation(*deviation_args); });

  auto render_args = std::make_shared<RenderArgs>();
  CLI::App* render = app.add_subcommand("render",
                                        "Render a mesh to PNG by ray casting: shaded, optionally coloured by "
                                        "a vertex scalar with a colour bar.");
  render->add_option("MESH", render_args->mesh_path, "mesh file (PLY, STL, OBJ)")->required();
  render->add_option("-o,--output", render_args->out_path, "PNG file to write")->required();
  render->add_option("--scalar", render_args->scalar, "vertex scalar to colour by (e.g. deviation)");
  render->add_option("--view", render_args->view, "iso, top or front")->capture_default_str();
  render->add_option("--size", render_args->size, "WIDTHxHEIGHT in pixels")->capture_default_str();
  render->add_option("--map", render_args->map, "auto, viridis or coolwarm")->capture_default_str();
  render->add_option("--unit", render_args->unit, "unit shown with the scale title");
  auto* render_range = render->add_option("--range", render_args->range, "fixed colour range LOW,HIGH")
                           ->delimiter(',')
                           ->expected(2);
  render->add_flag("--symmetric", render_args->symmetric, "colour range symmetric about zero")
      ->excludes(render_range);
  render->callback([render_args] { run_render(*render_args); });
}

}  // namespace morphmill
