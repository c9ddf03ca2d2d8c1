// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file erode_limits.h
/// What a job may ask of a generator (erode.h declares the checks both use: the memory cap, a
/// tolerance the coordinates resolve), and generator 2's up-front memory estimate, from the job alone, made
/// before anything large is built: the sweeps' facets dominate (each kept facet is carved, conformed and
/// emitted; every facet is culled). Fitted to the peak resident memory of the bundled and reproducer jobs
/// (tests/apps/erode_estimate_test.cpp holds it within a factor of 2).
#include <morph/erode.h>
#include <morph/job.h>

namespace morph {

struct Erode2Estimate {
  double segments = 0.0;         ///< straight pieces after splitting arcs into chords
  double sweep_facets = 0.0;     ///< facets of all the sweep polytopes
  double stock_triangles = 0.0;  ///< of a mesh stock
  double bytes = 0.0;            ///< estimated peak resident memory of the process
};

/// The estimate at `tolerance` (job units; the tool polytopes and arc chords within 0.4 of it,
/// as erode2 builds them). Throws LimitError when a tool polytope alone would be too large.
Erode2Estimate estimate_erode2(const Job& job, double tolerance);

}  // namespace morph
