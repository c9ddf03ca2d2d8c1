// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file erode.h
/// The paper's secondary three-dimensional model: the boundary of the regularized partial erosion
/// X \ (T (+) B) built directly from the ordered tool positions, as a sum of surfaces (no solid
/// booleans, no voxels):
///   - side sweeps: the tool's contour generator perpendicular to each straight (sub-)move,
///     swept along it (the paper's arches);
///   - front sweeps: the tool's own surface at path ends and where the direction turns;
///   - cut surfaces: the stock's faces.
/// Every patch has an exact parametrisation. A point of a patch survives iff it is inside the stock
/// and outside every other move's swept volume (found through a bounding-volume hierarchy); each
/// patch is trimmed by marching squares in its parameter domain, with every trimming vertex placed
/// on the exact trimming curve by root finding on the exact swept-volume distances.
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
  /// Optional progress / interruption (stages "erode: patches", "erode: assemble").
  Progress* progress = nullptr;
  /// Refuse (LimitError, before the long stages) work estimated to need more memory than this,
  /// bytes; 0: no cap. The estimate comes from the job alone: segments after splitting arcs,
  /// then the patches' tessellation grids (ErodeStats::estimated_bytes).
  std::size_t memory_cap_bytes = 0;
  /// Generator 1 only: the most golden-section searches of the exact sweep distance its trimming
  /// may run (the bulk of its time where a tool's body nears many sweeps: deep pockets of a ball
  /// end); past it, erode throws SearchLimitError. 0: no limit. The count depends on the job and
  /// the tolerance alone, not on threads or timing, so whether a job passes it does too.
  std::uint64_t search_limit = 0;
};

/// How often one step of the surface's assembly fired. A fallback repairs what the construction
/// left wrong (its target is 0, and code that never fires goes); an exact step is part of the
/// construction itself (generator 2's limit of the perturbation), counted for insight.
struct StepCount {
  std::string name;  ///< snake_case, e.g. "rounding_flipped_edges"
  std::size_t count = 0;
  bool fallback = true;
};

struct ErodeStats {
  std::size_t moves = 0;                 ///< moves of the job
  std::size_t moves_touching_stock = 0;  ///< moves whose swept bounds meet the stock bounds
  std::size_t segments =
      0;  ///< straight pieces after splitting arcs by chord tolerance (generator 2: straight runs joined)
  std::size_t patches = 0;                  ///< parametric patches considered
  std::size_t patches_kept = 0;             ///< patches that left at least one triangle
  std::size_t triangles = 0;                ///< output triangles
  std::size_t vertices = 0;                 ///< output vertices
  std::size_t seam_splits = 0;              ///< boundary edges split at the other side's vertices
  std::size_t corner_holes = 0;             ///< holes closed where three patches meet
  std::size_t defects_repaired = 0;         ///< small open / non-manifold spots replaced by a fan
  std::size_t flat_components_removed = 0;  ///< closed zero-volume slivers left by tangent contacts
  std::size_t open_edges = 0;               ///< boundary edges left (0 for a closed surface)
  std::uint64_t searches = 0;     ///< generator 1: golden-section searches of the trimming's sweep distances
  double seconds_setup = 0.0;     ///< segments, patches, spatial index
  double seconds_trim = 0.0;      ///< evaluating and contouring the patches
  double seconds_assemble = 0.0;  ///< concatenation and welding
  double seconds_total = 0.0;
  double grid_cells = 0.0;       ///< cells of the patches' tessellation grids before trimming
  double estimated_bytes = 0.0;  ///< the up-front estimate of the peak memory
  /// Generator 2: CPU seconds of each stage summed over the threads, in stage order (what a long
  /// job spends where; empty for generator 1).
  std::vector<std::pair<std::string, double>> stage_cpu_seconds;
  /// Every counted step, fallbacks and exact steps, in a fixed order per generator (all listed,
  /// also when 0).
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

/// Computes the boundary of the regularized partial erosion of `job`. Supports sphere and ballend
/// tools, straight moves, arcs and helices (split into chords within half the tolerance), and box
/// and cylinder stock. Throws InputError for an unsupported tool or stock type or a non-positive
/// tolerance, Interrupted if options.progress asks to stop.
ErodeResult erode(const Job& job, const ErodeOptions& options = {});

}  // namespace morph
