// SPDX-License-Identifier: Apache-2.0
// morphmill compare: the machined result (the generator's exact surface) against the design model.
#include <fmt/format.h>
#include <morph/erode.h>
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>
#include <raytest/heatmap.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "cli/cli_conventions.h"
#include "cli/commands.h"
#include "cli/memory_cap.h"
#include "cli/terminal_progress.h"
#include "io/deviation_files.h"
#include "io/provenance.h"
#include "verify/compare.h"
#include "verify/soundness.h"

namespace morphmill {

namespace {

struct CompareArgs {
  std::string job_path, design_path, out_dir;
  std::vector<double> band;
  double tolerance = 0.0;
  double resolution = 0.0;
  std::size_t face_samples = 100000;
  std::uint64_t seed = 1;
  std::string json_path;
  CLI::Option* json_option = nullptr;
  double memory_cap_gib = 8.0;
};

void print_comparison(const DesignComparison& c, const morph::Job& job, const std::string& design) {
  const std::string u = morph::to_string(job.units);
  fmt::print("compare {} against design {}\n", job.name, design);
  fmt::print("  sign: {}\n", raytest::kSignConvention);
  fmt::print("  band: {:+.6g} / {:+.6g} {}\n", c.band.low, c.band.high, u);
  const raytest::DeviationStats& s = c.per_point;
  fmt::print(
      "  points: {} (machined surface refined to {:.4g} {})  min {:+.6g}  max {:+.6g}  mean {:+.6g} {}\n",
      s.count, c.resolution, u, s.min, s.max, s.mean, u);
  fmt::print("  gouge {:.3f}%  within {:.3f}%  excess {:.3f}%\n", 100 * s.share_gouge,
             100 * s.share_within_band, 100 * s.share_excess);
  fmt::print("  regions: {} gouge, {} excess\n", c.gouge_regions, c.excess_regions);
  for (const DesignRegion& r : c.regions) {
    const auto& p = r.region.location;
    fmt::print("    {:<6} depth {:.6g} {} area {:.6g} {}^2 at ({:.4f}, {:.4f}, {:.4f})",
               raytest::to_string(r.region.kind), std::abs(r.region.worst), u, r.region.area, u, p.x(), p.y(),
               p.z());
    if (r.nearest_move >= 0)
      fmt::print("; nearest move {} ({} line {})", r.nearest_move, r.nearest_source, r.nearest_line);
    fmt::print("\n");
    for (const raytest::RegionSource& source : r.region.sources)
      fmt::print("      made by {} ({:+.6g})\n", provenance_text(source.tag), source.worst);
  }
  fmt::print("  verdict: {}\n", c.within_band() ? "WITHIN THE BAND" : "OUT OF THE BAND");
}

void run_compare(const CompareArgs& args) {
  const morph::Job job = load_job(args.job_path);
  const DesignSpec spec = load_design(args.job_path);
  const std::string design_path = args.design_path.empty() ? spec.path : args.design_path;
  if (design_path.empty())
    throw morph::InputError(args.job_path + ": the job names no design; give one with --design part.stl");
  CompareOptions options;
  options.band = args.band.empty() ? default_band(job, spec.low, spec.high)
                                   : raytest::ToleranceBand{args.band.at(0), args.band.at(1)};
  options.resolution = args.resolution;
  options.face_samples = args.face_samples;
  options.seed = args.seed;
  // Bad input fails before the long work.
  if (options.band.empty() || options.band.low > 0 || options.band.high < 0)
    throw morph::InputError(
        fmt::format("--band: expected LOW,HIGH with LOW <= 0 <= HIGH, not both 0 (got {},{})",
                    options.band.low, options.band.high));
  const morph::TriangleMesh design = read_mesh(design_path);

  TerminalProgress progress;
  morph::ErodeOptions erode_options;
  erode_options.tolerance = args.tolerance > 0 ? args.tolerance : job.tolerance;
  erode_options.progress = &progress;
  erode_options.memory_cap_bytes = memory_cap_bytes(args.memory_cap_gib);
  const morph::ErodeResult machined = [&] {
    try {
      return morph::erode(job, erode_options);
    } catch (const morph::LimitError& e) {
      throw morph::LimitError(args.job_path + ": " + e.what() + " (--memory-cap " +
                              describe_bytes(double(erode_options.memory_cap_bytes)) + ")");
    }
  }();
  const DesignComparison comparison = compare_with_design(job, machined.mesh, design, options);
  const bool json_on_stdout = args.json_option->count() > 0 && is_standard_output(args.json_path);
  if (!json_on_stdout) print_comparison(comparison, job, design_path);

  std::vector<std::string> inputs = job_input_files(job);
  inputs.push_back(design_path);
  const Provenance provenance = make_provenance(inputs,
                                                {{"command", "compare"},
                                                 {"band", {options.band.low, options.band.high}},
                                                 {"tolerance", erode_options.tolerance},
                                                 {"resolution", args.resolution},
                                                 {"samples", args.face_samples},
                                                 {"seed", args.seed}},
                                                morph::to_string(job.units));
  nlohmann::json summary;
  summary["format"] = "morphmill-compare";
  summary["format_version"] = 1;  // docs/summary-schema.md
  summary["provenance"] = to_json(provenance);
  summary["units"] = morph::to_string(job.units);
  summary.update(comparison_to_json(comparison, job));
  summary["job"] = {{"name", job.name}, {"file", job.file}};
  summary["design"] = design_path;

  if (!args.out_dir.empty()) {
    namespace fs = std::filesystem;
    std::error_code error;
    fs::create_directories(args.out_dir, error);
    if (error)
      throw morph::IoError(args.out_dir + ": cannot create the output directory: " + error.message());
    const fs::path dir(args.out_dir);
    morph::write_file_atomically((dir / "compare.json").string(), summary.dump(2) + "\n");
    morph::TriangleMesh heat = comparison.refined.mesh;
    const double reach = std::max(-comparison.band.low, comparison.band.high) * 2.0;
    raytest::apply_heatmap(heat, "deviation", comparison.point_values, raytest::ColorMap::CoolWarm,
                           {-reach, reach});
    write_deviation_ply(heat, "deviation", (dir / "machined_vs_design.ply").string(), provenance);
    write_deviation_vtp(heat, "deviation", (dir / "machined_vs_design.vtp").string(), provenance);
    if (!json_on_stdout)
      fmt::print("  wrote {}/compare.json, machined_vs_design.ply and .vtp\n", args.out_dir);
  }
  if (args.json_option->count() > 0) write_json(summary, args.json_path);
  if (!comparison.within_band()) throw VerdictFailed();
}

}  // namespace

void register_compare_command(CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  CLI::App* compare = app.add_subcommand(
      "compare",
      "Compare the machined result of a job (the generator's exact surface) with the design model the\n"
      "program was written for. Signed: + excess (material left where the design wants none), - gouge\n"
      "(material removed where the design wants it). Every point of the machined surface is classified\n"
      "gouge / within / excess against the band; out-of-band points are merged into regions with their\n"
      "area, largest depth, location, the moves whose faces they lie on and the move that came nearest.\n"
      "Exit code 0 when everything is within the band, 1 when not, 2 for bad input.\n"
      "Example: morphmill compare data/jobs/design_gouge_excess.json --output out/compare");
  compare->add_option("job", args->job_path, "Job file (JSON, see docs/job-format.md)")
      ->required()
      ->check(CLI::ExistingFile);
  compare->add_option("--design", args->design_path,
                      "Design mesh (STL, PLY, OBJ; job units); default: the job's 'design'");
  compare
      ->add_option("--band", args->band,
                   "Allowed signed deviation LOW,HIGH in job units, e.g. -0.02,0.1 (default: the job's, else "
                   "-/+ 5 x tolerance)")
      ->delimiter(',')
      ->expected(2);
  compare->add_option("--tolerance", args->tolerance, "Generator tolerance in job units (default: the job's)")
      ->check(CLI::PositiveNumber);
  compare
      ->add_option("--resolution", args->resolution,
                   "Longest edge of the refined machined surface, job units (default: diagonal / 400)")
      ->check(CLI::PositiveNumber);
  compare->add_option("--samples", args->face_samples, "Area-uniform samples per surface for the statistics")
      ->capture_default_str();
  compare->add_option("--seed", args->seed, "Seed of the surface sampling")->capture_default_str();
  compare->add_option("-o,--output", args->out_dir,
                      "Directory for compare.json and machined_vs_design.ply/.vtp");
  args->json_option =
      add_json_option(*compare, args->json_path, "the summary (compare.json's content; also when exit 1)");
  add_retired_generator_option(*compare);
  add_memory_cap_option(compare, args->memory_cap_gib);
  compare->callback([args] { run_compare(*args); });
}

}  // namespace morphmill
