// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file erode2.h
/// Generator 2 (issue 18): the boundary of the stock minus the union of the moves' convex sweep
/// polytopes, closed, oriented and manifold by construction (exact plane predicates and one tie
/// order: carve.h, conform.h, emit.h). Arcs become chords and the tool a polytope, each within its
/// share of the tolerance (error_budget.h, tool_polytope.h). The culling stage (sweep_culling.h) decides which
/// facets and cutters the exact carving sees (carve_culled.h), in parallel under options.policy.
/// A box stock is its six planes; a cylinder a prism within the stock's share of it
/// (stock_polytope.h), carved by the same code; a mesh stock its triangles, their vertices on a
/// grid within that share (stock_mesh.h), the sweeps' pieces kept where inside it.
#include <morph/erode.h>

namespace morph {

/// Same contract as erode() for the jobs it supports: any stock, any tool of revolution with a
/// profile. Throws InputError for a tool without a profile or a mesh stock it cannot make exact
/// (not a closed 2-manifold, degenerate on its grid, coordinates too large; stock_mesh.h).
ErodeResult erode2(const Job& job, const ErodeOptions& options = {});

/// Generator 2's up-front estimate, from the job alone, made before anything large is built: the
/// sweeps' facets dominate (each kept facet is carved, conformed and emitted; every facet is culled).
struct Erode2Estimate {
  double segments = 0.0;         ///< straight pieces: arcs as chords, straight runs joined (sweep_segments.h)
  double sweep_facets = 0.0;     ///< facets of all the sweep polytopes
  double stock_triangles = 0.0;  ///< of a mesh stock
  double bytes = 0.0;            ///< estimated peak resident memory of the process
};

/// The estimate at `tolerance` (job units; the tool polytopes and arc chords within their shares
/// of it, error_budget.h, as erode2 builds them). Throws LimitError when a tool polytope alone would be too large.
Erode2Estimate estimate_erode2(const Job& job, double tolerance);

}  // namespace morph
