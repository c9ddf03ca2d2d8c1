// SPDX-License-Identifier: Apache-2.0
// The public API (morphmill/morphmill.h): the CLI's steps, called the way its commands call them.
#include <morphmill/morphmill.h>

#include <morph/erode.h>

#include "io/build_info.h"
#include "verify/soundness.h"
#include "verify/verify.h"

namespace morphmill {

std::string version() {
  return program_version();
}

ErodeReport erode(const morph::Job& job, const ErodeSettings& settings) {
  morph::ErodeOptions options;
  options.tolerance = settings.tolerance;
  options.memory_cap_bytes = settings.memory_cap_bytes;
  options.progress = settings.progress;
  ErodeReport report;
  morph::ErodeResult result = morph::erode(job, options);
  report.mesh = std::move(result.mesh);
  report.stats = std::move(result.stats);
  const SurfaceSoundness soundness = check_soundness(report.mesh);
  report.topology = soundness.topology;
  report.self_intersections = soundness.crossings.pairs;
  return report;
}

double default_voxel_size(const morph::Job& job) {
  return auto_voxel_size(job);
}

vdb_ref::ReferenceResult reference(const morph::Job& job, const ReferenceSettings& settings) {
  vdb_ref::ReferenceOptions options;
  options.voxel_size = settings.voxel_size > 0.0 ? settings.voxel_size : auto_voxel_size(job);
  options.memory_cap_bytes = settings.memory_cap_bytes;
  options.progress = settings.progress;
  return vdb_ref::compute_reference(job, options);
}

raytest::TwoSidedDeviation deviation(const morph::TriangleMesh& a, const morph::TriangleMesh& b,
                                     const DeviationSettings& settings) {
  raytest::DeviationOptions options;
  options.sampling.vertices = settings.vertices;
  options.sampling.face_samples = settings.face_samples;
  options.sampling.edge_samples = settings.edge_samples;
  options.sampling.seed = settings.seed;
  options.mode = settings.mode;
  options.max_distance = settings.max_distance;
  return raytest::measure_two_sided(a, b, options);
}

VerifyReport verify(const morph::Job& job, const VerifySettings& settings) {
  EvaluateOptions options;
  options.voxel_size = settings.voxel_size;
  options.tolerance = settings.tolerance;
  options.face_samples = settings.face_samples;
  options.seed = settings.seed;
  options.reference_only = settings.reference_only;
  options.reference_memory_cap_bytes = settings.reference_memory_cap_bytes;
  options.progress = settings.progress;
  Evaluation evaluation = evaluate_job(job, options);
  const VerifyOutcome& outcome = evaluation.outcome;
  VerifyReport report;
  report.verdict = outcome.verdict();
  report.generator_within_tolerance = outcome.generator_within_tolerance;
  report.sides_agree = outcome.sides_agree;
  report.pieces_match = outcome.pieces_match;
  report.generator_skipped = outcome.generator_skipped;
  report.tolerance = outcome.tolerance;
  report.voxel_size = outcome.voxel_size;
  report.agreement_bound = outcome.agreement_bound;
  report.resolvable_hausdorff = outcome.resolvable_hausdorff;
  report.summary = outcome_to_json(outcome);
  report.generator_to_exact = std::move(evaluation.outcome.morph_to_exact);
  report.reference_to_exact = std::move(evaluation.outcome.reference_to_exact);
  report.generator_mesh = std::move(evaluation.morph_mesh);
  report.reference_mesh = std::move(evaluation.reference_mesh);
  return report;
}

}  // namespace morphmill
