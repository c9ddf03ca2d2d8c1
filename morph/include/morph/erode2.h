// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file erode2.h
/// Generator 2 (issue 18): the boundary of the stock minus the union of the moves' convex sweep
/// polytopes, closed, oriented and manifold by construction (exact plane predicates and one tie
/// order: carve.h, conform.h, emit.h). Arcs become chords within 0.4 of the tolerance, the tool a
/// polytope within 0.4 of it (tool_polytope.h). The culling stage (sweep_culling.h) decides which
/// facets and cutters the exact carving sees (carve_culled.h), in parallel under options.policy.
/// A box stock is its six planes; a cylinder a prism within 0.2 of the tolerance of it
/// (stock_polytope.h), carved by the same code.
#include <morph/erode.h>

namespace morph {

/// Same contract as erode() for the jobs it supports: box or cylinder stock, any tool of revolution
/// with a profile. Throws InputError for a mesh stock or a tool without a profile.
ErodeResult erode2(const Job& job, const ErodeOptions& options = {});

}  // namespace morph
