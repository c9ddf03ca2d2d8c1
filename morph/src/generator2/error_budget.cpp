// SPDX-License-Identifier: Apache-2.0
#include <morph/error_budget.h>
#include <morph/quantize.h>

#include <algorithm>

namespace morph {

ErrorBudget error_budget(const Job& job, double tolerance) {
  const bool has_arcs = std::any_of(job.paths.begin(), job.paths.end(), [](const Path& path) {
    return std::any_of(path.moves.begin(), path.moves.end(), [](const Move& m) { return m.is_arc(); });
  });
  ErrorBudget budget;
  budget.chords = has_arcs ? 0.4 * tolerance : 0.0;
  budget.tool = 0.8 * tolerance - budget.chords;
  budget.stock = 0.2 * tolerance;
  budget.grid_exponent = grid_exponent_for(budget.tool);
  return budget;
}

}  // namespace morph
