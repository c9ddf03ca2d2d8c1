#include <morph/exceptions.h>

#include <iostream>

#include "commands.h"
#include "stress.h"
#include "terminal_progress.h"

namespace morphmill {

namespace {

void print_summary(const stress::Summary& summary, const std::string& out_dir) {
  const std::size_t failed = summary.failed_cases();
  std::cout << "stress: " << summary.results.size() << " case(s) of " << summary.cases << ", seed "
            << summary.seed << ": "
            << (failed == 0 ? std::string("no failures") : std::to_string(failed) + " FAILING") << "\n";
  const auto json = stress::summary_to_json(summary);
  for (const auto& [name, count] : json["failures_by_invariant"].items())
    if (count.get<int>() > 0) std::cout << "  " << name << ": " << count.get<int>() << " case(s)\n";
  std::cout << "  wall time " << json["wall_seconds"].get<double>() << " s, peak memory "
            << json["peak_rss_mib"].get<double>() << " MiB\n  summary: " << out_dir << "/summary.md\n";
  if (failed > 0) std::cout << "  failing jobs: " << out_dir << "/failures/\n";
}

}  // namespace

void register_stress_command(CLI::App& app) {
  auto options = std::make_shared<stress::StressOptions>();
  auto shard = std::make_shared<std::string>("0/1");
  CLI::App* command = app.add_subcommand(
      "stress",
      "Run the generator, the reference and the deviation measurement on random cases built to break\n"
      "them (slots splitting the stock, freed islands, removed pieces, self-crossing paths, coincident,\n"
      "tangent and overlapping passes, grazing contacts, features at the tolerance, passes outside the\n"
      "stock; box, cylinder and mesh stock; sphere and ball-end tools) and check invariants on each.\n"
      "Writes DIR/summary.json, DIR/summary.md and DIR/failures/case_NNNNNN.json for every failing case.\n"
      "Exit code 0 when every case passes, 1 when any invariant fails, 2 for bad input. See docs/stress.md.\n"
      "Example: morphmill stress --cases 1000 --seed 7 --out out/stress --shard 3/16");
  command->add_option("--cases,-n", options->cases, "Cases of the campaign (indices 0..N-1)")
      ->capture_default_str();
  command->add_option("--seed,-s", options->seed, "Campaign seed: same seed, same cases")
      ->capture_default_str();
  command->add_option("--out,-o", options->out_dir, "Output directory")->required();
  command->add_option("--shard", *shard, "Run only the cases k with k mod n == i (i/n)")
      ->capture_default_str();
  command->add_option("--threads,-j", options->threads, "Worker threads (0: all cores)")
      ->capture_default_str();
  command
      ->add_option("--samples", options->face_samples, "Area-uniform deviation samples per surface and case")
      ->capture_default_str();
  command
      ->add_option("--reference-memory-cap", options->reference_memory_cap_mib,
                   "Per case: largest memory the reference may need (MiB)")
      ->capture_default_str();
  command
      ->add_option("--max-rss", options->max_peak_rss_mib,
                   "Peak resident memory of the process allowed (MiB)")
      ->capture_default_str();
  command->callback([options, shard] {
    stress::StressOptions run = *options;
    std::tie(run.shard_index, run.shard_count) = stress::parse_shard(*shard);
    TerminalProgress progress;
    run.progress = &progress;
    const stress::Summary summary = stress::run_stress(run);
    print_summary(summary, run.out_dir);
    if (summary.failed_cases() > 0) throw VerdictFailed();
  });

  auto dirs = std::make_shared<std::vector<std::string>>();
  auto merged_out = std::make_shared<std::string>();
  CLI::App* merge = app.add_subcommand(
      "stress-merge",
      "Combine the shard directories of one stress campaign (same seed and case count) into one summary.\n"
      "Exit code 0 when no merged case fails, 1 otherwise, 2 for bad input.\n"
      "Example: morphmill stress-merge out/stress_* --out out/stress");
  merge->add_option("dirs", *dirs, "Shard output directories")->required()->check(CLI::ExistingDirectory);
  merge->add_option("--out,-o", *merged_out, "Output directory")->required();
  merge->callback([dirs, merged_out] {
    const stress::Summary summary = stress::merge_stress(*dirs, *merged_out);
    print_summary(summary, *merged_out);
    if (summary.failed_cases() > 0) throw VerdictFailed();
  });
}

}  // namespace morphmill
