// SPDX-License-Identifier: Apache-2.0
#pragma once
// `morphmill verify`: the generator, the reference and the deviation measurement on one job,
// with a verdict and a report a person reads.
#include <morph/erode.h>
#include <morph/job.h>
#include <morph/progress.h>
#include <morph/sweep_distance.h>
#include <morph/topology.h>
#include <raytest/deviation.h>
#include <raytest/regions.h>
#include <vdb_ref/reference.h>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>
#include "io/provenance.h"
#include "verify/compare.h"
#include "verify/pieces.h"

namespace morphmill {

struct VerifyOptions {
  std::string job_path;
  std::string out_dir;
  double voxel_size = 0.0;  ///< reference voxel, job units; 0 picks one from the tools (see auto_voxel_size)
  double tolerance = 0.0;   ///< generator tolerance, job units; 0 uses the job's
  std::size_t face_samples = 100000;  ///< area-uniform samples per surface, on top of every vertex
  std::uint64_t seed = 1;
  int image_width = 1200, image_height = 900;  ///< pixels of each picture
  /// Check only the reference against the exact surface (the generator is not run).
  bool reference_only = false;
  /// The generator and the reference each refuse (LimitError, before computing) work estimated
  /// to need more than this many bytes; 0 keeps their defaults (no generator cap, 8 GiB).
  std::size_t memory_cap_bytes = 0;
  morph::Progress* progress = nullptr;
};

/// Timing and memory of one stage.
struct StageRecord {
  std::string name;
  double seconds = 0.0;
  double peak_rss_mib = 0.0;  ///< process peak resident memory after the stage
};

/// A gouge or excess region of the generator's surface against one truth, out of `band`.
struct RegionRecord {
  std::string against;  ///< "exact surface" or "reference"
  raytest::ToleranceBand band;
  raytest::DeviationRegion region;
};

/// The sample that decided a check, and where it came from.
struct WorstPlace {
  Eigen::Vector3d position;
  double deviation = 0.0;
  morph::FaceTag tag;
  std::string against;  ///< "exact surface" or "reference"
};

struct VerifyOutcome {
  morph::Job job;
  double tolerance = 0.0;
  double voxel_size = 0.0;
  std::vector<StageRecord> stages;
  std::size_t morph_triangles = 0, reference_triangles = 0, reference_active_voxels = 0;
  morph::TopologyReport morph_topology, reference_topology;
  std::vector<PieceRecord> morph_pieces, reference_pieces;
  raytest::OneSidedDeviation morph_to_reference, reference_to_morph;
  raytest::OneSidedDeviation morph_to_exact, reference_to_exact;
  /// Points of the exact surface to the generator's mesh, signed (+ where the exact surface lies
  /// outside the generator's solid).
  raytest::DeviationStats exact_to_morph;
  std::vector<WorstPlace> worst;  ///< the place that decided the agreement check
  /// Out-of-band regions of the generator's (refined) surface, deepest first, at most 10 per truth;
  /// filled by run_verify, with the counts of all of them.
  std::vector<RegionRecord> regions;
  std::size_t exact_regions = 0, reference_regions = 0;
  double region_resolution = 0.0;  ///< longest edge of the refined surface the regions are on
  /// The verdict and its parts.
  bool generator_within_tolerance = false;
  bool sides_agree = false;
  bool pieces_match = false;
  /// Pieces of either side under (2 voxels)^3, which the reference's voxels miss, swell or cut off
  /// at a narrow neck, judged by the exact field instead (match_pieces): the generator's chips
  /// freed by undercutting passes, the reference's pieces the exact solid joins to more of itself.
  /// 0 when the pieces matched without it.
  std::size_t pieces_below_resolution = 0;
  double agreement_bound = 0.0;  ///< tolerance + sqrt(3) * voxel
  /// Largest generator<->reference deviation over the samples where the surface is resolvable at
  /// the voxel size (no surface within two voxels faces against the sample: no acute wedge, thin
  /// wall or narrow gap there), and how many samples were left out as unresolvable.
  double resolvable_hausdorff = 0.0;
  std::size_t unresolvable_samples = 0, agreement_samples = 0;
  /// The machined result against the design the job names (design_path empty when it names none);
  /// its per-point arrays are dropped once written.
  std::string design_path;
  DesignComparison design;
  bool design_within_band() const { return design_path.empty() || design.within_band(); }
  /// Why the generator was not run ("" when it was): --reference-only was given.
  std::string generator_skipped;
  /// What the generator counted (morph::ErodeStats::steps): its fallbacks and exact steps.
  std::vector<morph::StepCount> generator_steps;
  /// Reference against the exact surface (judged when the generator is not run): the largest
  /// deviation over the samples where the surface is resolvable at the voxel size, its bound
  /// sqrt(3) * voxel, and whether it holds.
  double reference_resolvable_max = 0.0, reference_bound = 0.0;
  std::size_t reference_resolvable_samples = 0;
  bool reference_converges = false;
  /// The whole verdict: the generator's checks and the design's band; with the generator not run
  /// (--reference-only), the reference's check.
  bool verdict() const {
    if (!generator_skipped.empty()) return reference_converges;
    return generator_within_tolerance && sides_agree && pieces_match && design_within_band();
  }
  std::vector<std::string> files;  ///< written into out_dir, relative names
  /// Who made these outputs from what (filled by run_verify; written into every file).
  Provenance provenance;
};

/// What evaluate_job needs: the verify pipeline without any file output.
struct EvaluateOptions {
  double voxel_size = 0.0;            ///< reference voxel, job units; 0 picks one with auto_voxel_size
  double tolerance = 0.0;             ///< generator tolerance, job units; 0 uses the job's
  std::size_t face_samples = 100000;  ///< area-uniform samples per surface, on top of every vertex
  std::uint64_t seed = 1;
  morph::Progress* progress = nullptr;
  std::string vdb_output_path;  ///< if not empty, the reference level set is also written there
  std::vector<std::pair<std::string, std::string>> vdb_metadata;  ///< stored with that grid
  bool reference_only = false;                                    ///< see VerifyOptions::reference_only
  std::size_t reference_memory_cap_bytes = std::size_t(8)
                                           << 30;  ///< vdb_ref::ReferenceOptions::memory_cap_bytes
  std::size_t generator_memory_cap_bytes = 0;      ///< morph::ErodeOptions::memory_cap_bytes (0: none)
  /// When true, each stage's peak_rss_mib is the peak resident memory during that stage alone
  /// (Linux: the high-water mark is reset through /proc/self/clear_refs before the stage);
  /// otherwise it is the process's peak so far. Only meaningful when nothing else runs in the process.
  bool per_stage_peak_memory = false;
};

/// The outcome and the two surfaces it was measured on.
struct Evaluation {
  VerifyOutcome
      outcome;  ///< stages "generator (morph)", "reference (OpenVDB)", "deviation (Embree)"; files empty
  morph::TriangleMesh morph_mesh;
  morph::TriangleMesh reference_mesh;
  vdb_ref::ReferenceStats reference_stats;
};

/// Runs the generator, the reference and the deviation measurement on `job` and computes the
/// verdict exactly as run_verify does, writing nothing (except options.vdb_output_path).
/// Throws what erode / compute_reference throw (InputError for bad options, LimitError when the
/// reference would exceed its memory cap).
Evaluation evaluate_job(const morph::Job& job, const EvaluateOptions& options);

/// Voxel size for a job when none is given: a sixth of the smallest tool radius, bounded below
/// so the reference stays within memory on large stock.
double auto_voxel_size(const morph::Job& job);

/// Runs everything and writes morph.ply, reference.ply, reference.vdb, deviation.json, heatmap
/// PLYs and PNGs, report.md and report.html into out_dir.
VerifyOutcome run_verify(const VerifyOptions& options);

/// The outcome as JSON (what deviation.json holds, plus the verdict).
nlohmann::json outcome_to_json(const VerifyOutcome& outcome);
nlohmann::json stats_to_json(const raytest::DeviationStats& stats);

/// report.md and report.html (self-contained: pictures embedded as data URIs; `view3d_html`, the
/// interactive 3D view's block, goes into the HTML before the pictures).
void write_reports(const VerifyOutcome& outcome, const std::string& out_dir,
                   const std::vector<std::pair<std::string, std::string>>& pictures,
                   const std::string& view3d_html = "");

}  // namespace morphmill
