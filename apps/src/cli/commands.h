// SPDX-License-Identifier: Apache-2.0
#pragma once
// Each command group registers its subcommands on the root app; main() dispatches and maps
// exceptions to exit codes (see exit_codes below).
#include <morph/job.h>
#include <CLI/CLI.hpp>

namespace morphmill {

/// Exit codes of every morphmill command.
enum ExitCode : int {
  kExitOk = 0,            ///< success (verify: the verdict holds)
  kExitVerdictFails = 1,  ///< verify/stress: the computation ran but the verdict does not hold
  kExitBadInput = 2,      ///< the input is wrong (job, G-code, mesh, options)
  kExitInternal = 3,      ///< an unexpected internal error
  kExitIncomplete = 4,    ///< stress/stress-merge: not every case ran (stopped, or shards missing)
};

/// Thrown by a command whose computation ran but whose verdict does not hold (exit code 1).
struct VerdictFailed {};

/// Thrown by a command that stopped or was refused before every case of its campaign ran, after
/// saying what is missing (exit code 4).
struct CampaignIncomplete {};

/// `morphmill --strict`: warnings become exit 2.
bool& strict_warnings();
/// Prints the job's warnings on stderr (`print`; info shows them in its report instead) and,
/// under --strict, throws morph::InputError if there are any.
void report_job_warnings(const morph::Job& job, bool print = true);

void register_info_commands(CLI::App& app);       // info, mesh-info
void register_erode_command(CLI::App& app);       // erode
void register_reference_command(CLI::App& app);   // reference
void register_deviation_commands(CLI::App& app);  // deviation, render
void register_verify_command(CLI::App& app);      // verify
void register_compare_command(CLI::App& app);     // compare
void register_stress_command(CLI::App& app);      // stress
void register_study_command(CLI::App& app);       // study
void register_planar_commands(CLI::App& app);     // erode2d, verify2d

}  // namespace morphmill
