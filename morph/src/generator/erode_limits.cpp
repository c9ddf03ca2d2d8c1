// SPDX-License-Identifier: Apache-2.0
// What a job may ask of the generator (erode.h): a tolerance the coordinates resolve, the memory
// cap, and the up-front memory estimate, from the job alone, made before anything large is built:
// the sweeps' facets dominate (each kept facet is carved, conformed and emitted; every facet is
// culled). Fitted to the peak resident memory of the bundled and reproducer jobs
// (tests/apps/erode_estimate_test.cpp holds it within a factor of 2).
#include <morph/erode.h>

#include <morph/error_budget.h>
#include <morph/exceptions.h>
#include <morph/path.h>
#include <morph/quantize.h>
#include <morph/sweep_segments.h>
#include <morph/tool_polytope.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace morph {

namespace {

// The process itself (libraries, the job, the output's writing); measured on single_slot.json.
constexpr double kBytesFixed = 45.0 * (1 << 20);
// Per facet of the sweep polytopes: its halfspace and box in the culling, and for the ones kept
// their exact polygons, cutters, conformed loops and output triangles. Measured 195-290 bytes
// over the bundled jobs (crossing_rose and helix_pocket the least, slots the most; 2026-11-29,
// after the pieces' and the vertices' planes went into tables), and far less where the joints
// cull most facets: 38 on 3D_Chips, 58 on bear.nc, 108 on cameo.nc.
constexpr double kBytesPerSweepFacet = 300.0;
// A mesh stock's triangle is a facet carved like a sweep's, with the mesh and its index beside it
// (the removed generator 1 measured 1400 bytes for the same on a 1M-triangle sphere stock).
constexpr double kBytesPerStockTriangle = 1000.0;

// Each thread carving holds the exact planes of the sweeps it met last (sweep_plane_cache.h: up to
// 64 MiB, 112 bytes a plane, about one per facet), the cutters' planes it made one at a time
// (carve_culled.cpp MadePlanes: up to 2^18 planes, ~100 bytes each in their pool, and the sides
// and plane slots of 4096 sweeps' facets, 5 bytes each) and the culling the faces of the last 1024 candidate
// sweeps (sweep_culling.cpp: about 80 bytes a facet); none more than every sweep's. The constants above were
// fitted on 2 threads; each further thread adds its own (at 64 threads about 8 GB on bear.nc at 0.01).
constexpr double kFittedThreads = 2.0;
double per_thread_bytes(double sweep_facets, double segments) {
  const double facets_per_sweep = sweep_facets / std::max(1.0, segments);
  return std::min(64.0 * (1 << 20), 112.0 * sweep_facets) + 100.0 * std::min(double(1 << 18), sweep_facets) +
         5.0 * std::min(4096.0, segments) * facets_per_sweep +
         80.0 * std::min(1024.0 * facets_per_sweep, sweep_facets);
}

/// A tolerance must span this many spacings of the doubles at the job's largest coordinate.
constexpr double kResolutionFactor = 1e6;

}  // namespace

void check_tolerance_resolves(const Job& job, double tolerance) {
  // The generators compare distances and signs in coordinates as large as the job's: a tolerance
  // within kResolutionFactor spacings of the doubles there cannot be met (at x = 1e15 doubles are
  // 0.125 apart, and a 0.01 tolerance gave open meshes of negative volume).
  double largest = 0.0;
  const Eigen::AlignedBox3d stock_box = bounds(job.stock);
  if (!stock_box.isEmpty())
    largest = std::max(stock_box.min().cwiseAbs().maxCoeff(), stock_box.max().cwiseAbs().maxCoeff());
  for (const Path& path : job.paths)
    for (const Move& move : path.moves)
      largest = std::max({largest, move.start.cwiseAbs().maxCoeff(), move.end.cwiseAbs().maxCoeff()});
  const double spacing = largest * std::numeric_limits<double>::epsilon();
  if (!(tolerance >= kResolutionFactor * spacing)) {
    std::ostringstream message;
    message << std::setprecision(3) << job.file << ": tolerance " << tolerance
            << " is below what the coordinates can resolve: at " << largest << " doubles are " << spacing
            << " apart, and the generator needs a tolerance of at least " << kResolutionFactor * spacing
            << " (" << kResolutionFactor * spacing / tolerance
            << " times the one asked for) there; move the job nearer the origin or raise the tolerance";
    throw InputError(message.str());
  }
}

void check_memory_cap(const ErodeOptions& options, double tolerance, double bytes, const std::string& what) {
  if (options.memory_cap_bytes == 0 || bytes <= double(options.memory_cap_bytes)) return;
  std::ostringstream message;
  message << "erode: at tolerance " << tolerance << " the job needs about " << std::fixed
          << std::setprecision(0) << bytes / double(1 << 20) << " MiB (" << what
          << "), over the memory cap of " << double(options.memory_cap_bytes) / double(1 << 20)
          << " MiB: raise the tolerance (memory grows about as 1 / tolerance) or the cap";
  throw LimitError(message.str());
}

ErodeEstimate estimate_erode(const Job& job, double tolerance) {
  ErodeEstimate estimate;
  // Segments as sweep_segments() makes them (straight runs joined), counted without listing them.
  const SweepCount sweeps = count_sweeps(job, error_budget(job, tolerance));
  estimate.segments = sweeps.segments;
  estimate.sweep_facets = sweeps.facets;
  if (job.stock.type == StockType::Mesh) estimate.stock_triangles = double(job.stock.mesh.triangles.size());
  const double threads = static_cast<double>(tbb::this_task_arena::max_concurrency());
  estimate.bytes =
      kBytesFixed + kBytesPerSweepFacet * estimate.sweep_facets +
      kBytesPerStockTriangle * estimate.stock_triangles +
      std::max(0.0, threads - kFittedThreads) * per_thread_bytes(estimate.sweep_facets, estimate.segments);
  return estimate;
}

}  // namespace morph
