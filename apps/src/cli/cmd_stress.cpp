// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "campaigns/stress.h"
#include "cli/cli_conventions.h"
#include "cli/commands.h"
#include "cli/stop_signals.h"
#include "cli/terminal_progress.h"
#include "verify/soundness.h"

namespace morphmill {

namespace {

void print_summary(const stress::Summary& summary, const std::string& out_dir) {
  const std::size_t failed = summary.failed_cases();
  std::cout << "stress: " << summary.results.size() << " case(s) of " << summary.cases << ", seed "
            << summary.seed << ": "
            << (failed == 0 ? std::string("no failures") : std::to_string(failed) + " FAILING")
            << (summary.complete() ? "" : " -- INCOMPLETE") << "\n";
  if (!summary.complete()) {
    std::cout << "  " << summary.partial_line() << "\n";
    for (const auto& line : summary.incomplete) std::cout << "  " << line << "\n";
  }
  const auto json = stress::summary_to_json(summary);
  for (const auto& [name, count] : json["failures_by_invariant"].items())
    if (count.get<int>() > 0) std::cout << "  " << name << ": " << count.get<int>() << " case(s)\n";
  std::cout << "  wall time " << json["wall_seconds"].get<double>() << " s, peak memory "
            << json["peak_rss_mib"].get<double>() << " MiB\n  summary: " << out_dir << "/summary.md\n";
  if (failed > 0) std::cout << "  failing jobs: " << out_dir << "/failures/\n";
}

/// The human summary on standard output, and the JSON one where --json says (standard output then
/// holds the JSON alone).
void report(const stress::Summary& summary, const std::string& out_dir, const CLI::Option* json_option,
            const std::string& json_path) {
  const bool json = json_option->count() > 0;
  if (!json || !is_standard_output(json_path)) print_summary(summary, out_dir);
  if (json) write_json(stress::summary_to_json(summary), json_path);
}

/// Exit code: 1 when a case failed (a failure found is a result even in an incomplete run), 4 when
/// cases are missing, 0 otherwise.
void finish(const stress::Summary& summary) {
  if (summary.failed_cases() > 0) throw VerdictFailed();
  if (!summary.complete()) throw CampaignIncomplete();
}

/// `--resume DIR` alone continues DIR's campaign: the options not given are read from its
/// campaign.json (those given must agree; run_stress compares every one).
void take_recorded_options(const CLI::App& command, const std::string& dir, stress::StressOptions& run,
                           std::string& shard) {
  const std::filesystem::path file = std::filesystem::path(dir) / "campaign.json";
  if (!std::filesystem::exists(file)) {
    if (command.count("--cases") == 0)
      throw morph::InputError("--resume " + dir +
                              ": no campaign.json there, so no campaign to continue (give --cases, --seed "
                              "and --shard to start one)");
    return;
  }
  nlohmann::json recorded;
  try {
    std::ifstream in(file);
    recorded = nlohmann::json::parse(in);
    if (command.count("--cases") == 0) run.cases = recorded.at("--cases").get<std::size_t>();
    if (command.count("--seed") == 0) run.seed = recorded.at("--seed").get<std::uint64_t>();
    if (command.count("--samples") == 0) run.face_samples = recorded.at("--samples").get<std::size_t>();
    stress::check_recorded_generator(recorded, file.string());
    if (command.count("--families") == 0) run.families = recorded.value("--families", std::string("classic"));
    if (command.count("--reference-memory-cap") == 0)
      run.reference_memory_cap_mib = recorded.at("--reference-memory-cap").get<double>();
    if (command.count("--max-rss") == 0) run.max_peak_rss_mib = recorded.at("--max-rss").get<double>();
    if (command.count("--shard") == 0) shard = recorded.at("shard").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    throw morph::InputError(file.string() + ": not a stress campaign: " + e.what());
  }
}

}  // namespace

void register_stress_command(CLI::App& app) {
  auto options = std::make_shared<stress::StressOptions>();
  auto shard = std::make_shared<std::string>("0/1");
  auto resume_dir = std::make_shared<std::string>();
  auto json_path = std::make_shared<std::string>();
  CLI::App* command = app.add_subcommand(
      "stress",
      "Run the generator, the reference and the deviation measurement on random cases built to break\n"
      "them (slots splitting the stock, freed islands, removed pieces, self-crossing paths, coincident,\n"
      "tangent and overlapping passes, grazing contacts, features at the tolerance, passes outside the\n"
      "stock; box, cylinder and mesh stock; sphere and ball-end tools; with --families motion the\n"
      "motions of real programs and every tool shape) and check invariants on each.\n"
      "Writes DIR/campaign.json, DIR/cases/ (each finished case), DIR/failures/case_NNNNNN.json for every\n"
      "failing case, DIR/fallbacks/ for every passing case on which a generator fallback fired and,\n"
      "last, DIR/summary.md and DIR/summary.json.\n"
      "SIGINT/SIGTERM stop cleanly: the cases in flight finish, the summary says what is missing, and\n"
      "'morphmill stress --resume DIR' runs only the cases not finished.\n"
      "Exit code 0 when every case ran and passed, 1 when any invariant fails, 2 for bad input,\n"
      "4 when stopped before every case ran. See docs/stress.md.\n"
      "Example: morphmill stress --cases 1000 --seed 7 --output out/stress --shard 3/16");
  command->add_option("--cases,-n", options->cases, "Cases of the campaign (indices 0..N-1)")
      ->capture_default_str();
  command->add_option("--seed,-s", options->seed, "Campaign seed: same seed, same cases")
      ->capture_default_str();
  command->add_option("-o,--output", options->out_dir, "Output directory (a new run replaces what is there)");
  command->add_option("--shard", *shard, "Run only the cases k with k mod n == i (i/n)")
      ->capture_default_str();
  command
      ->add_option("--resume", *resume_dir,
                   "Continue the campaign in DIR (or in --output): keep its finished cases, run the others.\n"
                   "Options not given are the campaign's; options given must equal them. With --output and\n"
                   "the options, starts the campaign if DIR holds none (for a requeued batch task)")
      ->expected(0, 1);
  command->add_option("--threads,-j", options->threads, "Worker threads (0: all cores)")
      ->capture_default_str();
  add_retired_generator_option(*command);
  command
      ->add_option(
          "--families", options->families,
          "Case families: classic (the default), motion (retrace, plunge_retract, reversal,\n"
          "submicron, arcs, cutout, self_crossing, mixed_tools, fine_steps: box stock; mesh_stock:\n"
          "a box as a mesh of slivers; every tool shape the generator builds), all, or family names\n"
          "separated by commas")
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
  CLI::Option* json_option =
      add_json_option(*command, *json_path, "the summary (summary.json's content; also when exit 1 or 4)");
  command->callback([command, options, shard, resume_dir, json_path, json_option] {
    stress::StressOptions run = *options;
    std::string shard_text = *shard;
    run.resume = command->count("--resume") > 0;
    if (run.resume && !resume_dir->empty()) {
      if (!run.out_dir.empty() && std::filesystem::path(run.out_dir) != std::filesystem::path(*resume_dir))
        throw morph::InputError("--resume " + *resume_dir + " and --output " + run.out_dir +
                                " name different directories");
      run.out_dir = *resume_dir;
    }
    if (run.out_dir.empty()) throw morph::InputError("--output DIR (or --resume DIR) is required");
    if (run.resume) take_recorded_options(*command, run.out_dir, run, shard_text);
    std::tie(run.shard_index, run.shard_count) = stress::parse_shard(shard_text);
    TerminalProgress progress;
    run.progress = &progress;
    run.stop_signal = &stop_signal();
    stress::Summary summary;
    {
      StopOnSignals stop_on_signals;
      summary = stress::run_stress(run);
    }
    report(summary, run.out_dir, json_option, *json_path);
    finish(summary);
  });

  auto dirs = std::make_shared<std::vector<std::string>>();
  auto merged_out = std::make_shared<std::string>();
  auto partial = std::make_shared<bool>(false);
  auto merged_json_path = std::make_shared<std::string>();
  CLI::App* merge = app.add_subcommand(
      "stress-merge",
      "Combine the shard directories of one stress campaign into one summary. Refuses shards of different\n"
      "campaigns (naming the option, version or commit that differs) and, unless --partial, a campaign\n"
      "with shards or cases missing (naming them). --output must be new, empty or a previous merge "
      "(replaced\n"
      "whole).\n"
      "Exit code 0 when every case ran and none fails, 1 when a merged case fails, 2 for bad input,\n"
      "4 when cases are missing (refused, or merged with --partial).\n"
      "Example: morphmill stress-merge out/stress_* --output out/stress");
  merge->add_option("dirs", *dirs, "Shard output directories")->required()->check(CLI::ExistingDirectory);
  merge->add_option("-o,--output", *merged_out, "Output directory")->required();
  merge->add_flag("--partial", *partial,
                  "Merge an incomplete campaign: the summary says 'partial: K of N cases, missing ...'");
  CLI::Option* merged_json_option = add_json_option(
      *merge, *merged_json_path, "the merged summary (summary.json's content; also when exit 1 or 4)");
  merge->callback([dirs, merged_out, partial, merged_json_path, merged_json_option] {
    try {
      const stress::Summary summary = stress::merge_stress(*dirs, *merged_out, *partial);
      report(summary, *merged_out, merged_json_option, *merged_json_path);
      finish(summary);
    } catch (const stress::IncompleteCampaign& e) {
      std::cerr << "morphmill: " << e.what() << '\n';
      throw CampaignIncomplete();
    }
  });
}

}  // namespace morphmill
