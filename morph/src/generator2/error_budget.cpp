// SPDX-License-Identifier: Apache-2.0
#include <morph/error_budget.h>
#include <morph/exceptions.h>
#include <morph/quantize.h>
#include <morph/sweep_segments.h>
#include <morph/tool_polytope.h>

#include <algorithm>
#include <map>
#include <optional>

namespace morph {

SweepCount count_sweeps(const Job& job, const ErrorBudget& budget) {
  SweepCount count;
  // A sweep has the tool's facets (each at the start or at the end) and one parallelogram per
  // silhouette edge: about two per sector and two per meridian point.
  for (const auto& [tool, segments] : sweep_segment_counts(job, budget.chords, budget.grid_exponent)) {
    const ToolPolytopeSize size = tool_polytope_size(job.tools.find(tool)->second.profile, budget.tool);
    count.segments += segments;
    count.facets += segments * (double(size.facets) + 2.0 * (size.sectors + double(size.meridian_points)));
  }
  return count;
}

ErrorBudget error_budget(const Job& job, double tolerance) {
  const bool has_arcs = std::any_of(job.paths.begin(), job.paths.end(), [](const Path& path) {
    return std::any_of(path.moves.begin(), path.moves.end(), [](const Move& m) { return m.is_arc(); });
  });
  auto split = [&](double chords) {
    ErrorBudget budget;
    budget.chords = chords;
    budget.tool = 0.8 * tolerance - chords;
    budget.stock = 0.2 * tolerance;
    budget.grid_exponent = grid_exponent_for(budget.tool);
    return budget;
  };
  if (!has_arcs) return split(0.0);
  // Finer chords make more segments, a finer tool more facets to each: of the splits from 0.05 to
  // 0.4 of the tolerance to the chords, the one with the fewest sweep facets (the generator's
  // work), the coarser chords on a tie. A split the tool polytope cannot be made for is skipped.
  std::optional<ErrorBudget> best;
  double fewest = 0.0;
  std::optional<LimitError> refused;
  for (int k = 8; k >= 1; --k) {
    const ErrorBudget budget = split(0.05 * k * tolerance);
    try {
      const double facets = count_sweeps(job, budget).facets;
      if (!best || facets < fewest) best = budget, fewest = facets;
    } catch (const LimitError& e) {
      refused = e;
    }
  }
  if (!best) throw *refused;
  return *best;
}

}  // namespace morph
