// SPDX-License-Identifier: Apache-2.0
// morphmill erode2d and verify2d: the paper's two-dimensional model (docs/planar.md).
#include <fmt/format.h>
#include <morph/planar_erosion.h>
#include <morphmill/planar_io.h>
#include <tbb/global_control.h>

#include <iostream>
#include <memory>
#include <optional>

#include "cli/cli_conventions.h"
#include "cli/commands.h"
#include "cli/terminal_progress.h"
#include "planar/planar_verify.h"

namespace morphmill {

namespace {

struct Erode2dOptions {
  std::string job_path;
  std::string out_path;
  std::string dilation_path;
  bool classical = false;
  int threads = 0;
};

void run_erode2d(const Erode2dOptions& options) {
  std::optional<tbb::global_control> threads;
  if (options.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, options.threads);
  const PlanarJob job = load_planar_job(options.job_path);
  for (const morph::Warning& w : job.warnings)
    std::cerr << "morphmill: warning: " << w.file << (w.line > 0 ? ":" + std::to_string(w.line) : "") << ": "
              << w.message << '\n';
  TerminalProgress progress;
  morph::planar::PlanarOptions planar;
  planar.progress = &progress;
  const morph::planar::PlanarResult result =
      options.classical ? morph::planar::classical_erosion(job.stock, job.radius, planar)
                        : morph::planar::erode(job.stock, job.moves, job.radius, planar);
  PlanarDrawing drawing;
  drawing.result = &result.region;
  drawing.stock = &job.stock;
  if (!options.classical) drawing.moves = &job.moves;
  drawing.title = job.name + (options.classical ? ": classical erosion" : ": X \\ (T + B)");
  write_planar_result(drawing, options.out_path);
  if (!options.dilation_path.empty()) {
    const morph::planar::PlanarResult dilation = morph::planar::dilate(job.moves, job.radius, planar);
    PlanarDrawing d;
    d.dilation = &dilation.region;
    d.stock = &job.stock;
    d.moves = &job.moves;
    d.title = job.name + ": T + B";
    write_planar_result(d, options.dilation_path);
  }
  const auto& s = result.stats;
  std::cout << fmt::format(
      "erode2d {}{}: disc radius {}, {} moves ({} near the stock)\n  {} piece(s), {} hole(s), area {:.12g}, "
      "perimeter {:.12g}\n  {} curves kept of {} pieces ({} candidate curves, {} intersections), {:.3f} s -> "
      "{}\n",
      job.name, options.classical ? " (classical erosion)" : "", job.radius, s.moves, s.moves_near_stock,
      result.region.pieces.size(), morph::planar::hole_count(result.region),
      morph::planar::area(result.region), morph::planar::perimeter(result.region), s.pieces_kept, s.pieces,
      s.candidate_curves, s.intersections, s.seconds, options.out_path);
}

}  // namespace

void register_planar_commands(CLI::App& app) {
  auto erode = std::make_shared<Erode2dOptions>();
  CLI::App* e = app.add_subcommand(
      "erode2d",
      "The paper's two-dimensional model, exact: the stock region minus the dilation of the trajectory by\n"
      "a disc, as lines and arcs, each with its provenance (stock element, or move and G-code line).\n"
      "The job is a planar job file (docs/planar.md); the output format follows the extension:\n"
      ".svg (picture with exact arcs), .dxf (LINE and ARC entities), .json (loops, pieces, areas).\n"
      "Example: morphmill erode2d data/planar/figure13.json -o out/figure13.svg");
  e->add_option("job", erode->job_path, "Planar job file (JSON, see docs/planar.md)")->required();
  e->add_option("-o,--output", erode->out_path, "Output: .svg, .dxf or .json")->required();
  e->add_option("--dilation", erode->dilation_path, "Also write the dilation T + B (.svg, .dxf or .json)");
  e->add_flag("--classical", erode->classical,
              "Write the classical erosion X - B instead (paper eq. 2-3: the contour a tool centre follows\n"
              "to finish the stock's profile from inside)");
  e->add_option("--threads", erode->threads, "Worker threads (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  e->callback([erode] { run_erode2d(*erode); });

  auto verify = std::make_shared<Verify2dOptions>();
  CLI::App* v = app.add_subcommand(
      "verify2d",
      "Compute the exact planar erosion and an independent Clipper reference (round offsets, arcs as\n"
      "chords), measure the exact deviation between them both ways and its convergence with the chord\n"
      "tolerance, and write pictures and a report. The verdict holds when both have the same pieces and\n"
      "holes and their boundaries are within twice the tolerance (chords within it; see docs/planar.md).\n"
      "Exit code 0 when the verdict holds, 1 when it does not, 2 for bad input.\n"
      "Example: morphmill verify2d data/planar/sheet.json -o out/sheet");
  v->add_option("job", verify->job_path, "Planar job file (JSON, see docs/planar.md)")->required();
  v->add_option("-o,--output", verify->out_dir, "Directory for the pictures, result files and report")
      ->required();
  auto json_path = std::make_shared<std::string>();
  CLI::Option* json_option = add_json_option(
      *v, *json_path,
      "the summary (report.json's content: areas, pieces, deviation, verdict; also when exit 1)");
  v->add_option("--tolerance", verify->tolerance, "Reference chord tolerance, job units (default: the job's)")
      ->check(CLI::PositiveNumber);
  v->callback([verify, json_path, json_option] {
    TerminalProgress progress;
    Verify2dOptions run = *verify;
    run.progress = &progress;
    const Verify2dOutcome o = run_verify2d(run);
    const bool json_wanted = json_option->count() > 0;
    if (json_wanted) write_json(verify2d_summary_json(o), *json_path);
    if (!(json_wanted && is_standard_output(*json_path)))
      std::cout << fmt::format(
          "verify2d {}: verdict {}\n  exact: {} piece(s), {} hole(s), area {:.12g}\n  reference: {} "
          "piece(s), "
          "{} "
          "hole(s), area {:.12g}\n  Hausdorff distance {:.3g} at chord tolerance {} (bound {})\n  report: "
          "{}/report.md\n",
          o.job.name, o.verdict() ? "HOLDS" : "DOES NOT HOLD", o.exact.region.pieces.size(),
          morph::planar::hole_count(o.exact.region), morph::planar::area(o.exact.region),
          o.reference.pieces.size(), morph::planar::hole_count(o.reference), morph::planar::area(o.reference),
          o.deviation.hausdorff(), o.tolerance, 2.0 * o.tolerance, run.out_dir);
    if (!o.verdict()) throw VerdictFailed();
  });
}

}  // namespace morphmill
