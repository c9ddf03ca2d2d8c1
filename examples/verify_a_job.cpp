// SPDX-License-Identifier: Apache-2.0
// What `morphmill verify` does, through the public C++ API (morphmill/morphmill.h): load a job,
// build the generator's surface, the OpenVDB reference, measure one against the other, and verify.
// Usage: verify_a_job JOB_FILE [VOXEL_SIZE]
#include <morphmill/morphmill.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s JOB_FILE [VOXEL_SIZE]\n", argv[0]);
    return 2;
  }
  try {
    const morph::Job job = morphmill::load_job(argv[1]);
    const double voxel = argc > 2 ? std::stod(argv[2]) : morphmill::default_voxel_size(job);

    const morphmill::ErodeReport part = morphmill::erode(job);
    std::printf("generator: %zu triangles, %zu piece(s), volume %.4f, valid %s\n", part.mesh.triangle_count(),
                part.topology.components, part.topology.volume, part.valid() ? "yes" : "no");

    morphmill::ReferenceSettings reference_settings;
    reference_settings.voxel_size = voxel;
    const vdb_ref::ReferenceResult reference = morphmill::reference(job, reference_settings);
    std::printf("reference: voxel %.4f, %zu piece(s), volume %.4f\n", voxel, reference.pieces.size(),
                reference.volume());

    morphmill::DeviationSettings deviation_settings;
    deviation_settings.face_samples = 20000;
    const raytest::TwoSidedDeviation deviation =
        morphmill::deviation(part.mesh, reference.mesh, deviation_settings);
    std::printf("deviation: Hausdorff %.4f (%zu + %zu samples)\n", deviation.hausdorff,
                deviation.a_to_b.samples.size(), deviation.b_to_a.samples.size());

    morphmill::VerifySettings verify_settings;
    verify_settings.voxel_size = voxel;
    verify_settings.face_samples = 20000;
    const morphmill::VerifyReport verdict = morphmill::verify(job, verify_settings);
    std::printf("verify: %s (generator within tolerance %s, sides agree %s, pieces match %s)\n",
                verdict.verdict ? "holds" : "FAILS", verdict.generator_within_tolerance ? "yes" : "no",
                verdict.sides_agree ? "yes" : "no", verdict.pieces_match ? "yes" : "no");
    return verdict.verdict ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "verify_a_job: %s\n", e.what());
    return 2;
  }
}
