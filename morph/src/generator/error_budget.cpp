// SPDX-License-Identifier: Apache-2.0
#include <morph/error_budget.h>
#include <morph/quantize.h>
#include <morph/sweep_segments.h>
#include <morph/tool_polytope.h>

#include <algorithm>
#include <map>

namespace morph {

SweepCount count_sweeps(const Job& job, const ErrorBudget& budget) {
  SweepCount count;
  // A sweep has the tool's facets (each at the start or at the end) and one parallelogram per
  // silhouette edge: about two per sector and two per meridian point.
  for (const auto& [tool, segments] : sweep_segment_counts(job, budget.chords, budget.grid_exponent)) {
    const ToolPolytopeSize size = tool_polytope_size(profile_of(job.tools.find(tool)->second), budget.tool);
    count.segments += segments;
    count.facets += segments * (double(size.facets) + 2.0 * (size.sectors + double(size.meridian_points)));
  }
  return count;
}

ErrorBudget error_budget(const Job& job, double tolerance) {
  const bool has_arcs = std::any_of(job.paths.begin(), job.paths.end(), [](const Path& path) {
    return std::any_of(path.moves.begin(), path.moves.end(), [](const Move& m) { return m.is_arc(); });
  });
  ErrorBudget budget;
  budget.chords = has_arcs ? 0.39 * tolerance : 0.0;
  budget.tool = 0.4 * tolerance;
  budget.stock = 0.2 * tolerance;
  budget.ends = 0.01 * tolerance;
  budget.grid_exponent = grid_exponent_for(budget.tool);
  return budget;
}

}  // namespace morph
