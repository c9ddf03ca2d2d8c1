// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file error_budget.h
/// How generator 2 spends the tolerance. Its surface departs from the exact one in three ways:
/// an arc swept as chords, the tool as a polytope, the stock (a cylinder's prism, a mesh's
/// vertices on a grid). A point of the surface is off by at most the chords' and the tool's
/// deviations where a sweep bounds it, by the stock's where a stock face does, and by all of them
/// where the two meet; so the three shares add up to the tolerance. A job without arcs has no
/// chords to pay for, and its tool takes their share too: about half the tool polytope's facets,
/// and half generator 2's work, for the same tolerance.
#include <morph/job.h>

namespace morph {

/// Shares of the tolerance, in job units.
struct ErrorBudget {
  double chords = 0.0;  ///< an arc's chords within this of it (0: the job has no arcs)
  double tool = 0.0;    ///< every tool polytope within this of its tool (tool_polytope.h)
  double stock = 0.0;   ///< a cylinder stock's prism, a mesh stock's grid (stock_polytope.h)
  /// The tool polytopes' grid, on which every segment's ends lie too (quantize.h).
  int grid_exponent = 0;
};

/// The budget of `job` at `tolerance` (> 0, finite; job units): 0.4 of it to the chords and 0.4
/// to the tool when any move is an arc, else 0.8 to the tool; 0.2 to the stock.
ErrorBudget error_budget(const Job& job, double tolerance);

}  // namespace morph
