// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file error_budget.h
/// How generator 2 spends the tolerance. Its surface departs from the exact one in three ways:
/// an arc swept as chords, the tool as a polytope, the stock (a cylinder's prism, a mesh's
/// vertices on a grid). A point of the surface is off by at most the chords' and the tool's
/// deviations where a sweep bounds it, by the stock's where a stock face does, and by all of them
/// where the two meet; so the three shares add up to the tolerance. A job without arcs has no
/// chords to pay for, and its tool takes their share too: about half the tool polytope's facets
/// for the same tolerance. A job with arcs splits the sweeps' share where it costs least.
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

/// The budget of `job` at `tolerance` (> 0, finite; job units): 0.2 of it to the stock, 0.8 to the
/// sweeps. A job without arcs gives those all to the tool; one with arcs splits them between the
/// chords and the tool, 0.05 to 0.4 of the tolerance to the chords in steps of 0.05, at the split
/// that makes the fewest sweep facets (count_sweeps): arcs that are few or flat take little. Throws
/// LimitError when no split gives a tool polytope (tool_polytope_size()).
ErrorBudget error_budget(const Job& job, double tolerance);

/// The segments (sweep_segments.h) and sweep polytope facets generator 2 makes for `job` with
/// `budget`, counted without listing or building them: its work, and most of its memory.
struct SweepCount {
  double segments = 0.0;
  double facets = 0.0;
};
SweepCount count_sweeps(const Job& job, const ErrorBudget& budget);

}  // namespace morph
