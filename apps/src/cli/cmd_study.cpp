// SPDX-License-Identifier: Apache-2.0
#include <iostream>

#include "campaigns/study.h"
#include "cli/cli_conventions.h"
#include "cli/commands.h"
#include "cli/stop_signals.h"
#include "cli/terminal_progress.h"

namespace morphmill {

void register_study_command(CLI::App& app) {
  auto options = std::make_shared<study::StudyOptions>();
  auto json_path = std::make_shared<std::string>();
  CLI::App* command = app.add_subcommand(
      "study",
      "Sweep parameters over jobs, one at a time (reference voxel size, generator tolerance, tool radius,\n"
      "step-over of generated zigzag jobs), and write a convergence table (study.csv, study.json), plots\n"
      "(error vs voxel size with the fitted order, time and memory vs accuracy), heatmaps of every\n"
      "setting and a self-contained report.html. Study file format: docs/study.md.\n"
      "SIGINT/SIGTERM stop after the setting in flight, write the table of what ran and exit 4;\n"
      "--resume then evaluates only the settings left.\n"
      "Example: morphmill study data/studies/convergence.json --output out/convergence");
  command->add_option("study", options->study_path, "Study file (JSON)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("-o,--output", options->out_dir, "Output directory")->required();
  command->add_flag(
      "--resume", options->resume,
      "Keep the settings a stopped run already evaluated in --output (settings/), evaluate the others");
  CLI::Option* json_option =
      add_json_option(*command, *json_path, "the table (study.json's content; also when stopped, exit 4)");
  command->callback([options, json_path, json_option] {
    TerminalProgress progress;
    study::StudyOptions run = *options;
    run.progress = &progress;
    run.stop_signal = &stop_signal();
    study::StudyResult result;
    {
      StopOnSignals stop_on_signals;
      result = study::run_study(run);
    }
    if (json_option->count() > 0) {
      write_json(study::result_to_json(result), *json_path);
      if (is_standard_output(*json_path)) {  // standard output holds the JSON alone
        if (!result.complete()) throw CampaignIncomplete();
        return;
      }
    }
    if (!result.complete()) {
      std::cout << "study " << result.spec.name << ": " << result.stopped << " after " << result.evaluated
                << " of " << result.settings
                << " setting(s): INCOMPLETE\n  table of what ran: " << run.out_dir
                << "/study.csv, study.json\n  continue with: morphmill study " << run.study_path
                << " --output " << run.out_dir << " --resume\n";
      throw CampaignIncomplete();
    }
    std::cout << "study " << result.spec.name << ": " << result.rows.size() << " setting(s)\n";
    for (const auto& c : result.convergence)
      std::cout << "  " << c.job << (c.tools.empty() ? "" : " (" + c.tools + ")") << ": " << c.measure
                << " error order " << c.fit.order << " (R^2 " << c.fit.r_squared << ", " << c.fit.points
                << " points)\n";
    for (const auto& row : result.rows)
      if (!row.error.empty())
        std::cout << "  " << row.job << " " << study::to_string(row.parameter) << " = " << row.value
                  << ": not evaluated: " << row.error << "\n";
    std::cout << "  report: " << run.out_dir << "/report.html\n";
  });
}

}  // namespace morphmill
