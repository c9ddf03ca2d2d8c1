// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>

#include <iostream>

#include "cli/cli_conventions.h"
#include "cli/commands.h"
#include "cli/memory_cap.h"
#include "cli/terminal_progress.h"
#include "verify/verify.h"

namespace morphmill {

void register_verify_command(CLI::App& app) {
  auto options = std::make_shared<VerifyOptions>();
  auto json_path = std::make_shared<std::string>();
  auto memory_cap_gib = std::make_shared<double>();
  CLI::App* verify = app.add_subcommand(
      "verify",
      "Run the generator, the OpenVDB reference and the Embree deviation measurement on one job and write\n"
      "a report. Checks that the generator stays within the job's tolerance of the exact surface (both\n"
      "ways) and that generator and reference agree within tolerance + sqrt(3) * voxel wherever the\n"
      "surface is resolvable at that voxel size (acute wedges, thin walls and gaps under two voxels are\n"
      "reported but left out), with the same pieces and volumes; when the job names a design, also that\n"
      "the machined result is within the design's band (see morphmill compare).\n"
      "Signed deviations: + excess (A outside B's solid), - gouge (A inside).\n"
      "Jobs may be JSON job files or CAMotics projects (.camotics).\n"
      "Exit code 0 when the verdict holds, 1 when it does not, 2 for bad input.\n"
      "Example: morphmill verify data/jobs/through_slots.json --output out/slots");
  verify
      ->add_option("job", options->job_path,
                   "Job file (JSON, see docs/job-format.md) or CAMotics project (.camotics)")
      ->required()
      ->check(CLI::ExistingFile);
  verify
      ->add_option("-o,--output", options->out_dir,
                   "Directory for morph.ply, reference.ply/.vdb, heatmaps, report.html")
      ->required();
  verify
      ->add_option("--voxel", options->voxel_size,
                   "Reference voxel size in job units (default: smallest tool radius / 6)")
      ->check(CLI::PositiveNumber);
  verify
      ->add_option("--tolerance", options->tolerance, "Generator tolerance in job units (default: the job's)")
      ->check(CLI::PositiveNumber);
  verify
      ->add_option("--samples", options->face_samples,
                   "Area-uniform samples per surface, on top of every vertex")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 2e7));
  verify->add_option("--seed", options->seed, "Seed of the surface sampling")->capture_default_str();
  verify->add_flag(
      "--reference-only", options->reference_only,
      "Check only the reference against the exact surface (within sqrt(3) * voxel where resolvable);\n"
      "the generator is not run");
  add_retired_generator_option(*verify);
  CLI::Option* json_option =
      add_json_option(*verify, *json_path, "the summary (deviation.json's content; also when exit 1)");
  add_memory_cap_option(verify, *memory_cap_gib);
  verify->callback([options, json_path, json_option, memory_cap_gib] {
    TerminalProgress progress;
    VerifyOptions run = *options;
    run.progress = &progress;
    run.memory_cap_bytes = memory_cap_bytes(*memory_cap_gib);
    const VerifyOutcome outcome = [&] {
      try {
        return run_verify(run);
      } catch (const morph::LimitError& e) {
        throw morph::LimitError(run.job_path + ": " + e.what() + " (--memory-cap " +
                                describe_bytes(double(run.memory_cap_bytes)) + ")");
      }
    }();
    if (json_option->count() > 0) write_json(outcome_to_json(outcome), *json_path);
    if (json_option->count() > 0 && is_standard_output(*json_path)) {
      // Standard output holds the JSON alone; the verdict is in it and in the exit code.
      if (!outcome.verdict()) throw VerdictFailed();
      return;
    }
    if (!outcome.generator_skipped.empty()) {
      std::cout << "verify " << outcome.job.name << ": verdict "
                << (outcome.verdict() ? "HOLDS" : "NOT VERIFIED") << "\n  generator: not run ("
                << outcome.generator_skipped << ")"
                << "\n  reference against the exact surface: " << (outcome.reference_converges ? "yes" : "NO")
                << " (max " << outcome.reference_resolvable_max << " over "
                << outcome.reference_resolvable_samples
                << " resolvable samples, bound sqrt(3) * voxel = " << outcome.reference_bound << ")";
      std::cout << "\n  report: " << run.out_dir << "/report.html\n";
      if (!outcome.verdict()) throw VerdictFailed();
      return;
    }
    std::cout
        << "verify " << outcome.job.name << ": verdict " << (outcome.verdict() ? "HOLDS" : "DOES NOT HOLD")
        << "\n  generator within tolerance: " << (outcome.generator_within_tolerance ? "yes" : "no")
        << "\n  generator and reference agree: " << (outcome.sides_agree ? "yes" : "no")
        << "\n  pieces: generator " << outcome.morph_pieces.size() << ", reference "
        << outcome.reference_pieces.size() << (outcome.pieces_match ? " (match)" : " (MISMATCH)")
        << (outcome.pieces_below_resolution
                ? ", " + std::to_string(outcome.pieces_below_resolution) +
                      " piece(s) below the voxels' resolution (of both sides), judged by the exact field"
                : std::string())
        << (outcome.design_path.empty()
                ? std::string()
                : "\n  design: " + std::to_string(outcome.design.gouge_regions) + " gouge, " +
                      std::to_string(outcome.design.excess_regions) + " excess regions" +
                      (outcome.design.within_band() ? " (within the band)" : " (OUT OF THE BAND)"))
        << "\n  report: " << run.out_dir << "/report.html\n";
    if (!outcome.verdict()) throw VerdictFailed();
  });
}

}  // namespace morphmill
