// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file erode.h
/// The paper's secondary three-dimensional model: the boundary of the regularized partial erosion
/// X \ (T (+) B) built directly from the ordered tool positions (no solid booleans, no voxels), as
/// the boundary of the stock minus the union of the moves' convex sweep polytopes, closed, oriented
/// and manifold by construction (exact plane predicates and one tie order: carve.h, conform.h,
/// emit.h). Arcs become chords and the tool a polytope, each within its share of the tolerance
/// (error_budget.h, tool_polytope.h). The culling stage (sweep_culling.h) decides which facets and
/// cutters the exact carving sees (carve_culled.h), in parallel under options.policy. A box stock
/// is its six planes; a cylinder a prism within the stock's share of it (stock_polytope.h), carved
/// by the same code; a mesh stock its triangles, their vertices on a grid within that share
/// (stock_mesh.h), the sweeps' pieces kept where inside it.
#include <morph/job.h>
#include <morph/mesh.h>
#include <morph/parallel.h>
#include <morph/progress.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace morph {

struct ErodeOptions {
  /// Largest allowed distance between the output and the exact boundary, job units; 0 uses
  /// Job::tolerance. Half of it goes to the tessellation of curved patches (chord error), half
  /// to the trimming curves and the chords of arcs.
  double tolerance = 0.0;
  /// Patches are independent and processed in parallel; the output bytes do not depend on it.
  ExecutionPolicy policy = ExecutionPolicy::Parallel;
  /// Optional progress / interruption.
  Progress* progress = nullptr;
  /// Refuse (LimitError, before the long stages) work estimated to need more memory than this,
  /// bytes; 0: no cap. The estimate comes from the job alone (estimate_erode(),
  /// ErodeStats::estimated_bytes).
  std::size_t memory_cap_bytes = 0;
};

/// How often one step of the surface's assembly fired. A fallback repairs what the construction
/// left wrong (its target is 0, and code that never fires goes); an exact step is part of the
/// construction itself (the limit of the perturbation), counted for insight.
struct StepCount {
  std::string name;  ///< snake_case, e.g. "rounding_flipped_edges"
  std::size_t count = 0;
  bool fallback = true;
};

struct ErodeStats {
  std::size_t moves = 0;                 ///< moves of the job
  std::size_t moves_touching_stock = 0;  ///< moves whose swept bounds meet the stock bounds
  std::size_t segments = 0;      ///< straight pieces: arcs as chords, straight runs joined (sweep_segments.h)
  std::size_t patches = 0;       ///< faces considered: every sweep facet and the stock's faces
  std::size_t patches_kept = 0;  ///< carved pieces kept
  std::size_t triangles = 0;     ///< output triangles
  std::size_t vertices = 0;      ///< output vertices
  double seconds_setup = 0.0;    ///< segments, tool polytopes, stock
  double seconds_trim = 0.0;     ///< culling and exact carving
  double seconds_assemble = 0.0;  ///< conforming, the limit and the triangles
  double seconds_total = 0.0;
  double estimated_bytes = 0.0;  ///< the up-front estimate of the peak memory
  /// CPU seconds of each stage summed over the threads, in stage order (what a long job spends where).
  std::vector<std::pair<std::string, double>> stage_cpu_seconds;
  /// Every counted step, fallbacks and exact steps, in a fixed order (all listed, also when 0).
  std::vector<StepCount> steps;
};

/// Sum of the counts of the fallbacks among `stats.steps`.
inline std::size_t fallbacks_fired(const ErodeStats& stats) {
  std::size_t fired = 0;
  for (const StepCount& step : stats.steps)
    if (step.fallback) fired += step.count;
  return fired;
}

struct ErodeResult {
  TriangleMesh mesh;  ///< tagged with FaceTag provenance, wound outward
  ErodeStats stats;
};

/// Throws LimitError when `bytes`, an up-front estimate of the peak memory at `tolerance`, is over
/// options.memory_cap_bytes (0: no cap); the message names the estimate, `what` it counts, the cap,
/// and what would lower it.
void check_memory_cap(const ErodeOptions& options, double tolerance, double bytes, const std::string& what);

/// Throws InputError naming job.file when `tolerance` is below what the doubles resolve at the
/// job's largest coordinate (the stock's and the moves'), with the tolerance that would do.
void check_tolerance_resolves(const Job& job, double tolerance);

/// Computes the boundary of the regularized partial erosion of `job`: any stock, any tool of
/// revolution with a profile. Throws InputError for a non-positive tolerance, a tool without a
/// profile or a mesh stock it cannot make exact (not a closed 2-manifold, degenerate on its grid,
/// coordinates too large; stock_mesh.h), LimitError over options.memory_cap_bytes, Interrupted if
/// options.progress asks to stop.
ErodeResult erode(const Job& job, const ErodeOptions& options = {});

/// The up-front estimate, from the job alone, made before anything large is built: the sweeps'
/// facets dominate (each kept facet is carved, conformed and emitted; every facet is culled).
struct ErodeEstimate {
  double segments = 0.0;         ///< straight pieces: arcs as chords, straight runs joined (sweep_segments.h)
  double sweep_facets = 0.0;     ///< facets of all the sweep polytopes
  double stock_triangles = 0.0;  ///< of a mesh stock
  double bytes = 0.0;            ///< estimated peak resident memory of the process
};

/// The estimate at `tolerance` (job units; the tool polytopes and arc chords within their shares
/// of it, error_budget.h, as erode builds them). Throws LimitError when a tool polytope alone would
/// be too large.
ErodeEstimate estimate_erode(const Job& job, double tolerance);

}  // namespace morph
