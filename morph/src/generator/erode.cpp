// SPDX-License-Identifier: Apache-2.0
#include <morph/carve_culled.h>
#include <morph/conform.h>
#include <morph/degenerate_collapse.h>
#include <morph/emit.h>
#include <morph/erode.h>
#include <morph/error_budget.h>
#include <morph/exceptions.h>
#include <morph/quantize.h>
#include <morph/sweep_polytope.h>
#include <morph/sweep_segments.h>
#include <morph/tool_polytope.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <map>
#include <memory>

namespace morph {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Moving segment ends within the budget (every plane exact, no sub-share move) is part of the
// construction; so are the limit step's merges, removals and zips (the construction's ε → 0).
// What the limit keeps apart or leaves flat, and every change the rounding to doubles makes, is a
// fallback.
std::vector<StepCount> steps_counted(const SettledEnds& settled, const LimitCounts& limit,
                                     const EmitCounts& rounding) {
  return {{"ends_aligned", settled.aligned, false},
          {"short_segments_collapsed", settled.collapsed, false},
          {"limit_merged_vertices", limit.merged_vertices, false},
          {"limit_removed_polygons", limit.removed_polygons, false},
          {"limit_zipped_slivers", limit.zipped_slivers, false},
          {"limit_kept_apart", limit.kept_apart, true},
          {"limit_flat_polygons_left", limit.flat_polygons_left, true},
          {"limit_unsettled", limit.unsettled, true},
          {"rounding_collapsed_edges", rounding.collapsed_edges, true},
          {"rounding_flipped_edges", rounding.flipped_edges, true},
          {"rounding_rerounded_vertices", rounding.rerounded_vertices, true},
          {"rounding_misoriented_left", rounding.misoriented_left, true}};
}

// CPU seconds of the process, all threads.
double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

ErodeResult erode(const Job& job, const ErodeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  // 0 is the job's; a negative or non-finite tolerance is bad input, not the job's by accident.
  const double tolerance = options.tolerance == 0.0 ? job.tolerance : options.tolerance;
  if (!(tolerance > 0.0) || !std::isfinite(tolerance))
    throw InputError(job.file + ": erode: the tolerance must be positive, got " + std::to_string(tolerance));
  check_tolerance_resolves(job, tolerance);
  Progress& progress = options.progress ? *options.progress : null_progress();

  ErodeResult result;
  ErodeStats& stats = result.stats;
  // What the job will cost, before anything large is built.
  const ErodeEstimate estimate = estimate_erode(job, tolerance);
  stats.estimated_bytes = estimate.bytes;
  check_memory_cap(options, tolerance, estimate.bytes,
                   std::to_string(std::llround(estimate.segments)) +
                       " segments (arcs as chords, straight runs joined), " +
                       std::to_string(std::llround(estimate.sweep_facets)) + " sweep facets, " +
                       std::to_string(std::llround(estimate.stock_triangles)) + " stock triangles");
  stats.moves = job.move_count();
  // Ends on the tools' grid (quantize.h), so the sweeps' planes are exact there; straight runs
  // joined (sweep_segments.h).
  const ErrorBudget budget = error_budget(job, tolerance);
  std::vector<SweepSegment> segments = sweep_segments(job, budget.chords, budget.grid_exponent);

  // One polytope per tool, within its share of the tolerance of the exact tool.
  std::map<int, std::unique_ptr<SweepPolytopeBuilder>> builders;
  std::map<int, std::int64_t> largest_step;
  for (const SweepSegment& s : segments)
    if (!builders.count(s.tool)) {
      auto builder = std::make_unique<SweepPolytopeBuilder>(
          tool_polytope(profile_of(job.tool_of(*job.moves()[s.move])), budget.tool).polytope);
      largest_step[s.tool] = builder->largest_exact_step();
      builders.emplace(s.tool, std::move(builder));
    }
  // Every sweep's planes exact, long moves in general directions too; no sub-share moves.
  const SettledEnds settled = settle_segment_ends(segments, largest_step, budget.grid_exponent, budget.ends);
  stats.segments = segments.size();
  // The stock's share: a cylinder's prism, a mesh's vertices on a grid.
  const StockPolytope stock_polytope = generator2_stock(job.stock, budget.stock);
  const Eigen::AlignedBox3d stock = stock_polytope.bounds;
  std::vector<CarveSweep> sweeps;
  std::vector<std::int32_t> move_index, move_line;
  for (const SweepSegment& s : segments) {
    sweeps.push_back(CarveSweep{builders.at(s.tool).get(), s.from, s.to});
    move_index.push_back(s.move);
    move_line.push_back(s.line);
  }
  // A segment stands for its first move up to the next segment's (a joined run, an arc's chords).
  const std::vector<Eigen::AlignedBox3d> boxes = sweep_boxes(sweeps);
  std::int64_t counted_up_to = -1;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (!boxes[i].intersects(stock)) continue;
    const std::int64_t first = std::max<std::int64_t>(segments[i].move, counted_up_to + 1);
    const std::int64_t last = i + 1 < segments.size()
                                  ? std::max<std::int64_t>(segments[i + 1].move - 1, segments[i].move)
                                  : static_cast<std::int64_t>(stats.moves) - 1;
    if (last >= first) stats.moves_touching_stock += static_cast<std::size_t>(last - first + 1);
    counted_up_to = std::max(counted_up_to, last);
  }
  stats.seconds_setup = seconds_since(start);

  if (progress.interrupted()) throw Interrupted("erode: interrupted");
  CarveStages stages;
  CarvedPieces pieces = carve_culled(stock_polytope, sweeps, options.policy, &stages, &progress);
  stats.patches = static_cast<std::size_t>(stages.culling.facets) + stock_face_count(stock_polytope);
  stats.patches_kept = pieces.size();
  stats.seconds_trim = seconds_since(start) - stats.seconds_setup;

  double cpu = process_cpu_seconds();
  ConformedSurface surface = conform(pieces, options.policy);
  pieces = CarvedPieces();  // the surface holds what the later steps need
  const double conform_cpu = process_cpu_seconds() - cpu;
  cpu = process_cpu_seconds();
  const LimitSurface limit = collapse_degenerates(std::move(surface));
  EmitCounts rounding;
  result.mesh = emit(limit, move_index, move_line, &rounding, options.policy,
                     [&](std::int32_t sweep, std::int32_t facet) {
                       const CarveSweep& s = sweeps[static_cast<std::size_t>(sweep)];
                       return is_cap(*s.tool, s.from, s.to, facet);
                     });
  stats.stage_cpu_seconds = {{"cull", stages.seconds_cull},
                             {"kept_facets", stages.seconds_facets},
                             {"stock_faces", stages.seconds_stock},
                             {"conform", conform_cpu},
                             {"limit_and_emit", process_cpu_seconds() - cpu}};
  stats.steps = steps_counted(settled, limit.counts, rounding);
  stats.triangles = result.mesh.triangle_count();
  stats.vertices = result.mesh.vertex_count();
  stats.seconds_total = seconds_since(start);
  stats.seconds_assemble = stats.seconds_total - stats.seconds_setup - stats.seconds_trim;
  return result;
}

}  // namespace morph
