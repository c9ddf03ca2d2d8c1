// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file error_budget.h
/// How the generator spends the tolerance. Its surface departs from the exact one in three ways:
/// an arc swept as chords, the tool as a polytope, the stock (a cylinder's prism, a mesh's
/// vertices on a grid). A point of the surface is off by at most the chords' and the tool's
/// deviations where a sweep bounds it, by the stock's where a stock face does, and by all of them
/// where the two meet; so the three shares add up to at most the tolerance.
///
/// The tool keeps 0.4 of it even when a job has no arcs, and the rest is margin, because the
/// sweeps' displacement is not the surface's error everywhere: a ridge of material between two
/// sweeps meeting at an angle θ moves by the displacement / sin(θ/2), and a wall or pillar of
/// material thinner than twice the displacement can vanish, leaving exact surface as far from
/// the output as the feature is long. Giving the tool 0.8 (about 40% fewer sweep facets on
/// bear.nc) erased a V-bit's 0.03 mm pillar between seven grooves at tolerance 0.05 (stress seed
/// 43, case 516: the exact surface 0.75 mm from the output); at 0.4 it stands.
#include <morph/job.h>

namespace morph {

/// Shares of the tolerance, in job units.
struct ErrorBudget {
  double chords = 0.0;  ///< an arc's chords within this of it (0: the job has no arcs)
  double tool = 0.0;    ///< every tool polytope within this of its tool (tool_polytope.h)
  double stock = 0.0;   ///< a cylinder stock's prism, a mesh stock's grid (stock_polytope.h)
  /// Segment ends moved so that every sweep's planes are exact and no sub-share move is swept
  /// (settle_segment_ends(), sweep_segments.h).
  double ends = 0.0;
  /// The tool polytopes' grid, on which every segment's ends lie too (quantize.h).
  int grid_exponent = 0;
};

/// The budget of `job` at `tolerance` (> 0, finite; job units): 0.4 of it to the tool, 0.39 to
/// the chords when any move is an arc (0 otherwise), 0.2 to the stock and 0.01 to moving segment
/// ends (a chord's end moved adds to its chord's deviation).
ErrorBudget error_budget(const Job& job, double tolerance);

/// The segments (sweep_segments.h) and sweep polytope facets the generator makes for `job` with
/// `budget`, counted without listing or building them: its work, and most of its memory.
struct SweepCount {
  double segments = 0.0;
  double facets = 0.0;
};
SweepCount count_sweeps(const Job& job, const ErrorBudget& budget);

}  // namespace morph
